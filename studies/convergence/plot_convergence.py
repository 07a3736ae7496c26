#!/usr/bin/python3
"""Plot the convergence study (studies/convergence, CSV from `convergence_study`).

Six log-log panels: the large-deformation manufactured solution (G = 0.05) against cell size
and against wall time, the small-deformation MMS (G = 1e-4) and the vibrating bar's
displacement against the same two, and the spherical elastic wave's radial-stress error
(tests/verification/engine/spherical_wave_test.cpp, SphericalWave.DISABLED_ConvergenceStudy with
SPHERICAL_WAVE_STUDY_CSV) against the same two, one series per transfer scheme (uGIMP) and per
shape (FLIP), with the least-squares order of each series in the legends of the cell-size panels.

Problem names in the CSV are <problem>[_symwall][_<scheme>], scheme one of apic, pic<f> (the
FLIP/PIC blend with PIC fraction f), xpic<m> (XPIC of order m), fmpm<k> (FMPM of order k), each
of xpic/fmpm optionally with _every<N> (the filter on every N-th step only, FLIP between); no
scheme suffix is FLIP. Periodic (_every) schemes are drawn dashed.

Usage: /usr/bin/python3 studies/convergence/plot_convergence.py docs/convergence.csv docs/convergence.png
"""
import argparse
import csv
import re
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

BASES = ("bar_displacement", "bar_com_velocity", "mms_small", "mms_large", "spherical_wave_srr")
LABELS = {"bar_displacement": "bar u", "mms_small": "MMS G=1e-4", "mms_large": "MMS G=0.05",
          "spherical_wave_srr": "spherical wave s_rr"}
MARKERS = {"bar_displacement": "o", "mms_small": "s", "mms_large": "^", "spherical_wave_srr": "D"}
SCHEME_COLOURS = {
    "flip": "tab:blue",
    "pic0.05": "tab:orange",
    "pic1": "tab:red",
    "xpic2": "tab:green",
    "xpic5": "tab:olive",
    "apic": "tab:purple",
    "fmpm2": "tab:cyan",
    "fmpm5": "tab:brown",
    "fmpm10": "tab:pink",
}
SHAPE_STYLES = {"ugimp": "-", "linear": ":", "bspline2": "--"}


def fitted_order(h, err):
    """Least-squares slope of log(err) against log(h)."""
    return np.polyfit(np.log(h), np.log(err), 1)[0]


def split_problem(name):
    """(base problem, symwall?, scheme) of a CSV problem name."""
    for base in BASES:
        if name.startswith(base):
            rest = name[len(base):]
            sym = rest.startswith("_symwall")
            rest = rest.removeprefix("_symwall")
            m = re.fullmatch(r"(?:_(apic|pic[0-9.]+|(?:xpic|fmpm)[0-9]+(?:_every[0-9]+)?))?", rest)
            if m is None:
                return None
            return base, sym, m.group(1) or "flip"
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("png")
    args = ap.parse_args()

    series = defaultdict(lambda: {"h": [], "err": [], "wall": []})
    with open(args.csv, newline="") as f:
        for row in csv.DictReader(f):
            key = split_problem(row["problem"])
            if key is None or key[0] == "bar_com_velocity" or key[1]:
                continue  # the centre-of-mass and mirrored-wall rows stay in the table only
            s = series[(key[0], key[2], row["shape"])]
            s["h"].append(float(row["h_m"]))
            s["err"].append(float(row["error"]))
            s["wall"].append(float(row["wall_s"]))

    fig, axes = plt.subplots(3, 2, figsize=(17, 18))
    panels = {"mms_large": (axes[0, 0], axes[0, 1]), "mms_small": (axes[1, 0], axes[1, 1]),
              "bar_displacement": (axes[1, 0], axes[1, 1]),
              "spherical_wave_srr": (axes[2, 0], axes[2, 1])}
    for (base, scheme, shape), s in sorted(series.items()):
        order = np.argsort(s["h"])
        h = np.asarray(s["h"])[order]
        err = np.asarray(s["err"])[order]
        wall = np.asarray(s["wall"])[order]
        periodic = "_every" in scheme
        style = dict(color=SCHEME_COLOURS.get(scheme.split("_every")[0], "k"), marker=MARKERS[base],
                     linestyle="--" if periodic else SHAPE_STYLES.get(shape, "-"), markersize=5,
                     alpha=0.6 if periodic else 1.0)
        label = f"{LABELS[base]}, {scheme}, {shape}"
        ax_h, ax_t = panels[base]
        ax_h.loglog(h / h.max(), err, label=f"{label}: order {fitted_order(h, err):.2f}", **style)
        ax_t.loglog(wall, err, label=label, **style)

    axes[0, 0].set_title("large-deformation MMS (G = 0.05), error vs cell size")
    axes[0, 1].set_title("large-deformation MMS (G = 0.05), error vs run time")
    axes[1, 0].set_title("small MMS (G = 1e-4, squares) and vibrating bar (circles) vs cell size")
    axes[1, 1].set_title("small MMS and vibrating bar vs run time")
    axes[2, 0].set_title("spherical elastic wave, s_rr L2 error / peak vs cell size (a/h = 4-16)")
    axes[2, 1].set_title("spherical elastic wave vs run time (CPU s, 1 thread)")
    for row, ax in enumerate(axes[:, 0]):
        ax.set_xlabel("cell size h / h_coarsest")
        # Guides over the row's range of h (the spherical wave spans a/h = 4-16 only).
        x, c = (np.array([1 / 64, 1.0]), 3e-1) if row < 2 else (np.array([1 / 4, 1.0]), 6e-1)
        ax.loglog(x, c * x, "k:", linewidth=1, label="order 1")
        ax.loglog(x, c * x**2, "k-.", linewidth=1, label="order 2")
        ax.legend(fontsize=7, loc="lower right", ncol=1)
    for ax in axes[:2, 1]:
        ax.set_xlabel("wall time per run [s] (1 thread, shared cores)")
    axes[2, 1].set_xlabel("CPU time per run [s] (1 thread)")
    for ax in axes[:2].flat:
        ax.set_ylabel("relative L2 displacement error")
    for ax in axes[2]:
        ax.set_ylabel("L2 error of s_rr / exact peak |s_rr|")
        ax.grid(True, which="both", alpha=0.3)
    fig.suptitle("shatter verification per transfer scheme (colour) and shape (line style: "
                 "uGIMP solid, linear dotted, B-spline dashed)")
    fig.tight_layout()
    fig.savefig(args.png, dpi=110)


if __name__ == "__main__":
    main()
