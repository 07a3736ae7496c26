#!/usr/bin/python3
"""Plot the convergence study (tools/convergence, CSV from `convergence_study`).

Two log-log panels: error against wall time (what accuracy a given run time buys) and error
against cell size h, with the least-squares order of each series in the legend.

Usage: /usr/bin/python3 tools/plot_convergence.py docs/convergence.csv docs/convergence.png
"""
import argparse
import csv
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# The series plotted, with their labels; the centre-of-mass rows stay in the table only, so the
# figure has one error measure per problem.
PROBLEMS = {
    "bar_displacement": "bar u",
    "mms_small": "MMS G=1e-4",
    "mms_large": "MMS G=0.05",
    "bar_displacement_symwall": "bar u, sym. wall",
    "mms_small_symwall": "MMS G=1e-4, sym. wall",
    "mms_large_symwall": "MMS G=0.05, sym. wall",
}
COLOURS = {"linear": "tab:red", "ugimp": "tab:blue", "bspline2": "tab:green"}
MARKERS = {"bar_displacement": "o", "mms_small": "s", "mms_large": "^"}


def fitted_order(h, err):
    """Least-squares slope of log(err) against log(h)."""
    return np.polyfit(np.log(h), np.log(err), 1)[0]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("png")
    args = ap.parse_args()

    series = defaultdict(lambda: {"h": [], "err": [], "wall": []})
    with open(args.csv, newline="") as f:
        for row in csv.DictReader(f):
            if row["problem"] not in PROBLEMS:
                continue
            s = series[(row["problem"], row["shape"])]
            s["h"].append(float(row["h_m"]))
            s["err"].append(float(row["error"]))
            s["wall"].append(float(row["wall_s"]))

    fig, (ax_t, ax_h) = plt.subplots(1, 2, figsize=(17, 6.5))
    for (problem, shape), s in sorted(series.items(), key=lambda kv: list(PROBLEMS).index(kv[0][0])):
        order = np.argsort(s["h"])
        h = np.asarray(s["h"])[order]
        err = np.asarray(s["err"])[order]
        wall = np.asarray(s["wall"])[order]
        base = problem.removesuffix("_symwall")
        style = dict(
            color=COLOURS.get(shape, "k"),
            marker=MARKERS.get(base, "x"),
            linestyle="--" if problem.endswith("_symwall") else "-",
            markersize=5,
        )
        label = f"{PROBLEMS[problem]}, {shape}"
        ax_t.loglog(wall, err, label=label, **style)
        ax_h.loglog(h / h.max(), err, label=f"{label}: order {fitted_order(h, err):.2f}", **style)

    ax_t.set_xlabel("wall time per run [s] (1 thread)")
    ax_t.set_ylabel("relative L2 displacement error")
    ax_t.set_title("error vs run time")
    ax_h.set_xlabel("cell size h / h_coarsest")
    ax_h.set_title("error vs cell size (fitted order over all points)")
    for ax in (ax_t, ax_h):
        ax.grid(True, which="both", alpha=0.3)
    # Guide slopes for orders 1 and 2.
    x = np.array([1 / 64, 1.0])
    ax_h.loglog(x, 3e-1 * x, "k:", linewidth=1, label="order 1")
    ax_h.loglog(x, 3e-1 * x**2, "k-.", linewidth=1, label="order 2")
    # One legend for both panels (same styles), outside the axes so it hides no data.
    ax_h.legend(fontsize=8, loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.suptitle("shatter verification: vibrating bar (problem 1) and manufactured solution (problem 2)")
    fig.tight_layout()
    fig.savefig(args.png, dpi=120)


if __name__ == "__main__":
    main()
