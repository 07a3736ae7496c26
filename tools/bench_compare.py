#!/usr/bin/python3
"""Run shatter's benchmark programs and compare every figure with a committed baseline.

Each benchmark program links the same reference kernel (bench/support/reference.cpp, the
benchmark named "reference"). Every figure is taken as process CPU time per iteration divided by
the reference's CPU time per iteration *from the same process*, so what the machine's load,
frequency or cache contention does to both cancels in the ratio. The comparison is the ratio of
those normalised costs, baseline / now: above 1 means faster now. Each benchmark (the reference
included) runs --repetitions times and the least CPU time counts.

    tools/bench_compare.py --particles 100000    # run all at 1e5 points, compare with
                                                 # bench/baseline.json (made the same way)
    tools/bench_compare.py --programs step p2g   # some programs only
    tools/bench_compare.py --write-baseline      # run and store as the new baseline
    tools/bench_compare.py --fail-slower 0.8     # exit 1 when a figure is below 0.8x baseline

Stdout: one line per benchmark (normalised cost now, in baseline, speed-up), then the lists of
what got faster and slower than the threshold. Figures missing from either side are listed.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
REFERENCE = "reference"


def run_program(exe: Path, min_time: float, filt: str | None, particles: int | None,
                repetitions: int) -> dict:
    """Runs one benchmark program; returns {name: cpu_time per iteration (ns)} with the reference,
    the least of the repetitions (the least disturbed run on a shared machine)."""
    env = dict(os.environ)
    if particles:
        env["SHATTER_BENCH_PARTICLES"] = str(particles)
    with tempfile.NamedTemporaryFile(suffix=".json", delete=False) as f:
        out = Path(f.name)
    cmd = [str(exe), f"--benchmark_min_time={min_time}", f"--benchmark_out={out}",
           "--benchmark_out_format=json", "--benchmark_format=console",
           f"--benchmark_repetitions={repetitions}"]
    if filt:
        cmd.append(f"--benchmark_filter={REFERENCE}|{filt}")
    proc = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                          text=True, check=False)
    if proc.returncode != 0:
        sys.exit(f"bench_compare: {exe.name} failed (exit {proc.returncode}):\n{proc.stderr}")
    data = json.loads(out.read_text())
    out.unlink()
    scale = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}
    figures = {}
    for b in data.get("benchmarks", []):
        if b.get("run_type", "iteration") != "iteration" or "error_occurred" in b:
            continue
        name = b["name"]
        if name.split("/")[0] == REFERENCE:
            name = REFERENCE  # "reference/process_time"
        t = b["cpu_time"] * scale[b.get("time_unit", "ns")]
        figures[name] = min(t, figures.get(name, t))
    if REFERENCE not in figures:
        sys.exit(f"bench_compare: {exe.name} has no '{REFERENCE}' benchmark "
                 "(bench/support/reference.cpp must be linked into every program)")
    return {"context": data.get("context", {}), "figures": figures}


def normalised(run: dict) -> dict:
    ref = run["figures"][REFERENCE]
    return {k: v / ref for k, v in run["figures"].items() if k != REFERENCE}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("--build", default=str(ROOT / "build/release"),
                    help="build directory holding bench/bench_* (default build/release)")
    ap.add_argument("--baseline", default=str(ROOT / "bench/baseline.json"))
    ap.add_argument("--programs", nargs="*", help="program stems (step, p2g, ...); default all")
    ap.add_argument("--filter", help="regex of benchmark names (the reference always runs)")
    ap.add_argument("--min-time", type=float, default=0.2, help="seconds per benchmark run")
    ap.add_argument("--repetitions", type=int, default=3,
                    help="runs of each benchmark; the least CPU time counts (default 3)")
    ap.add_argument("--particles", type=int,
                    help="run size-dependent benchmarks at this particle count only")
    ap.add_argument("--threshold", type=float, default=0.05,
                    help="relative change reported as faster/slower (default 0.05)")
    ap.add_argument("--fail-slower", type=float, metavar="RATIO",
                    help="exit 1 if any figure runs below RATIO x its baseline speed")
    ap.add_argument("--write-baseline", action="store_true", help="store this run as baseline")
    ap.add_argument("--json", help="also write this run (raw and normalised) to this file")
    args = ap.parse_args()

    bench_dir = Path(args.build) / "bench"
    exes = sorted(p for p in bench_dir.glob("bench_*") if p.is_file() and os.access(p, os.X_OK))
    if args.programs:
        wanted = {f"bench_{s}" for s in args.programs}
        missing = wanted - {p.name for p in exes}
        if missing:
            sys.exit(f"bench_compare: no program {', '.join(sorted(missing))} in {bench_dir}")
        exes = [p for p in exes if p.name in wanted]
    if not exes:
        sys.exit(f"bench_compare: no bench_* programs in {bench_dir} "
                 "(configure with -DSHATTER_BUILD_BENCH=ON and build them)")

    now = {}
    for exe in exes:
        print(f"running {exe.name} ...", file=sys.stderr, flush=True)
        r = run_program(exe, args.min_time, args.filter, args.particles, args.repetitions)
        now[exe.name] = {"reference_ns": r["figures"][REFERENCE], "cpu_ns": r["figures"],
                         "normalised": normalised(r)}
    record = {
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "host": platform.node(), "load": os.getloadavg(), "particles": args.particles,
        "min_time": args.min_time, "programs": now,
    }
    if args.json:
        Path(args.json).write_text(json.dumps(record, indent=1) + "\n")
    if args.write_baseline:
        base_path = Path(args.baseline)
        old = json.loads(base_path.read_text()) if base_path.exists() else {"programs": {}}
        old["programs"].update(now)  # a partial run updates only the programs it ran
        for k in ("date", "host", "load", "particles", "min_time"):
            old[k] = record[k]
        base_path.write_text(json.dumps(old, indent=1, sort_keys=True) + "\n")
        print(f"baseline written: {base_path}")
        return 0

    base_path = Path(args.baseline)
    if not base_path.exists():
        sys.exit(f"bench_compare: no baseline {base_path} (make one with --write-baseline)")
    base_all = json.loads(base_path.read_text())
    if base_all.get("particles") != args.particles:
        print(f"note: the baseline was run with --particles {base_all.get('particles')}, this run "
              f"with {args.particles}: only benchmarks of the same name are compared",
              file=sys.stderr)
    base = base_all["programs"]
    faster, slower, unmatched = [], [], []
    print(f"{'benchmark':64s} {'now':>10s} {'baseline':>10s} {'speed-up':>9s}")
    for prog, r in now.items():
        b = base.get(prog, {}).get("normalised", {})
        for name, cost in sorted(r["normalised"].items()):
            if name not in b:
                unmatched.append(f"{prog}: {name} (not in baseline)")
                continue
            speedup = b[name] / cost
            print(f"{prog[6:] + ': ' + name:64s} {cost:10.4g} {b[name]:10.4g} {speedup:8.2f}x")
            if speedup > 1.0 + args.threshold:
                faster.append((speedup, f"{prog}: {name}"))
            elif speedup < 1.0 - args.threshold:
                slower.append((speedup, f"{prog}: {name}"))
        for name in sorted(set(b) - set(r["normalised"])):
            if args.filter is None and args.particles is None:
                unmatched.append(f"{prog}: {name} (in baseline, not run)")
    print(f"\nnormalised cost = process CPU time per iteration / the '{REFERENCE}' kernel's in "
          f"the same process; speed-up = baseline / now (load now {os.getloadavg()[0]:.1f})")
    print(f"\nfaster by more than {args.threshold:.0%}: {len(faster)}")
    for s, n in sorted(faster, reverse=True):
        print(f"  {s:6.2f}x  {n}")
    print(f"slower by more than {args.threshold:.0%}: {len(slower)}")
    for s, n in sorted(slower):
        print(f"  {s:6.2f}x  {n}")
    if unmatched:
        print("not compared:")
        for u in unmatched:
            print(f"  {u}")
    if args.fail_slower is not None and any(s < args.fail_slower for s, _ in slower):
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
