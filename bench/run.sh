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

# Installs what is missing and builds the benchmark's targets (bench/prepare.sh).
bash "$top/bench/prepare.sh" "$build"

if [ "${1:-}" = "--scanner" ]; then  # scanner noise, light noise and the real scans (issue 16)
  shift
  /usr/bin/python3 "$top/bench/scanner_bench.py" --build "$build" "$@"
  /usr/bin/python3 "$top/bench/real_scans.py" --build "$build"
  # issue 16's criteria from these two runs (FAIL lines are findings, not a failed benchmark)
  /usr/bin/python3 "$top/bench/done_when.py" --build "$build" || true
  exit 0
fi
exec /usr/bin/python3 "$top/bench/bench.py" --build "$build" "$@"
