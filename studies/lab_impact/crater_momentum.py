#!/usr/bin/python3
"""The crater's backward momentum (issue 27): the target's momentum along the impact, split at a
speed, at given times.

Per run: the target's (the most massive body's) momentum along the projectile's initial velocity,
in kg m/s, at each time (the snapshot nearest it), split into the points moving slower and faster
than --split (30 m/s: the crater's ejecta against the rock that becomes fragments). MPM's crater
throws its ejecta backwards with several times SPH's momentum; that momentum, returned to the slow
rock, is what makes the survivor fast (docs/validation-lab-impact.md).

Usage: crater_momentum.py RUN [RUN ...] [--times 10e-6 100e-6] [--split 30]"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import shatter_plot as sp  # noqa: E402


def split_momentum(run, times, split):
    _, first, _ = sp.read_snapshot(sp.snapshots(run)[0])
    body = first["body"].astype(int)
    target = int(np.argmax(np.bincount(body, weights=first["mass"])))
    proj = body != target
    v0 = np.array([first[k][proj].mean() for k in ("vx", "vy", "vz")])
    along = v0 / np.linalg.norm(v0)
    rows = []
    for want in times:
        t, snap, _ = sp.read_snapshot(sp.snapshot_at(run, want))
        sel = snap["body"].astype(int) == target
        vel = np.stack([snap[k][sel] for k in ("vx", "vy", "vz")], axis=1)
        p = snap["mass"][sel] * (vel @ along)
        fast = np.linalg.norm(vel, axis=1) >= split
        rows.append((t, p.sum(), p[~fast].sum(), p[fast].sum(), int(fast.sum())))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--times", type=float, nargs="+", default=[10e-6, 100e-6])
    ap.add_argument("--split", type=float, default=30.0, help="speed splitting ejecta (m/s)")
    args = ap.parse_args()
    print(f"| run | t (us) | target total | below {args.split:g} m/s | at or above (points) |")
    print("|---|---|---|---|---|")
    for run in args.runs:
        for t, total, slow, fast, n in split_momentum(run, args.times, args.split):
            print(f"| {run} | {t * 1e6:.1f} | {total:.3f} | {slow:.3f} | {fast:.3f} ({n}) |")


if __name__ == "__main__":
    main()
