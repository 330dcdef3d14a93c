#!/usr/bin/env bash
# Installs the dependencies (scripts/setup.sh, scripts/setup_pymeshlab.sh) and builds everything
# into build/ (or $SBS_BUILD_DIR). Quiet on success.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build="${SBS_BUILD_DIR:-$top/build}"
bash "$top/scripts/setup.sh"
bash "$top/scripts/setup_pymeshlab.sh"
cmake -S "$top" -B "$build" -DCMAKE_BUILD_TYPE=Release >"$build.configure.log" 2>&1 ||
  { cat "$build.configure.log"; exit 1; }
cmake --build "$build" -j"$(nproc)" >"$build.build.log" 2>&1 ||
  { grep -E "error|Error" -A3 "$build.build.log" | head -60; exit 1; }
