#!/usr/bin/env bash
# The long fuzzing and fault-injection run (tests/fuzz/fuzz.py --long; docs/reliability.md), to
# run before a release: every mutation of every key of every shipped scene, 100 kill-and-resume
# loops, 20 corrupted checkpoints. About 10 minutes on 2 cores (Release). CI runs the bounded
# version (ctest -R fuzz_bounded).
#   bash tools/fuzz-long.sh [build/release] [extra fuzz.py options, e.g. --jobs 4]
set -euo pipefail
if [ "${1:-}" = "--help" ] || [ "${1:-}" = "-h" ]; then
  sed -n '2,/^set -euo/p' "$0" | sed -n 's/^# \{0,1\}//p'
  exit 0
fi
cd "$(dirname "$0")/.."
build=${1:-build/release}
shift || true
cmake --build "$build" --target shatter
python3 tests/fuzz/fuzz.py --shatter "$build/shatter" --long "$@"
