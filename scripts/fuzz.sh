#!/usr/bin/env bash
# Builds the libFuzzer targets with clang into build/fuzz and runs each for
# SECONDS (default 20) from a corpus it seeds itself. A crash, a leak, an
# undefined behaviour or an unexpected exception fails the run; the input is
# kept in build/fuzz/artifacts/ (replay: build/fuzz/fuzz/<target> FILE).
# Usage: scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
CC=clang CXX=clang++ cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DAMBLER_FUZZ=ON -DBUILD_TESTING=OFF > build/fuzz-configure.log 2>&1 ||
  { cat build/fuzz-configure.log; exit 1; }
cmake --build build/fuzz --target fuzzers
mkdir -p build/fuzz/artifacts
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
status=0
for target in fuzz_link_codec fuzz_range_image fuzz_json_config fuzz_pcd; do
  corpus=build/fuzz/corpus/$target
  mkdir -p "$corpus"
  echo "fuzz: $target for ${seconds} s"
  if ! build/fuzz/fuzz/$target -max_total_time="$seconds" -max_len=65536 -rss_limit_mb=2048 \
      -timeout=10 -print_final_stats=1 -artifact_prefix=build/fuzz/artifacts/$target- \
      "$corpus" > "build/fuzz/$target.log" 2>&1; then
    tail -n 60 "build/fuzz/$target.log"
    echo "fuzz: $target FAILED (log: build/fuzz/$target.log)"
    status=1
  else
    grep -E "stat::number_of_executed_units|cov: " "build/fuzz/$target.log" | tail -n 2
  fi
done
exit $status
