#!/usr/bin/env bash
# The main job: set up, build, and launch the ground station against the
# built-in simulator. Extra arguments go to ambler-gs (e.g. --seed 4).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
exec build/bin/ambler-gs "$@"
