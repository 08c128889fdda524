#!/bin/sh
# Issue 27 item 5 on a device machine (NVIDIA, EGL, no display), in one run: installs what
# tools/device_prepare.sh put in .whl/ and .gl/ (carried with the run), shows the GPU, and
# runs benchmarks/bench_gpu.py (the scene, the clouds, the precomputation and the viewer's
# frame, each beside its goal), its output also in $OUT/gpu.log, then a set of GL tests
# ($OUT/gl_tests.log). About 3-7 minutes on a GPU after the machine's start; run it with a
# timeout that leaves time for a second try.
set -e
for f in .gl/*.deb; do if [ -e "$f" ]; then dpkg -x "$f" /; fi; done
ldconfig
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade \
    --target /tmp/site .whl/*.whl
export PYTHONPATH="$PWD/src:/tmp/site" PYTHONUNBUFFERED=1
# the NVIDIA driver's EGL, where the loaders do not find it by themselves
if [ -f /usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json ]; then
    export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
fi
nvidia-smi -L || true
(cd benchmarks && python3 bench_gpu.py --repeats "${REPEATS:-20}") 2>&1 | tee "${OUT:-/tmp}/gpu.log"
# Then the GL tests that need none of the dev extras (skyfield, ephem, ...), on the GPU's
# arithmetic instead of llvmpipe's, for at most TEST_SECONDS (default 240).
timeout "${TEST_SECONDS:-240}" python3 -m pytest -q -p no:cacheprovider \
    tests/test_frame_graph.py tests/test_precompute.py tests/test_single_scattering.py \
    tests/test_precomputed_render.py tests/test_sky_view.py tests/test_clouds.py \
    2>&1 | tee "${OUT:-/tmp}/gl_tests.log" || true
