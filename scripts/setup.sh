#!/usr/bin/env bash
# From a fresh clone: install dependencies, build (Release), then
#   scripts/setup.sh demo   run the built-in synthetic demo end to end
#   scripts/setup.sh test   run every test (ctest)
set -euo pipefail
cd "$(dirname "$0")/.."
mode="${1:-build}"
case "$mode" in
  test) scripts/install_deps.sh --with-colmap ;;
  *) scripts/install_deps.sh ;;
esac
jobs="$(nproc)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DVARSFM_BUILD_TESTS=ON -DVARSFM_BUILD_BENCH=ON >/dev/null
# The demo needs only the command-line tool (and its I/O plug-in); the tests build everything.
case "$mode" in
  demo) cmake --build build -j "$jobs" --target varsfm_cli ;;
  *) cmake --build build -j "$jobs" ;;
esac
case "$mode" in
  demo) build/varsfm demo --output build/demo ;;
  test) cd build && ctest --output-on-failure -j "$jobs" ;;
  build) ;;
  *) echo "usage: scripts/setup.sh [build|demo|test]" >&2; exit 2 ;;
esac
