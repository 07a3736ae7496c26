#!/usr/bin/python3
"""First-passage radial compression and the radial tension that follows it, by distance from
the impact point, in a lab-impact run (docs/validation-lab-impact.md, Sec. 4b (a)).

Usage: lab_tension_tail.py RUN_DIR [--impact-point X Y Z] [--window 3e-6] [--shell 1.5e-3]

RUN_DIR is a `shatter run` of scenes/lab-impact.toml with flaws too strong to activate
(--set body.target.damage.weibull_k=1e20) and snapshots every microsecond
(--set output.snapshot_every=1e-6). For the interior target points (initial radius < 27 mm) in
shells of initial distance r from the impact point, the script prints the median peak radial
compression and the median largest radial tension within --window after that peak. The tension
in the tail of a short elastic pulse is as large as its compression (zero net impulse), so a
ratio near 1 is the wave's own shape; ringing would make it depend on the viscosity."""

import argparse

import numpy as np

import shatter_plot as sp

PAIRS = [((0, 0), "sxx"), ((1, 1), "syy"), ((2, 2), "szz"), ((0, 1), "sxy"), ((1, 2), "syz"),
         ((0, 2), "sxz")]


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run_dir")
    # scenes/lab-impact.toml: offset half the 30 mm radius, so x = -sqrt(30^2 - 15^2) mm.
    ap.add_argument("--impact-point", type=float, nargs=3, default=[-25.98e-3, 15.0e-3, 0.0])
    ap.add_argument("--window", type=float, default=3e-6, help="s after the compression peak")
    ap.add_argument("--shell", type=float, default=1.5e-3, help="half-width of a shell (m)")
    ap.add_argument("--target-body", type=int, default=1, help="body index of the target")
    a = ap.parse_args()

    files = sp.snapshots(a.run_dir)
    _, c0, _ = sp.read_snapshot(files[0])
    o0 = np.argsort(c0["id"])
    x0 = np.stack([c0["x"], c0["y"], c0["z"]], 1)[o0]
    target = (c0["body"] == a.target_body)[o0]
    imp = np.array(a.impact_point)
    dist = np.linalg.norm(x0 - imp, axis=1)
    radial = (x0 - imp) / np.maximum(dist, 1e-12)[:, None]
    interior = np.linalg.norm(x0, axis=1) < 27e-3

    times, srr = [], []
    for f in files:
        t, c, _ = sp.read_snapshot(f)
        o = np.argsort(c["id"])
        s = np.zeros((o.size, 3, 3))
        for (i, j), k in PAIRS:
            s[:, i, j] = c[k][o]
            s[:, j, i] = s[:, i, j]
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
