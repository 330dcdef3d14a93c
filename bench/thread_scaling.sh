#!/usr/bin/env bash
# One thread against two on the default (tools/smooth_mesh, the filter's core in-process), rounds
# interleaved: wall and CPU seconds, peak memory, medians, the speed-up, and whether the two
# outputs are byte-identical. Needs the scale benchmark's meshes (python3 bench/scale.py); installs
# and builds what it needs (bench/prepare.sh).
#   bash bench/thread_scaling.sh [MESH] [ROUNDS] [BUILD]
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
mesh=${1:-$top/bench/out/scale/meshes/bunny_2M_n0.2.ply}
rounds=${2:-3}
build=${3:-$top/build}
bash "$top/bench/prepare.sh" "$build" # GNU time and the tools
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for r in $(seq "$rounds"); do
  for t in 1 2; do
    /usr/bin/time -o "$work/time" -f "%e %U %S %M" env OMP_NUM_THREADS=$t \
      "$build/tools/smooth_mesh" "$mesh" "$work/out_$t.ply" >"$work/log" 2>&1 ||
      { cat "$work/log"; exit 1; }
    echo "$t $(cat "$work/time")" >>"$work/runs"
  done
  cmp -s "$work/out_1.ply" "$work/out_2.ply" && echo same >>"$work/identical" ||
    echo different >>"$work/identical"
done
/usr/bin/python3 - "$work/runs" "$work/identical" "$mesh" <<'PY'
import statistics, sys
runs = [line.split() for line in open(sys.argv[1])]
identical = open(sys.argv[2]).read().split()
med = {t: [statistics.median(float(r[i]) for r in runs if r[0] == t) for i in (1, 2, 3, 4)]
       for t in ("1", "2")}
print(f"{sys.argv[3]}: medians of {len(identical)} interleaved rounds")
print("| threads | wall s | user+sys s | peak MB |\n|---:|---:|---:|---:|")
for t in ("1", "2"):
    wall, user, sys_, rss = med[t]
    print(f"| {t} | {wall:.2f} | {user + sys_:.2f} | {rss / 1024:.0f} |")
print(f"speed-up (wall, 1 thread / 2 threads): {med['1'][0] / med['2'][0]:.2f}; outputs "
      f"byte-identical in {identical.count('same')} of {len(identical)} rounds")
PY
