#!/usr/bin/env bash
# Installs the Debian packages the project needs, then configures and builds
# it (Release) into build/. Programs land in build/bin/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build
