#!/bin/bash
# The convergence study (docs/verification.md) for every transfer scheme: FLIP (the paper's),
# the FLIP/PIC blend, PIC, XPIC(m) and APIC, uGIMP with fixed walls, the manufactured solution
# at both amplitudes to 512 cells and the vibrating bar to 256 cells, one thread per run.
# Usage: tools/convergence/all_schemes.sh [build dir] [csv]   (about 15 min on one free core)
set -euo pipefail
B=${1:-build/release}/convergence_study
OUT=${2:-docs/convergence.csv}
MMS="--mms-cells 8 16 32 64 128 256 512"
BAR="--bar-cells 16 32 64 128 256"
first=1
run() {
  if [ $first = 1 ]; then "$B" "$@" -t 1 -o "$OUT"; first=0; else "$B" "$@" -t 1 --append -o "$OUT"; fi
}
for scheme in "--transfer flip" "--transfer flip --pic-fraction 0.05" "--transfer flip --pic-fraction 1" \
              "--transfer xpic --xpic-order 2" "--transfer xpic --xpic-order 5" "--transfer apic"; do
  # shellcheck disable=SC2086
  run --shapes ugimp --problems mms bar $MMS $BAR $scheme
done
# The other shapes with FLIP, as before (B-spline with mirrored walls: the first-order fixed-wall
# rows are gone since the fixed-wall image of Boundaries::mirror).
run --shapes linear bspline2 --problems mms bar $MMS $BAR --transfer flip
