#!/usr/bin/python3
"""Failed share of the target's points by where they started: distance from the impact point
(rows, 10 mm bins) against distance from the target centre (columns: inner/middle/outer third of
the radius), at a run's snapshot nearest a given time. Tells a core from a far-side crescent
(issue 27): SPH beside MPM on scenes/lab-impact-ba94.toml.

Usage: failure_map.py RUN [RUN ...] [--time 100e-6]"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import plot_lab_convergence as lab  # noqa: E402


def failure_map(run, t_want):
    scene = lab.scene_of(run)
    files = lab.sp.snapshots(run)
    _, first, axis = lab.sp.read_snapshot(files[0])
    t_got, snap, _ = lab.sp.read_snapshot(lab.sp.snapshot_at(run, t_want))
    tb = lab.target_body(first)
    centre = np.array(scene["body"]["target"]["centre"], dtype=float)
    radius = float(scene["body"]["target"]["radius"])
    threshold = scene.get("fracture", {}).get("threshold", 0.9)
    in0 = first["body"].astype(int) == tb
    pos0 = np.stack([first["x"], first["y"], first["z"]], 1)
    proj = pos0[~in0].mean(axis=0)
    if axis >= 0:
        proj[axis] = centre[axis]
    impact = centre + radius * (proj - centre) / np.linalg.norm(proj - centre)
    ids0 = first["id"][in0].astype(np.int64)
    r0 = dict(zip(ids0, np.linalg.norm(pos0[in0] - centre, axis=1)))
    d0 = dict(zip(ids0, np.linalg.norm(pos0[in0] - impact, axis=1)))
    sel = snap["body"].astype(int) == tb
    ids = snap["id"][sel].astype(np.int64)
    r = np.array([r0[i] for i in ids]) / radius
    d = np.array([d0[i] for i in ids])
    failed = snap["damage"][sel] >= threshold
    rows = []
    for lo in np.arange(0.0, 2.0 * radius, 0.01):
        row = []
        for a, b in ((0.0, 1 / 3), (1 / 3, 2 / 3), (2 / 3, 1.01)):
            m = (d >= lo) & (d < lo + 0.01) & (r >= a) & (r < b)
            row.append(f"{failed[m].mean():.0%} ({m.sum()})" if m.any() else "-")
        rows.append((lo, row))
    return t_got, rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--time", type=float, default=100e-6)
    args = ap.parse_args()
    for run in args.runs:
        t, rows = failure_map(run, args.time)
        print(f"\n{run} at {t * 1e6:.1f} us: failed share (points) by distance from the "
              "impact point")
        print("| from impact (mm) | r0 < R/3 | R/3-2R/3 | 2R/3-R |\n|---|---|---|---|")
        for lo, row in rows:
            print(f"| {lo * 1e3:.0f}-{lo * 1e3 + 10:.0f} | " + " | ".join(row) + " |")


if __name__ == "__main__":
    sys.exit(main())
