#!/usr/bin/env bash
# What every benchmark needs, once: the build dependencies (scripts/setup.sh), the benchmark's own
# Debian packages (as root or with sudo; quiet when already there) and the plugin and tools built
# into BUILD (default: $SBS_BUILD_DIR or build/). bench/run.sh and bench/scale.py call it.
#   bash bench/prepare.sh [BUILD]
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build="${1:-${SBS_BUILD_DIR:-$top/build}}"

log() { echo "[bench] $*" >&2; }
as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@";
  else log "need root for: $*"; exit 1; fi
}

# Build dependencies, MeshLab 2020.09 headers and vcglib (quiet when already there).
bash "$top/scripts/setup.sh"

# The benchmark's own: plots, the libcgal-demo meshes, GNU time for peak memory, Xvfb, MeshLab and
# the SD filter (meshsdfilter-tools: MeshDenoiser), the peers.
packages=(python3-numpy python3-matplotlib libcgal-demo time xvfb meshlab meshsdfilter-tools)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  log "installing Debian packages: ${missing[*]}"
  as_root apt-get update -qq >/dev/null 2>&1 || true
  as_root env DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=900 install -y -qq \
    --no-install-recommends "${missing[@]}" >/dev/null
fi

log "building into $build"
mkdir -p "$build"
cmake -S "$top" -B "$build" -DCMAKE_BUILD_TYPE=Release >"$build/bench.configure.log" 2>&1 ||
  { cat "$build/bench.configure.log"; exit 1; }
cmake --build "$build" -j"$(nproc)" --target filter_saliency_bezier_smooth smooth_mesh add_noise \
  mesh_compare write_mlx >"$build/bench.build.log" 2>&1 ||
  { grep -E "error|Error" -A3 "$build/bench.build.log" | head -60; exit 1; }
