#!/usr/bin/env bash
# Every test under AddressSanitizer and UndefinedBehaviorSanitizer: a
# separate build in build/asan (RelWithDebInfo, -DAMBLER_SANITIZE=ON), then
# ctest under xvfb-run. Any memory error, leak in our code or undefined
# behaviour fails the test it happens in. Leaks inside the system's graphics
# and font libraries are suppressed (tests/sanitizers/lsan.supp).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build/asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DAMBLER_SANITIZE=ON
cmake --build build/asan
# (No strict_string_checks: libxkbcommon-x11 hands strndup unterminated
# buffers with their length, which that check reads past.)
cc -shared -fPIC -o build/asan/keep_loaded.so tests/sanitizers/keep_loaded.c
export LD_PRELOAD="$PWD/build/asan/keep_loaded.so"
# (verify_asan_link_order=0: that preload comes before the ASan runtime.)
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:detect_stack_use_after_return=1:verify_asan_link_order=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/sanitizers/lsan.supp:print_suppressions=0"
xvfb-run -a -s "-noreset -screen 0 1280x800x24" \
  ctest --test-dir build/asan --output-on-failure --timeout 1800 -j "$(nproc)" "$@"
