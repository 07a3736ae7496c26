#!/usr/bin/python3
"""Laboratory impact, SPH beside MPM (issue 10 "Laboratory impact"): tables from finished seed
ensembles of tools/ensemble.py (one directory per method and resolution, seed<S>/ runs inside).

Per ensemble, mean +- sample std (and range) over its seeds of:
  failure ratio (timeseries.csv failure_ratio: points with D >= fracture.threshold) at
  10, 20, 40 and 100 us (linear interpolation);
  with --fof, the largest fragment by BA95 Sec. 4.4 (friends-of-friends, one-layer damaged
  veneer) on each run's last snapshot through `shatter fragments`: for SPH runs friends within
  one smoothing length (--smoothing-factor, the runs' solver.sph.h_factor), for MPM runs the
  module's 1.5-spacing link; its mass over the total mass (target + 0.2 g projectile) and speed.
The grid-density catalogue (the runs' own fragments.csv) is in each ensemble's ensemble.md.

Usage:
  sph_lab_compare.py DIR [DIR ...] [--fof] [--shatter build/release/shatter] [--h-factor 1.2]
"""

import argparse
import csv
import glob
import os
import statistics
import subprocess

import numpy as np

TIMES_US = (10.0, 20.0, 40.0, 100.0)


def failure_at(run_dir, t_us):
    t, f = [], []
    with open(os.path.join(run_dir, "timeseries.csv")) as fh:
        for row in csv.DictReader(fh):
            t.append(float(row["time_s"]) * 1e6)
            f.append(float(row["failure_ratio"]))
    return float(np.interp(t_us, t, f)) if t and t_us <= t[-1] * 1.0001 else float("nan")


def is_sph(run_dir):
    with open(os.path.join(run_dir, "scene.toml")) as fh:
        return 'method = "sph"' in fh.read()


def fof_largest(run_dir, shatter, h_factor):
    snaps = sorted(glob.glob(os.path.join(run_dir, "snapshots", "snapshot_*.h5")))
    prefix = os.path.join(run_dir, "fof")
    cmd = [shatter, "fragments", snaps[-1], "--method", "friends_of_friends", "--prefix", prefix,
           "--quiet"]
    if is_sph(run_dir):
        cmd += ["--smoothing-factor", str(h_factor)]
    subprocess.run(cmd, check=True)
    with open(prefix + ".csv") as fh:
        header = fh.readline()
        total = float(header.split("total_mass_kg=")[1].split()[0])
        rows = list(csv.DictReader(fh))
    big = rows[0]
    speed = np.linalg.norm([float(big["vx_m/s"]), float(big["vy_m/s"]), float(big["vz_m/s"])])
    return float(big["mass_kg"]) / total, float(speed)


def fmt(vals, f):
    vals = [v for v in vals if v == v]
    if not vals:
        return "-"
    if len(vals) == 1:
        return f.format(vals[0])
    return (f + " ± " + f + " (" + f + "-" + f + ")").format(
        statistics.mean(vals), statistics.stdev(vals), min(vals), max(vals))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--fof", action="store_true")
    ap.add_argument("--shatter", default="build/release/shatter")
    ap.add_argument("--h-factor", type=float, default=1.2)
    args = ap.parse_args()
    head = ["ensemble", "runs"] + [f"failure {t:g} us" for t in TIMES_US]
    if args.fof:
        head += ["FoF largest m/M", "its speed (m/s)"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for d in args.dirs:
        runs = sorted(r for r in glob.glob(os.path.join(d, "seed*")) if os.path.isdir(r))
        cells = [os.path.basename(os.path.normpath(d)), str(len(runs))]
        for t in TIMES_US:
            cells.append(fmt([100.0 * failure_at(r, t) for r in runs], "{:.1f}%"))
        if args.fof:
            res = [fof_largest(r, args.shatter, args.h_factor) for r in runs]
            cells.append(fmt([m for m, _ in res], "{:.3f}"))
            cells.append(fmt([v for _, v in res], "{:.2f}"))
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
