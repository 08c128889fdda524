# skydome: set-up, demo and tests. Everything installs into .venv; nothing global but
# Mesa's EGL/OpenGL libraries (Debian packages), installed when missing and run as root.
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: demo test lint gallery bench docs system-deps clean

system-deps:
	@if ! ldconfig -p | grep -q 'libEGL.so.1' || ! ls /usr/lib/*/dri/swrast_dri.so >/dev/null 2>&1; then \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    echo "installing Mesa EGL/OpenGL (libegl1 libgl1-mesa-dri)"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libegl1 libgl1-mesa-dri >/dev/null; \
	  else echo "warning: install libegl1 and libgl1-mesa-dri for OpenGL without a GPU" >&2; fi; \
	fi
	@if ! command -v Xvfb >/dev/null; then \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    echo "installing Xvfb (xvfb: a virtual display for the viewer's window tests)"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq xvfb >/dev/null; \
	  else echo "warning: install xvfb to run the viewer's window tests without a display" >&2; fi; \
	fi

$(STAMP): pyproject.toml | system-deps
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[dev,docs]'
	touch $(STAMP)

# Render a sky to out/ (PNG tone mapped, EXR in cd/m^2).
demo: $(STAMP)
	mkdir -p out
	$(VENV)/bin/skydome render --sun-elevation 8 --sun-azimuth 250 --size 1280x720 -o out/sky.png -o out/sky.exr

lint: $(STAMP)
	$(VENV)/bin/ruff check src tests benchmarks tools docs/examples
	$(VENV)/bin/ruff format --check src tests benchmarks tools docs/examples

# Lint, then the whole test suite (GL tests run headless, on the GPU or Mesa llvmpipe).
test: lint
	$(PY) -m pytest

gallery: $(STAMP)
	$(PY) tools/make_gallery.py && $(PY) tools/make_gallery.py --model single

# The documentation site into site/ (MkDocs, warnings are errors); the CLI page first.
docs: $(STAMP)
	$(PY) tools/make_cli_docs.py
	NO_MKDOCS_2_WARNING=1 $(PY) -m mkdocs build --strict -d site

bench: $(STAMP)
	$(PY) benchmarks/bench_render.py

clean:
	rm -rf $(VENV) out site .pytest_cache
