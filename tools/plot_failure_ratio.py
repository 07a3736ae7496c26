#!/usr/bin/python3
"""Failure ratio (fraction of target points with D >= threshold) against time for one or more
runs (MPM paper Fig. 5). Usage: plot_failure_ratio.py RUN_DIR [RUN_DIR ...] [--out FILE.png]"""

import argparse
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

import shatter_plot as sp


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("run_dirs", nargs="+")
    ap.add_argument("--out", help="output image (default FIRST_RUN/plots/failure_ratio.png)")
    a = ap.parse_args()
    fig, ax = plt.subplots(figsize=(6, 4))
    for d in a.run_dirs:
        ts = sp.timeseries(d)
        ax.plot(ts["time_s"] * 1e6, 100 * ts["failure_ratio"], label=sp.label_of(d))
    # The paper's converged value at 100 us (Sec. 4.1.1).
    ax.axhline(52, color="gray", ls="--", lw=0.8, label="MPM paper, converged (52%)")
    ax.set_title("points with D >= 0.9; " + ", ".join(
        sorted({sp.model_label(sp.symmetry_axis(d)) for d in a.run_dirs})), fontsize=9)
    ax.set_xlabel("time (us)")
    ax.set_ylabel("failure ratio (%)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    out = a.out or os.path.join(a.run_dirs[0], "plots", "failure_ratio.png")
    os.makedirs(os.path.dirname(out) or ".", exist_ok=True)
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    main()
