#!/usr/bin/python3
"""First-passage radial compression and the radial tension that follows it, by distance from
the impact point, in a lab-impact run (docs/validation-lab-impact.md, Sec. 4b (a)).

Usage: lab_tension_tail.py RUN_DIR [--window 3e-6] [--shell 1.5e-3]

RUN_DIR is a `shatter run` of scenes/lab-impact.toml with flaws too strong to activate
(--set body.target.damage.weibull_k=1e20) and snapshots every microsecond
(--set output.snapshot_every=1e-6). For the interior target points (initial distance from the
target centre < 0.9 of its radius) in
shells of initial distance r from the impact point, the script prints the median peak radial
compression and the median largest radial tension within --window after that peak. The target
(the heaviest body) comes from the first snapshot and the impact point from the run's scene.toml
(shatter_plot.impact_geometry). The tension
in the tail of a short elastic pulse is as large as its compression (zero net impulse), so a
ratio near 1 is the wave's own shape; ringing would make it depend on the viscosity."""

import argparse
import os
import sys

import numpy as np

# The readers (shatter_plot) are among the user's tools.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "tools"))
import shatter_plot as sp

def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run_dir")
    ap.add_argument("--window", type=float, default=3e-6, help="s after the compression peak")
    ap.add_argument("--shell", type=float, default=1.5e-3, help="half-width of a shell (m)")
    a = ap.parse_args()

    files = sp.snapshots(a.run_dir)
    _, c0, axis = sp.read_snapshot(files[0])
    target_body, centre, radius, _, imp = sp.impact_geometry(c0, axis, sp.scene(a.run_dir))
    o0 = np.argsort(c0["id"])
    x0 = np.stack([c0["x"], c0["y"], c0["z"]], 1)[o0]
    target = (c0["body"] == target_body)[o0]
    dist = np.linalg.norm(x0 - imp, axis=1)
    radial = (x0 - imp) / np.maximum(dist, 1e-12)[:, None]
    # Interior: away from the free surface, whose reflections would mix into the tail.
    interior = np.linalg.norm(x0 - centre, axis=1) < 0.9 * radius

    times, srr = [], []
    for f in files:
        t, c, _ = sp.read_snapshot(f)
        o = np.argsort(c["id"])
        s = sp.stress_tensors(c, o)
        srr.append(np.einsum("ij,ijk,ik->i", radial, s, radial))
        times.append(t)
    srr = np.array(srr)
    dt = np.median(np.diff(times))
    steps = max(1, int(round(a.window / dt)))

    print("r (mm), peak radial compression (MPa), radial tension after it (MPa), ratio")
    for r in np.arange(10e-3, 45e-3, 5e-3):
        sel = np.where(target & interior & (np.abs(dist - r) < a.shell))[0]
        if sel.size == 0:
            continue
        peak = srr[:, sel].min(0)
        at = srr[:, sel].argmin(0)
        tail = np.array([srr[i:i + steps + 1, k].max() for k, i in zip(sel, at)])
        print(f"{r * 1e3:.0f}, {np.median(peak) / 1e6:.0f}, {np.median(tail) / 1e6:.0f}, "
              f"{np.median(-tail / peak):.2f}")


if __name__ == "__main__":
    main()
