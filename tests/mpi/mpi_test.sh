#!/usr/bin/env bash
# MPI decomposition tests (docs/mpi.md), one case per ctest test (label mpi):
#   mpi_test.sh CASE SHATTER COMPARE_RUNS SOURCE_DIR WORK_DIR
# Every comparison is bitwise (tolerance zero): compare_runs matches particles by id and
# requires identical bits in every column, in the clock and energy accounts, and (for whole
# runs) in every time-series row but the wall-clock column; fragment catalogues are compared
# byte for byte. The single process is the reference; --oversubscribe runs 2-4 ranks on the
# 2-core CI machine, one thread each.
set -euo pipefail
case_name=$1 shatter=$2 compare=$3 src=$4 work=$5
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_mpi_yield_when_idle=1
export OMPI_MCA_rmaps_base_oversubscribe=1
rm -rf "$work" && mkdir -p "$work" && cd "$work"
mpi() { local n=$1; shift; mpirun --oversubscribe -np "$n" "$@"; }
fail() { echo "FAIL: $*"; exit 1; }

# run_pair NAME SCENE RANKS... -- ARGS: the single process, then each rank count, compared
run_all() {
  local name=$1 scene=$2; shift 2
  local ranks=() args=()
  while [ "$1" != "--" ]; do ranks+=("$1"); shift; done
  shift; args=("$@")
  "$shatter" run "$scene" --out "$name-1" --overwrite --threads 1 --quiet "${args[@]}"
  for n in "${ranks[@]}"; do
    mpi "$n" "$shatter" run "$scene" --out "$name-$n" --overwrite --threads 1 --quiet "${args[@]}"
    "$compare" "$name-1" "$name-$n" || fail "$name on $n ranks differs from one process"
    if [ -f "$name-1/fragments.csv" ]; then
      cmp "$name-1/fragments.csv" "$name-$n/fragments.csv" || fail "$name fragments on $n ranks"
      cmp "$name-1/fragments.h5" "$name-$n/fragments.h5" || fail "$name fragments.h5 on $n ranks"
    fi
  done
}

impact=("$src/scenes/lab-impact-coarse.toml" --set solver.cell_size=4e-3
        --set output.snapshot_every=0)

case $case_name in
  elastic_bar)
    # axially vibrating bar: a fixed face (odd mirror at the owner), slip sides; 30 steps
    run_all bar "$src/scenes/verification/vibrating-bar.toml" 2 4 -- \
      --set solver.end_time=0.7 --set output.snapshot_every=0
    ;;
  colliding_spheres)
    # two elastic spheres meet (contact from step ~34 of 45) on 1-4 ranks
    run_all spheres "$src/scenes/verification/colliding-spheres.toml" 2 3 4 -- \
      --set solver.end_time=0.25 --set output.snapshot_every=0 \
      --set 'body.a.velocity=[1.0, 1.0, 1.0]' --set 'body.b.velocity=[-1.0, -1.0, -1.0]'
    ;;
  transfers)
    # XPIC(2) (extra scatter passes, each exchanged) on 3 ranks and APIC on 2
    spheres=(--set solver.end_time=0.25 --set output.snapshot_every=0
             --set 'body.a.velocity=[1.0, 1.0, 1.0]' --set 'body.b.velocity=[-1.0, -1.0, -1.0]')
    run_all xpic "$src/scenes/verification/colliding-spheres-xpic.toml" 3 -- "${spheres[@]}"
    run_all apic "$src/scenes/verification/colliding-spheres.toml" 2 -- "${spheres[@]}" \
      --set solver.transfer=apic
    ;;
  impact_damage)
    # lab impact (basalt, Grady-Kipp damage, Tillotson, symmetry plane z = 0) at 4 mm, 40 steps:
    # particles, damage, flaws and the fragment catalogue
    run_all impact "${impact[0]}" 2 4 -- "${impact[@]:1}" --set solver.end_time=3e-6 \
      --set output.checkpoint_every=0
    grep -q "failure" impact-1/timeseries.csv || fail "no failure ratio column"
    ;;
  migration_rebalance)
    # a fast cube crossing rank boundaries; the curve recut at every step (it must not change
    # a bit), and the run must have migrated particles and recut
    recut=(--set solver.mpi.imbalance=1.0 --set solver.mpi.rebalance_every=1)
    "$shatter" run "$src/tests/mpi/fast-body.toml" --out fast-1 --overwrite --threads 1 --quiet \
      "${recut[@]}"
    mpi 3 "$shatter" run "$src/tests/mpi/fast-body.toml" --out fast-3 --overwrite --threads 1 \
      "${recut[@]}" 2> log.txt
    "$compare" fast-1 fast-3 || fail "fast body on 3 ranks differs from one process"
    line=$(grep "mpi: 3 ranks" log.txt) || fail "no mpi summary line"
    echo "$line"
    recuts=$(sed -E 's/.* ([0-9]+) recuts.*/\1/' <<<"$line")
    moved=$(sed -E 's/.*migration ([0-9]+) bytes.*/\1/' <<<"$line")
    [ "$recuts" -gt 10 ] || fail "only $recuts recuts"
    [ "$moved" -gt 0 ] || fail "no particle migrated"
    ;;
  resume)
    # a run checkpointed at 1.5 us and resumed to 3 us on another rank count equals the
    # uninterrupted one (particles, clock, energy accounts; the time series of a resumed run
    # has one more row at the checkpoint in one process too, so it is not compared)
    common=("${impact[@]:1}" --set output.checkpoint_every=1.5e-6)
    "$shatter" run "${impact[0]}" --out whole --overwrite --threads 1 --quiet "${common[@]}" \
      --set solver.end_time=3e-6
    "$shatter" run "${impact[0]}" --out a --overwrite --threads 1 --quiet "${common[@]}" \
      --set solver.end_time=1.5e-6
    mpi 3 "$shatter" resume a/checkpoint.h5 --set solver.end_time=3e-6 --threads 1 --quiet
    "$compare" whole/checkpoint.h5 a/checkpoint.h5 || fail "1 -> 3 ranks resume differs"
    mpi 3 "$shatter" run "${impact[0]}" --out b --overwrite --threads 1 --quiet "${common[@]}" \
      --set solver.end_time=1.5e-6
    mpi 2 "$shatter" resume b/checkpoint.h5 --set solver.end_time=3e-6 --threads 1 --quiet
    "$compare" whole/checkpoint.h5 b/checkpoint.h5 || fail "3 -> 2 ranks resume differs"
    cmp whole/fragments.csv b/fragments.csv || fail "fragments after resume"
    ;;
  fault)
    # a NaN in one rank's particles: every rank stops at that step with the numerical-failure
    # code (3), the cause reported once, by that rank; the post-mortem file is written
    spheres=("$src/scenes/verification/colliding-spheres.toml" --set solver.end_time=0.3
             --set output.snapshot_every=0 --threads 1)
    set +e
    SHATTER_FAULT_INJECT=nan:1:5 timeout 60 mpirun --oversubscribe -np 3 \
      -x SHATTER_FAULT_INJECT "$shatter" run "${spheres[@]}" --out nan 2> nan.txt
    code=$?
    set -e
    cat nan.txt
    [ "$code" -eq 3 ] || fail "NaN on rank 1: exit $code, expected 3"
    [ "$(grep -c 'non-finite vx' nan.txt)" -eq 1 ] || fail "the cause is not reported once"
    grep -q "\[rank 1\] error.*non-finite vx" nan.txt || fail "the report does not name rank 1"
    [ -f nan/failed_step5.h5 ] || fail "no post-mortem snapshot"
    # an exception on one rank: reported with its rank, every rank ends (no hang), non-zero
    set +e
    SHATTER_FAULT_INJECT=throw:1:3 timeout 60 mpirun --oversubscribe -np 2 \
      -x SHATTER_FAULT_INJECT "$shatter" run "${spheres[@]}" --out throw 2> throw.txt
    code=$?
    set -e
    cat throw.txt
    [ "$code" -ne 0 ] && [ "$code" -ne 124 ] || fail "exception on rank 1: exit $code"
    grep -q "\[rank 1\] error injected fault" throw.txt || fail "the report does not name rank 1"
    ;;
  *)
    fail "unknown case $case_name"
    ;;
esac
echo "PASS $case_name"
