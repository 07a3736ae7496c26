#!/bin/bash
# The convergence study (docs/verification.md) for every transfer scheme: FLIP (the paper's),
# the FLIP/PIC blend, PIC, XPIC(m), APIC, FMPM(k) and periodic XPIC/FMPM, uGIMP with fixed walls, the manufactured solution
# at both amplitudes to 512 cells and the vibrating bar to 256 cells, and the spherical elastic
# wave at a/h = 4-16 (SphericalWave.DISABLED_ConvergenceStudy of the verification_mpm test
# program, its s_rr L2 error and CPU time), one thread per run.
# Usage: studies/convergence/all_schemes.sh [build dir] [csv]   (about 15 min on one free core, and
#        about 12 CPU-min for the spherical wave; build targets convergence_study and
#        verification_mpm first)
set -euo pipefail
B=${1:-build/release}/convergence_study
WAVE=${1:-build/release}/tests/verification_mpm
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
# FMPM(k) and the periodic filters (solver.filter_every), the large-deformation MMS only (the
# issue's criterion), and the bar for FMPM; about 2 CPU-min.
for scheme in "--transfer fmpm --fmpm-order 2" "--transfer fmpm --fmpm-order 5" "--transfer fmpm --fmpm-order 10" \
              "--transfer xpic --xpic-order 5 --filter-every 5" "--transfer fmpm --fmpm-order 5 --filter-every 5" \
              "--transfer fmpm --fmpm-order 5 --filter-every 20" "--transfer xpic --xpic-order 2 --filter-every 20"; do
  # shellcheck disable=SC2086
  run --shapes ugimp --problems mms --mms-amplitudes large $MMS $scheme
done
for k in 2 5 10; do
  # shellcheck disable=SC2086
  run --shapes ugimp --problems bar $BAR --transfer fmpm --fmpm-order $k
done
# One point per cell per axis (issue 27's shock configuration) with FLIP, XPIC(2) and XPIC(5);
# about 4 CPU-min.
for scheme in "--transfer xpic --xpic-order 5" "--transfer flip" "--transfer xpic --xpic-order 2"; do
  # shellcheck disable=SC2086
  run --shapes ugimp --problems mms bar $MMS $BAR --points-per-cell 1 $scheme
done
# The other shapes with FLIP, as before (B-spline with mirrored walls: the first-order fixed-wall
# rows are gone since the fixed-wall image of Boundaries::mirror).
run --shapes linear bspline2 --problems mms bar $MMS $BAR --transfer flip
# The spherical elastic wave per scheme (tests/verification/mpm/spherical_wave_test.cpp).
for scheme in "flip" "flip 0.05" "flip 1" "xpic - 2" "xpic - 5" "apic" "fmpm - 2" "fmpm - 5"; do
  read -r kind fraction order <<<"$scheme"
  env=(SPHERICAL_WAVE_TRANSFER="$kind")
  [ -n "${fraction:-}" ] && [ "$fraction" != - ] && env+=(SPHERICAL_WAVE_PIC_FRACTION="$fraction")
  [ "$kind" = xpic ] && env+=(SPHERICAL_WAVE_XPIC_ORDER="$order")
  [ "$kind" = fmpm ] && env+=(SPHERICAL_WAVE_FMPM_ORDER="$order")
  env "${env[@]}" OMP_NUM_THREADS=1 SPHERICAL_WAVE_STUDY_CSV="$OUT" "$WAVE" \
    --gtest_also_run_disabled_tests --gtest_filter='SphericalWave.DISABLED_ConvergenceStudy'
done
