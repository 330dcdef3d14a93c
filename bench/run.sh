#!/usr/bin/env bash
# The benchmark in one command (bench/README.md):
#   bash bench/run.sh            full run -> bench/RESULTS.md and docs/img/*.png (takes a while)
#   bash bench/run.sh --quick    CI: small public cases, one run, ~10k timing only; exits non-zero
#                                when a table is missing -> bench/out/quick/RESULTS.md
#   options: --out DIR (RESULTS.md + img/ there), --runs N (timing runs, default 3 / quick 1)
#   bash bench/run.sh --scanner [--jobs N] [--quick]   scanner-noise and light-noise cases
#                                (bench/SCANNER_NOISE.md), the real scans (bench/REAL_SCANS.md),
#                                then issue 16's "Done when" criteria (bench/done_when.py)
# Installs what it needs (Debian packages, as root or with sudo), builds the tools and the plugin
# into $SBS_BUILD_DIR (default build/), then runs bench/bench.py with Debian's python3.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build="${SBS_BUILD_DIR:-$top/build}"

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

if [ "${1:-}" = "--scanner" ]; then  # scanner noise, light noise and the real scans (issue 16)
  shift
  /usr/bin/python3 "$top/bench/scanner_bench.py" --build "$build" "$@"
  /usr/bin/python3 "$top/bench/real_scans.py" --build "$build"
  # issue 16's criteria from these two runs (FAIL lines are findings, not a failed benchmark)
  /usr/bin/python3 "$top/bench/done_when.py" --build "$build" || true
  exit 0
fi
exec /usr/bin/python3 "$top/bench/bench.py" --build "$build" "$@"
