#!/usr/bin/env bash
# What every benchmark needs, once: the build dependencies (scripts/setup.sh), the benchmark's own
# Debian packages (as root or with sudo; quiet when already there) and the plugin and tools built
# into BUILD (default: $SBS_BUILD_DIR or build/). bench/run.sh, bench/scale.py and
# bench/thread_scaling.sh call it.
#   bash bench/prepare.sh [BUILD]
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build="${1:-${SBS_BUILD_DIR:-$top/build}}"

log() { echo "[bench] $*" >&2; }

# Build dependencies, MeshLab 2020.09 headers and vcglib, and the benchmark's own packages: plots,
# the libcgal-demo meshes, GNU time for peak memory and the SD filter (meshsdfilter-tools:
# MeshDenoiser), a peer (scripts/setup.sh installs what is missing; Xvfb and MeshLab come with it).
bash "$top/scripts/setup.sh" python3-matplotlib libcgal-demo time meshsdfilter-tools

log "building into $build"
mkdir -p "$build"
cmake -S "$top" -B "$build" -DCMAKE_BUILD_TYPE=Release >"$build/bench.configure.log" 2>&1 ||
  { cat "$build/bench.configure.log"; exit 1; }
cmake --build "$build" -j"$(nproc)" --target filter_saliency_bezier_smooth smooth_mesh add_noise \
  mesh_compare write_mlx >"$build/bench.build.log" 2>&1 ||
  { grep -E "error|Error" -A3 "$build/bench.build.log" | head -60; exit 1; }
