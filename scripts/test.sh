#!/usr/bin/env bash
# Every test: set up, build, and run the whole suite with ctest under a
# virtual X server (the widget tests need a display with OpenGL).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
xvfb-run -a -s "-screen 0 1280x800x24" \
  ctest --test-dir build --output-on-failure --timeout 600 -j "$(nproc)"
