#!/usr/bin/python3
"""Laboratory impact, SPH beside MPM: damage on the symmetry-plane cross-section (MPM paper
Figs. 6-7, BA95 Fig. 3) at the same times, one row per run (issue 10: cross-sections at 10, 20,
40 and 100 us).

The layer of points next to the symmetry plane (|z| < one spacing, tools/plot_cross_section.py's
slice) of each run's snapshot nearest each time: damage from 0 to 0.9, failed points
(D >= 0.9) in cyan. All panels share the axes.

Usage:
  sph_lab_cross_sections.py RUN [RUN ...] --label L [L ...] [--times 10e-6 20e-6 40e-6 100e-6]
                            --out FILE.png
"""

import argparse
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "tools"))
import shatter_plot as sp  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--label", nargs="+", required=True)
    ap.add_argument("--times", type=float, nargs="+", default=[10e-6, 20e-6, 40e-6, 100e-6])
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    if len(a.label) != len(a.runs):
        raise SystemExit("--label needs one label per run")
    fig, axes = plt.subplots(len(a.runs), len(a.times),
                             figsize=(2.6 * len(a.times) + 0.6, 2.6 * len(a.runs)),
                             squeeze=False, sharex=True, sharey=True)
    im = None
    for i, (run, lab) in enumerate(zip(a.runs, a.label)):
        for k, t_want in enumerate(a.times):
            t, c, axis = sp.read_snapshot(sp.snapshot_at(run, t_want))
            normal = "xyz"[axis] if axis >= 0 else "z"
            plane = [q for q in "xyz" if q != normal]
            h = np.cbrt(np.median(c["volume0"])) if "volume0" in c else np.ptp(c[normal]) / 50
            layer = np.abs(c[normal]) < h
            u, v = c[plane[0]][layer] * 1e3, c[plane[1]][layer] * 1e3
            d = c["damage"][layer] if "damage" in c else np.zeros(layer.sum())
            failed = d >= 0.9
            ax = axes[i][k]
            im = ax.scatter(u[~failed], v[~failed], c=d[~failed], s=1.5, cmap="inferno", vmin=0,
                            vmax=0.9, rasterized=True)
            ax.scatter(u[failed], v[failed], c="cyan", s=1.5, rasterized=True)
            ax.set_title(f"{lab}, {t * 1e6:.0f} us: {100 * failed.mean():.0f} % of slice failed",
                         fontsize=7)
            ax.set_aspect("equal")
            ax.set_xlim(-45, 45)
            ax.set_ylim(-45, 45)
            if i == len(a.runs) - 1:
                ax.set_xlabel(f"{plane[0]} (mm)", fontsize=8)
            if k == 0:
                ax.set_ylabel(f"{plane[1]} (mm)", fontsize=8)
            ax.tick_params(labelsize=7)
    fig.colorbar(im, ax=axes, shrink=0.6, label="damage (cyan: D >= 0.9)")
    fig.savefig(a.out, dpi=75)
    print("wrote", a.out)


if __name__ == "__main__":
    main()
