#!/usr/bin/python3
"""Peak tension the impact wave puts into an (effectively) undamaged lab-impact target.

Usage: plot_lab_peak_tension.py RUN_DIR [--out FILE.png] [--strength 31.4e6 40.2e6]

RUN_DIR is a `shatter run` of scenes/lab-impact.toml with flaws too strong to activate (e.g.
--set body.target.damage.weibull_k=1e20) and dense snapshots (--set output.snapshot_every=1e-6).
For each target point, the largest principal stress and the most compressive radial stress
(along the line from the impact point) over all snapshots are plotted against the initial
distance from the impact point. The printout gives the fraction of target points whose peak
tension exceeds each --strength (the MPM paper's Table 3 mean smallest and largest activation
stresses of the nominal flaws, 31.4 and 40.2 MPa). With the Grady–Kipp flaws of Sec. 3.3 such
points fail (docs/validation-lab-impact.md, Sec. 4)."""

import argparse
import sys
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

# The readers (shatter_plot) are among the user's tools.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "tools"))
import shatter_plot as sp


def principal_max(c, sel):
    s = sp.stress_tensors(c, sel)
    return s, np.linalg.eigvalsh(s)[:, -1]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run_dir")
    ap.add_argument("--out", help="output image (default RUN_DIR/plots/peak_tension.png)")
    ap.add_argument("--strength", type=float, nargs="*", default=[31.4e6, 40.2e6])
    a = ap.parse_args()

    files = sp.snapshots(a.run_dir)
    _, first, axis = sp.read_snapshot(files[0])
    body = first["body"].astype(int)
    target, _, radius, _, impact = sp.impact_geometry(first, axis)
    pos0 = np.stack([first["x"], first["y"], first["z"]], 1)

    ids = first["id"][body == target].astype(np.int64)
    index = {i: k for k, i in enumerate(ids)}
    dist = np.linalg.norm(pos0[body == target] - impact, axis=1)
    peak_t = np.full(len(ids), -np.inf)
    peak_c = np.zeros(len(ids))
    time_of = np.full(len(ids), np.inf)
    for path in files[1:]:
        t, c, _ = sp.read_snapshot(path)
        sel = c["body"].astype(int) == target
        k = np.array([index[i] for i in c["id"][sel].astype(np.int64)])
        s, smax = principal_max(c, sel)
        x = np.stack([c["x"][sel], c["y"][sel], c["z"][sel]], 1) - impact
        n = x / np.linalg.norm(x, axis=1)[:, None]
        srr = np.einsum("ni,nij,nj->n", n, s, n)
        first_time = (smax > a.strength[-1]) & ~np.isfinite(time_of[k])
        time_of[k[first_time]] = t
        peak_t[k] = np.maximum(peak_t[k], smax)
        peak_c[k] = np.minimum(peak_c[k], srr)
    for s in a.strength:
        print(f"peak tension > {s / 1e6:.1f} MPa: {np.mean(peak_t > s):.3f} of target points")
    for t_us in (5, 10, 15, 20, 30):
        print(f"  > {a.strength[-1] / 1e6:.1f} MPa by {t_us} us: {np.mean(time_of <= t_us * 1e-6 + 1e-9):.3f}")

    edges = np.linspace(0.0, 2.0 * radius, 21)
    mid = 0.5 * (edges[1:] + edges[:-1]) * 1e3
    b = np.clip(np.digitize(dist, edges) - 1, 0, len(edges) - 2)

    def stat(v, q):
        return np.array([np.percentile(v[b == i], q) if np.any(b == i) else np.nan
                         for i in range(len(mid))])

    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(mid, stat(peak_t, 50) / 1e6, "o-", ms=3, color="C3", label="peak tension (largest principal), median")
    ax.plot(mid, stat(peak_t, 90) / 1e6, ":", color="C3", label="peak tension, 90th percentile")
    ax.plot(mid, -stat(peak_c, 50) / 1e6, "s-", ms=3, color="C0", label="peak radial compression, median")
    for s, ls in zip(a.strength, ("--", "-.")):
        ax.axhline(s / 1e6, color="gray", ls=ls, lw=0.8, label=f"{s / 1e6:.1f} MPa")
    ax.set_yscale("log")
    ax.set_xlabel("initial distance from the impact point (mm)")
    ax.set_ylabel("stress (MPa)")
    ax.set_title(f"undamaged target, {len(files) - 1} snapshots to "
                 f"{sp.read_snapshot_time(files[-1]) * 1e6:.0f} us", fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    out = a.out or os.path.join(a.run_dir, "plots", "peak_tension.png")
    os.makedirs(os.path.dirname(out) or ".", exist_ok=True)
    fig.savefig(out, dpi=100)
    print(out)


if __name__ == "__main__":
    main()
