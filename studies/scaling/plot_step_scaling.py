#!/usr/bin/python3
"""Throughput of the whole elastic MPM step against particle count, 1 and 2 threads.

Runs bench_step's BM_Step/ugimp once per (particle count, threads), one benchmark per process
(SHATTER_BENCH_PARTICLES sets the count), and writes a CSV and a plot:

    studies/scaling/plot_step_scaling.py [--build build/release] [--counts 1e4 3e4 1e5 3e5 1e6]
                               [--out docs/figures/performance/step_scaling] [--replot]

Figures per run: particle-steps per wall second, per process-CPU second (the per-core rate,
comparable on a loaded machine), resident bytes per particle, and the load average at the time.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def run(exe: Path, n: int, threads: int, min_time: float) -> dict:
    env = dict(os.environ, SHATTER_BENCH_PARTICLES=str(n))
    flt = f"BM_Step/ugimp/particles:{n}/threads:{threads}/"
    proc = subprocess.run([str(exe), f"--benchmark_filter={flt}", f"--benchmark_min_time={min_time}",
                           "--benchmark_format=json"], env=env, capture_output=True, text=True,
                          check=False)
    if proc.returncode != 0:
        sys.exit(f"plot_step_scaling: {exe} failed for n={n}, threads={threads}:\n{proc.stderr}")
    b = [x for x in json.loads(proc.stdout)["benchmarks"] if x["name"].startswith("BM_Step")][0]
    scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[b["time_unit"]]
    particles = b["items_per_second"] * b["real_time"] * scale  # items per iteration
    return {
        "particles": round(particles), "threads": threads,
        "wall_rate": b["items_per_second"],
        "cpu_rate": particles / (b["cpu_time"] * scale),
        "resident_bytes_per_particle": b.get("resident_bytes/particle", float("nan")),
        "load": os.getloadavg()[0],
    }


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("--build", default=str(ROOT / "build/release"))
    ap.add_argument("--counts", nargs="*", type=float, default=[1e4, 3e4, 1e5, 3e5, 1e6])
    ap.add_argument("--threads", nargs="*", type=int, default=[1, 2])
    ap.add_argument("--min-time", type=float, default=1.0)
    ap.add_argument("--replot", action="store_true", help="plot the existing CSV, run nothing")
    ap.add_argument("--out", default=str(ROOT / "docs/figures/performance/step_scaling"),
                    help="output path without extension (.csv and .png are written)")
    args = ap.parse_args()
    out = Path(args.out)
    if args.replot:
        with open(out.with_suffix(".csv"), newline="") as f:
            rows = [{k: (int(v) if k in ("particles", "threads") else float(v))
                     for k, v in r.items()} for r in csv.DictReader(f)]
    else:
        exe = Path(args.build) / "bench" / "bench_step"
        if not exe.exists():
            sys.exit(f"plot_step_scaling: no {exe} (build bench_step with -DSHATTER_BUILD_BENCH=ON)")
        rows = []
        for n in args.counts:
            for t in args.threads:
                r = run(exe, int(n), t, args.min_time)
                print(f"n={r['particles']:>8d} threads={t} wall {r['wall_rate']:.3e}/s "
                      f"cpu {r['cpu_rate']:.3e}/s  {r['resident_bytes_per_particle']:.0f} "
                      f"B/particle load {r['load']:.1f}", flush=True)
                rows.append(r)
        out.parent.mkdir(parents=True, exist_ok=True)
        with open(out.with_suffix(".csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    args.threads = sorted({r["threads"] for r in rows})

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for t, colour in zip(args.threads, ["tab:blue", "tab:orange", "tab:green"]):
        sel = [r for r in rows if r["threads"] == t]
        ns = [r["particles"] for r in sel]
        ax.plot(ns, [r["wall_rate"] for r in sel], "o-", color=colour,
                label=f"{t} thread{'s' if t > 1 else ''}, wall (machine shared)")
        ax.plot(ns, [t * r["cpu_rate"] for r in sel], "s--", color=colour,
                label=f"{t} x per-core rate (process CPU time)")
    ax.axhline(1e7, color="grey", lw=0.8, ls=":")
    ax.text(min(r["particles"] for r in rows), 1.05e7,
            "issue 12 target, 2 threads", fontsize=8, color="grey")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("particles")
    ax.set_ylabel("particle-steps per second")
    ax.set_title("Elastic MUSL step, uGIMP (bench_step)")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out.with_suffix(".png"), dpi=120)
    print(f"wrote {out.with_suffix('.csv')} and {out.with_suffix('.png')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
