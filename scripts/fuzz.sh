#!/usr/bin/env bash
# The libFuzzer targets (tests/fuzz), built with clang into build/fuzz.
#
#   scripts/fuzz.sh --regress   what CI runs: each target replays its committed
#                               regression corpus (tests/fuzz/corpus/TARGET,
#                               every input that ever failed) and then makes a
#                               fixed number of mutations from a fixed seed.
#                               The same commit gives the same result.
#   scripts/fuzz.sh SECONDS     open-ended fuzzing, SECONDS per target (default
#                               20), from a random seed; a separate job, not CI.
#                               New inputs accumulate in build/fuzz/corpus.
#
# A crash, a leak, an undefined behaviour or an unexpected exception fails the
# run; the input is kept in build/fuzz/artifacts/ (replay it with
# build/fuzz/fuzz/TARGET FILE). Add it to tests/fuzz/corpus/TARGET with a
# unit test naming the defect.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=${1:-20}
targets=(fuzz_link_codec fuzz_range_image fuzz_json_config fuzz_pcd fuzz_ply fuzz_camera_image
         fuzz_mission_log)
# Mutations per target in --regress mode, and the seed they come from.
regress_runs=20000
regress_seed=20261124

mkdir -p build
CC=clang CXX=clang++ cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DAMBLER_FUZZ=ON -DBUILD_TESTING=OFF > build/fuzz-configure.log 2>&1 ||
  { cat build/fuzz-configure.log; exit 1; }
cmake --build build/fuzz --target fuzzers
mkdir -p build/fuzz/artifacts
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
common=(-max_len=65536 -rss_limit_mb=2048 -timeout=10 -print_final_stats=1)
status=0
# Regress mode runs each target on a fixed list of inputs (its seeds and the
# regression corpus, in name order) with no corpus directory, so directory
# order cannot change the run; with address randomisation off (setarch -R:
# comparisons of pointers feed the mutator) and no corpus reloads (timed),
# libFuzzer then makes the same mutations every time.
regress() {
  local target=$1 seeds=build/fuzz/seeds/$1 inputs
  rm -rf "$seeds" && mkdir -p "$seeds"
  build/fuzz/fuzz/$target -runs=0 "$seeds" > /dev/null 2>&1  # writes the seeds
  inputs=$(find "$seeds" "tests/fuzz/corpus/$target" -type f | LC_ALL=C sort | paste -sd, -)
  echo "fuzz: $target: $(ls "tests/fuzz/corpus/$target" | wc -l) regression inputs and its seeds, then $regress_runs runs from seed $regress_seed"
  setarch "$(uname -m)" -R build/fuzz/fuzz/$target "${common[@]}" -runs=$regress_runs \
    -seed=$regress_seed -reload=0 -seed_inputs="$inputs" \
    -artifact_prefix=build/fuzz/artifacts/$target-
}

explore() {
  local target=$1 corpus=build/fuzz/corpus/$1
  mkdir -p "$corpus"
  echo "fuzz: $target for $mode s"
  build/fuzz/fuzz/$target "${common[@]}" -max_total_time="$mode" \
    -artifact_prefix=build/fuzz/artifacts/$target- "$corpus" "tests/fuzz/corpus/$target"
}

for target in "${targets[@]}"; do
  if [ "$mode" = "--regress" ]; then run=regress; else run=explore; fi
  if ! $run "$target" > "build/fuzz/$target.log" 2>&1; then
    tail -n 60 "build/fuzz/$target.log"
    echo "fuzz: $target FAILED (log: build/fuzz/$target.log)"
    status=1
  else
    head -n 1 "build/fuzz/$target.log"
    grep -E "stat::number_of_executed_units|cov: " "build/fuzz/$target.log" | tail -n 2
  fi
done
exit $status
