#!/usr/bin/env bash
# Every test: set up, build, and run the whole suite with ctest under a
# virtual X server (the widget tests need a display with OpenGL).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
xvfb-run -a -s "-noreset -screen 0 1280x800x24" \
  ctest --test-dir build --output-on-failure --timeout 600 -j "$(nproc)"
# The libFuzzer targets (clang, build/fuzz) on their committed regression
# corpora and a fixed number of mutations from a fixed seed: decoders and file
# readers must refuse bad bytes with their own error, never crash.
bash scripts/fuzz.sh --regress
