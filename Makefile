# skydome: set-up, demo and tests. Everything installs into .venv; nothing global but
# Mesa's EGL/OpenGL libraries and Xvfb (Debian packages), installed when missing and run as root.
#
#   make demo        the package alone (pip install -e .), then render a sky to out/
#   make test        lint, then every test (what CI runs: .ci/run)
#   make test-fast   the fast tier of the tests, a few minutes on 2 cores: no test marked
#                    slow, window (a glfw window under Xvfb) or soak (tests/conftest.py
#                    marks them); no lint (make lint)
#   make lint, docs, gallery, bench
#
# demo, gallery and bench install what running needs (the package); test, test-fast, lint
# and docs add the dev and docs extras (pytest, hypothesis, ruff, the reference libraries,
# mkdocs) to the same .venv.
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
DEV_STAMP := $(VENV)/.installed-dev
#: The fast tier's marker expression (pytest -m).
FAST_TIER := not slow and not window and not soak

.PHONY: demo test test-fast lint gallery bench docs gl-deps system-deps clean

# Mesa's EGL and software OpenGL (llvmpipe): what rendering needs without a GPU.
gl-deps:
	@if ! ldconfig -p | grep -q 'libEGL.so.1' || ! ls /usr/lib/*/dri/swrast_dri.so >/dev/null 2>&1; then \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    echo "installing Mesa EGL/OpenGL (libegl1 libgl1-mesa-dri)"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libegl1 libgl1-mesa-dri >/dev/null; \
	  else echo "warning: install libegl1 and libgl1-mesa-dri for OpenGL without a GPU" >&2; fi; \
	fi

# Also Xvfb, the virtual display of the viewer's window tests.
system-deps: gl-deps
	@if ! command -v Xvfb >/dev/null; then \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    echo "installing Xvfb (xvfb: a virtual display for the viewer's window tests)"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq xvfb >/dev/null; \
	  else echo "warning: install xvfb to run the viewer's window tests without a display" >&2; fi; \
	fi

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip

# The package and its run-time dependencies only.
$(STAMP): pyproject.toml | $(PY) gl-deps
	$(PY) -m pip install -q -e .
	touch $(STAMP)

# The package with the test, lint and documentation tools.
$(DEV_STAMP): pyproject.toml | $(PY) system-deps
	$(PY) -m pip install -q -e '.[dev,docs]'
	touch $(DEV_STAMP) $(STAMP)

# Render a sky to out/ (PNG tone mapped, EXR in cd/m^2).
demo: $(STAMP)
	mkdir -p out
	$(VENV)/bin/skydome render --sun-elevation 8 --sun-azimuth 250 --size 1280x720 -o out/sky.png -o out/sky.exr

lint: $(DEV_STAMP)
	$(VENV)/bin/ruff check src tests benchmarks tools docs/examples
	$(VENV)/bin/ruff format --check src tests benchmarks tools docs/examples

# Lint, then the whole test suite (GL tests run headless, on the GPU or Mesa llvmpipe).
test: lint
	$(PY) -m pytest

# The fast tier: every test but the slow, window and soak ones (see tests/conftest.py).
test-fast: $(DEV_STAMP)
	$(PY) -m pytest -m "$(FAST_TIER)"

gallery: $(STAMP)
	$(PY) tools/make_gallery.py && $(PY) tools/make_gallery.py --model single
	$(PY) tools/make_gallery.py --clouds --size 1280x720 && $(PY) tools/make_gallery.py --weather --size 1280x720
	$(PY) tools/make_gallery.py --optics --size 1280x720 && $(PY) tools/make_gallery.py --ground --size 640x320 && $(PY) tools/make_howto_images.py

# The documentation site into site/ (MkDocs, warnings are errors); the CLI page and the
# example notebooks' pages (run afresh) first.
docs: $(DEV_STAMP)
	$(PY) tools/make_cli_docs.py
	$(PY) tools/run_notebooks.py
	NO_MKDOCS_2_WARNING=1 $(PY) -m mkdocs build --strict -d site

bench: $(STAMP)
	$(PY) benchmarks/bench_render.py

clean:
	rm -rf $(VENV) out site .pytest_cache
