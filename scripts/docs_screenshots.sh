#!/usr/bin/env bash
# Regenerates the MeshLab GUI screenshots in docs/ by running the GUI tests that take them
# (tests/e2e/test_gui.py, SBS_DOC_SCREENSHOTS): the dialog at 1366x768, the colour maps after
# Colorize by vertex Quality. Never edit those pictures by hand.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build="${SBS_BUILD_DIR:-$top/build}"
bash "$top/scripts/build.sh"
mkdir -p "$top/docs/img"
SBS_DOC_SCREENSHOTS="$top/docs/img" SBS_BUILD_DIR="$build" \
  "$top/.venv/bin/python" -m pytest -q "$top/tests/e2e/test_gui.py"
mv "$top/docs/img/filter_dialog.png" "$top/docs/filter_dialog.png"
