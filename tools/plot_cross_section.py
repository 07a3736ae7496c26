#!/usr/bin/python3
"""Damage and speed on the symmetry-plane cross-section (MPM paper Figs. 6-7).

Usage: plot_cross_section.py RUN_DIR [--times 10e-6 20e-6 ...] [--out FILE.png]
Points of the layer next to the symmetry plane (or of |z| < spacing for a full model) are drawn;
each panel names its slice. Damage from 0 to 0.9, failed points (D >= 0.9, the MPM paper's
criterion) in cyan, and the speed |v| in m/s; with a peak_pressure column also the peak pressure
in GPa; with a distension column (a porous body, issue 29) also the porosity 1 - 1/alpha, the
points of dense materials in grey. All panels share the axis ranges."""

import argparse
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import shatter_plot as sp


def porosity(c):
    """1 - 1/alpha of the porous points, NaN for the dense ones (their distension column is 0)."""
    alpha = c["distension"]
    return np.where(alpha >= 1.0, 1.0 - 1.0 / np.maximum(alpha, 1.0), np.nan)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run_dir")
    ap.add_argument("--times", type=float, nargs="*", help="snapshot times in s (default: all, at most 5)")
    ap.add_argument("--out", help="output image (default RUN_DIR/plots/cross_section.png)")
    a = ap.parse_args()

    files = sp.snapshots(a.run_dir)
    if a.times:
        files = [sp.snapshot_at(a.run_dir, t) for t in a.times]
    elif len(files) > 5:
        files = [files[i] for i in np.linspace(0, len(files) - 1, 5).round().astype(int)]
    data = [sp.read_snapshot(path) for path in files]
    peak_row = all("peak_pressure" in c for _, c, _ in data)
    porous_row = all("distension" in c for _, c, _ in data)
    rows = 2 + peak_row + porous_row
    fig, axes = plt.subplots(rows, len(files), figsize=(3.2 * len(files), 3.1 * rows),
                             squeeze=False, sharex=True, sharey=True)
    # One speed (and peak-pressure) colour range for all panels, like the shared axes.
    vmax = max([np.sqrt(c["vx"] ** 2 + c["vy"] ** 2 + c["vz"] ** 2).max(initial=0)
                for _, c, _ in data] + [1e-30])
    pmax = max([np.percentile(c["peak_pressure"], 99) / 1e9 for _, c, _ in data if peak_row]
               + [1e-30])
    # One porosity range: 0 to the largest initial porosity (compaction only lowers it).
    phimax = max([porosity(c).max(initial=0) for _, c, _ in data if porous_row] + [1e-30])
    for k, (t, c, axis) in enumerate(data):
        normal = "xyz"[axis] if axis >= 0 else "z"
        plane = [a_ for a_ in "xyz" if a_ != normal]
        h = np.cbrt(np.median(c["volume0"])) if "volume0" in c else np.ptp(c[normal]) / 50
        layer = np.abs(c[normal]) < h  # the layer of points next to the plane
        u, v = c[plane[0]][layer] * 1e3, c[plane[1]][layer] * 1e3
        damage = c["damage"][layer] if "damage" in c else np.zeros(layer.sum())
        speed = np.sqrt(c["vx"] ** 2 + c["vy"] ** 2 + c["vz"] ** 2)[layer]
        s = 4.0
        failed = damage >= 0.9
        im = axes[0][k].scatter(u[~failed], v[~failed], c=damage[~failed], s=s, cmap="inferno",
                                vmin=0, vmax=0.9)
        axes[0][k].scatter(u[failed], v[failed], c="cyan", s=s, label="D >= 0.9 (failed)")
        where = (f"slice |{normal}| < {h * 1e3:.2g} mm"
                 + (" (symmetry plane)" if axis >= 0 else ""))
        axes[0][k].set_title(f"damage, t = {t * 1e6:.3g} us\n{where}", fontsize=9)
        if k == 0:
            axes[0][k].legend(fontsize=7, loc="lower left", markerscale=3)
        im2 = axes[1][k].scatter(u, v, c=speed, s=s, cmap="viridis", vmin=0, vmax=vmax)
        axes[1][k].set_title("|v| (m/s)", fontsize=9)
        fig.colorbar(im, ax=axes[0][k], shrink=0.8)
        fig.colorbar(im2, ax=axes[1][k], shrink=0.8)
        if peak_row:
            peak = c["peak_pressure"][layer] / 1e9
            im3 = axes[2][k].scatter(u, v, c=peak, s=s, cmap="magma", vmin=0, vmax=pmax)
            axes[2][k].set_title("peak pressure (GPa)", fontsize=9)
            fig.colorbar(im3, ax=axes[2][k], shrink=0.8)
        if porous_row:
            ax = axes[rows - 1][k]
            phi = porosity(c)[layer]
            dense = np.isnan(phi)
            ax.scatter(u[dense], v[dense], c="0.75", s=s, label="dense material")
            im4 = ax.scatter(u[~dense], v[~dense], c=phi[~dense], s=s, cmap="cividis_r", vmin=0,
                             vmax=phimax)
            ax.set_title("porosity 1 - 1/alpha", fontsize=9)
            fig.colorbar(im4, ax=ax, shrink=0.8)
        for r in range(rows):
            axes[r][k].set_aspect("equal")
            axes[r][k].set_xlabel(f"{plane[0]} (mm)")
            axes[r][k].set_ylabel(f"{plane[1]} (mm)")
    fig.tight_layout()
    out = a.out or os.path.join(a.run_dir, "plots", "cross_section.png")
    os.makedirs(os.path.dirname(out) or ".", exist_ok=True)
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    main()
