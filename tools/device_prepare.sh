#!/bin/sh
# Prepares a device machine's run of benchmarks/gpu_check.sh (issue 27 item 5: the GPU
# figures), here, where the package registries answer (the device machine reaches nothing):
# the Python packages skydome needs that the device's image lacks (it has NumPy, Pillow,
# Typer, Rich), as CPython 3.12 wheels in .whl/, and the GL loaders (libglvnd's EGL and GL,
# Debian's) as .deb files in .gl/. Both folders are ignored by git (.git/info/exclude), about
# 3 MB together, and travel with the run:
#
#   sh tools/device_prepare.sh
#   device run: command "sh benchmarks/gpu_check.sh", carry [".whl", ".gl"], timeout_s 420
set -e
cd "$(git rev-parse --show-toplevel)"
for d in /.whl/ /.gl/; do
    grep -qxF "$d" .git/info/exclude || echo "$d" >> .git/info/exclude
done
mkdir -p .whl .gl /tmp/amd64/partial
python3 -m pip download -q --no-deps --only-binary=:all: --python-version 3.12 \
    --implementation cp --platform manylinux_2_28_x86_64 --platform manylinux_2_17_x86_64 \
    --platform manylinux2014_x86_64 --platform manylinux1_x86_64 -d .whl \
    moderngl glcontext OpenEXR tzdata
o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
# shellcheck disable=SC2086
apt-get $o update -qq
# shellcheck disable=SC2086
(cd .gl && apt-get $o download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
du -sh .whl .gl
