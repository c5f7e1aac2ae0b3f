#!/usr/bin/env bash
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer: builds everything with
# VARSFM_SANITIZE=ON (GCC) in build-asan, then runs ctest there at low priority (it is several
# times slower than the Release suite). Any memory error, leak or undefined behaviour fails the
# test that hit it. Extra arguments go to ctest, e.g. scripts/sanitize.sh -R 'Ply|Colmap'.
#   JOBS=2 scripts/sanitize.sh [CTEST_ARGS...]
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="${JOBS:-2}"
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
# Third-party findings that are not varsfm's are suppressed in scripts/sanitizers/, each with
# the reason.
export ASAN_OPTIONS="detect_leaks=1:${ASAN_OPTIONS:-}"
export LSAN_OPTIONS="suppressions=$PWD/scripts/sanitizers/lsan.supp:print_suppressions=0:${LSAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:${UBSAN_OPTIONS:-}"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DVARSFM_SANITIZE=ON \
  -DVARSFM_BUILD_TESTS=ON -DVARSFM_BUILD_BENCH=OFF "${launcher[@]}" >/dev/null
nice -n 19 cmake --build build-asan -j "$jobs"
cd build-asan
nice -n 19 ctest --output-on-failure -j "$jobs" "$@"
