#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite: a Release build, then the same tests built with
# AddressSanitizer + UndefinedBehaviorSanitizer.
set -euo pipefail
if [ "${1:-}" = "--help" ] || [ "${1:-}" = "-h" ]; then
  sed -n '2,/^set -euo/p' "$0" | sed -n 's/^# \{0,1\}//p'
  exit 0
fi
cd "$(dirname "$0")/.."
bash tools/setup.sh --tests

jobs=$(nproc)
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DSHATTER_BUILD_BENCH=ON
cmake --build build/release -j "$jobs"
ctest --test-dir build/release --output-on-failure -j "$jobs"

# The sanitizer tree is built at -O1 with line tables only (-g1): the composed material kernels
# (src/materials/compose_*.cpp) take 2.6x less time to compile under ASan than at -O2 -g (59 s
# against 156 s each, measured), which keeps CI inside its hour; the checks are the same, and the
# stack traces still name file and line.
cmake -S . -B build/sanitize -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSHATTER_SANITIZE=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DSHATTER_BUILD_BENCH=OFF -DSHATTER_BUILD_STUDIES=OFF
cmake --build build/sanitize -j "$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build/sanitize --output-on-failure -j "$jobs"
