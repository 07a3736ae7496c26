#!/bin/bash
# Interleaved whole-process rounds of shatter against a peer code on the same particles
# (docs/performance.md, "Peers"). Each round runs, under /usr/bin/time -v at nice -n 10:
#   shatter to 1 ns (start-up, point generation, end-of-run files: subtracted for the loop rate),
#   shatter to END, and each peer binary on its input, each in its own directory;
# odd rounds shatter first, even rounds the peers first. `uptime` before and after each process.
# rounds_table.py turns the directory into per-round rates, ratios, medians and ranges.
#
# usage: tools/peers/rounds.sh ROUNDS OUTDIR
# environment:
#   SHATTER   shatter binary                       SCENE   scene file
#   THREADS   threads for both codes (default 1)   END     end time, s
#   SETS      extra --set arguments for shatter, one string (word-split; e.g. the SPH method)
#   PEERS     space-separated NAME=BINARY pairs (e.g. "fast=/x/mpm3d-f90 o3=/y/mpm3d-f90")
#   PEER_INPUT  the peer input file (copied into each peer's directory)
#   PEER_ARGS   extra peer arguments after the input; the word THREADS is replaced by $THREADS
set -u
R=$1
OUT=$2
: "${SHATTER:?}" "${SCENE:?}" "${END:?}" "${PEERS:?}" "${PEER_INPUT:?}"
THREADS=${THREADS:-1}
SETS=${SETS:-}
PEER_ARGS=${PEER_ARGS:-}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
SCENE=$(cd "$(dirname "$SCENE")" && pwd)/$(basename "$SCENE")
PEER_INPUT=$(cd "$(dirname "$PEER_INPUT")" && pwd)/$(basename "$PEER_INPUT")
off=(--set output.snapshot_every=0 --set output.checkpoint_every=0 --set output.fragments=false
  --set output.progress_every=0)

run_shatter() { # $1 end time, $2 tag
  uptime >"$D/sh_$2.uptime"
  # shellcheck disable=SC2086
  nice -n 10 /usr/bin/time -v -o "$D/sh_$2.time" "$SHATTER" run "$SCENE" "${off[@]}" $SETS \
    --set solver.end_time="$1" --threads "$THREADS" --overwrite --out "$D/sh_$2" >"$D/sh_$2.log" 2>&1
  uptime >>"$D/sh_$2.uptime"
}
run_peers() {
  for p in $PEERS; do
    name=${p%%=*}
    bin=${p#*=}
    mkdir -p "$D/peer_$name"
    cp "$PEER_INPUT" "$D/peer_$name/"
    args=${PEER_ARGS//THREADS/$THREADS}
    uptime >"$D/peer_$name.uptime"
    # shellcheck disable=SC2086
    (cd "$D/peer_$name" && nice -n 10 /usr/bin/time -v -o "$D/peer_$name.time" "$bin" \
      "$(basename "$PEER_INPUT")" $args >"$D/peer_$name.log" 2>&1)
    uptime >>"$D/peer_$name.uptime"
  done
}
for r in $(seq 1 "$R"); do
  D=$OUT/r$r
  mkdir -p "$D"
  if [ $((r % 2)) -eq 1 ]; then
    run_shatter 1e-9 init
    run_shatter "$END" run
    run_peers
  else
    run_peers
    run_shatter 1e-9 init
    run_shatter "$END" run
  fi
  date -u >"$D/done"
done
