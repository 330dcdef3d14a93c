#!/usr/bin/env bash
# The unit tests under AddressSanitizer + UndefinedBehaviorSanitizer (gcc, into build-asan/), with
# vcglib's and Eigen's assertions on (no NDEBUG); then the libFuzzer target (clang, into
# build-fuzz/) for a short budget, starting from the committed corpus (docs/ROBUSTNESS.md).
#   SBS_FUZZ_SECONDS  fuzzing budget in seconds (default 60)
# Two compilers because clang 14's ASan aborts at exit when LLVM's OpenMP runtime ran
# ("CHECK failed: asan_posix.cpp:124 tsd_key_inited"): the unit tests need OpenMP, the fuzz target
# (one thread) is built without it.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
asan="${SBS_ASAN_BUILD_DIR:-$top/build-asan}"
fuzz="${SBS_FUZZ_BUILD_DIR:-$top/build-fuzz}"
seconds="${SBS_FUZZ_SECONDS:-60}"

if ! command -v clang++ >/dev/null; then
  echo "[sanitizers] installing clang (libFuzzer)" >&2
  as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }
  as_root apt-get update -qq >/dev/null 2>&1 || true
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    clang >/dev/null
fi

# configure <dir> <target> <cmake args...>: quiet unless it fails.
build() {
  local dir=$1 target=$2
  shift 2
  cmake -S "$top" -B "$dir" -DBUILD_PLUGIN=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" "$@" >"$dir.configure.log" 2>&1 ||
    { cat "$dir.configure.log"; exit 1; }
  cmake --build "$dir" -j"$(nproc)" --target "$target" >"$dir.build.log" 2>&1 ||
    { grep -E "error|Error|ERROR|runtime error" -A5 "$dir.build.log" | head -80; exit 1; }
}

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"

echo "== unit tests under ASan + UBSan (gcc)"
CXX=g++ build "$asan" unit_tests -DSBS_SANITIZE=ON
"$asan/tests/unit_tests" --gtest_brief=1

echo "== fuzzing both filters for ${seconds} s (clang libFuzzer + ASan + UBSan)"
CXX=clang++ build "$fuzz" fuzz_filters -DSBS_FUZZ=ON -DCMAKE_DISABLE_FIND_PACKAGE_OpenMP=ON
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$fuzz/findings"
# New inputs go to the scratch corpus; the committed one is only read. A finding is saved in
# build-fuzz/findings/ and fails this script: add it to tests/fuzz/regressions/ and fix the bug.
"$fuzz/tests/fuzz/fuzz_filters" -max_total_time="$seconds" -print_final_stats=1 -timeout=20 \
  -rss_limit_mb=4096 -artifact_prefix="$fuzz/findings/" "$work" "$top/tests/fuzz/corpus" \
  2>"$fuzz/fuzz.log" || { tail -60 "$fuzz/fuzz.log"; exit 1; }
grep -E "stat::number_of_executed_units|stat::average_exec_per_sec" "$fuzz/fuzz.log"
