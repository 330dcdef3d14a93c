#!/usr/bin/env bash
# The whole test suite: set-up, build, the GoogleTest units (ctest), then the end-to-end runs
# through the real meshlabserver and PyMeshLab (pytest).
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build="${SBS_BUILD_DIR:-$top/build}"
echo "== installing what is missing and building everything into $build (log: $build.build.log)"
bash "$top/scripts/build.sh"
echo "== unit tests (ctest)"
(cd "$build" && ctest --output-on-failure -j"$(nproc)")
echo "== end-to-end tests (pytest: meshlabserver, PyMeshLab)"
SBS_BUILD_DIR="$build" "$top/.venv/bin/python" -m pytest -q "$top/tests/e2e"
echo "== unit tests under AddressSanitizer + UndefinedBehaviorSanitizer, then 60 s of fuzzing"
bash "$top/scripts/test_sanitizers.sh"  # ASan + UBSan unit tests, 60 s of fuzzing (docs/ROBUSTNESS.md)
