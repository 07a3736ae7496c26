#!/usr/bin/python3
"""Fragment statistics against the experiment (MPM paper Figs. 9 and 10):
cumulative number of fragments with normalised mass >= m/M, with n(m) ~ m^(-3/5) for fine
fragments (Nakamura & Fujiwara 1991) and the experiment's largest fragment (0.31); and fragment
speed against m/M with the experiment's upper envelope V = 6.4 (m/M)^-0.155 m/s and its core
(m/M = 0.31, 1.35 m/s).
Fragments are those of the whole (mirrored) body. With composition columns (mass_body_NAME_kg),
m is the fragment's mass from the target (the heaviest body) and fragments made mostly of other
bodies (projectile material) are drawn open, not counted as target fragments.
Usage: plot_fragments.py RUN_DIR [RUN_DIR ...] [--out FILE.png]   (reads RUN_DIR/fragments.csv)"""

import argparse
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import shatter_plot as sp


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run_dirs", nargs="+")
    ap.add_argument("--target-mass", type=float,
                    help="M in kg (default: total mass in fragments.csv minus nothing)")
    ap.add_argument("--out", help="output image (default FIRST_RUN/plots/fragments.png)")
    a = ap.parse_args()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    for d in a.run_dirs:
        path = os.path.join(d, "fragments.csv")
        mass, speed, total = sp.fragments(path)
        cols, _ = sp.fragment_table(path)
        bodies = [k for k in cols if k.startswith("mass_body_")]
        target = np.ones(mass.size, bool)
        if bodies:
            main = max(bodies, key=lambda k: cols[k].sum())  # the target: most mass
            target = cols[main] >= 0.5 * mass
            mass = cols[main]
        M = a.target_mass or total
        m = np.sort(mass[target] / M)[::-1]
        line, = ax1.loglog(m, np.arange(1, m.size + 1), "D", ms=4, label=sp.label_of(d))
        ax2.loglog(mass[target] / M, speed[target], "D", ms=4, color=line.get_color(),
                   label=sp.label_of(d))
        if (~target).any():
            ax2.loglog(cols["mass_kg"][~target] / M, speed[~target], "D", ms=4, mfc="none",
                       color=line.get_color(), label=f"{sp.label_of(d)}: mostly projectile")
    mm = np.logspace(-5, -3.3, 20)
    ax1.loglog(mm, 3e-3 * mm ** (-0.6), "--", color="gray", label="n ~ m^(-3/5) (N&F 1991)")
    ax1.axvline(0.31, color="k", lw=0.8, ls=":", label="experiment, largest (0.31)")
    fig.suptitle("fragments of the whole (mirrored) body", fontsize=9)
    ax1.set_xlabel("m / M")
    ax1.set_ylabel("cumulative number N(>= m)")
    ax1.legend(fontsize=8)
    mv = np.logspace(-6, 0, 50)
    ax2.loglog(mv, 6.4 * mv ** -0.155, "--", color="gray", label="V = 6.4 (m/M)^-0.155")
    ax2.loglog([0.31], [1.35], "ko", label="experiment, core")
    ax2.set_xlabel("m / M")
    ax2.set_ylabel("speed (m/s)")
    ax2.legend(fontsize=8)
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    out = a.out or os.path.join(a.run_dirs[0], "plots", "fragments.png")
    os.makedirs(os.path.dirname(out) or ".", exist_ok=True)
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    main()
