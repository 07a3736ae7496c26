#!/usr/bin/python3
"""Relative total-energy error against time (the paper reports fluctuations below 0.6 %), and the
kinetic, internal and outflow energies (energy carried out of the domain by points that left it).
Energies are those of the model run: a half model's are half the whole body's (the title says
which). Usage: plot_energy.py RUN_DIR [RUN_DIR ...] [--out FILE.png]"""

import argparse
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

import shatter_plot as sp


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("run_dirs", nargs="+")
    ap.add_argument("--out", help="output image (default FIRST_RUN/plots/energy_error.png)")
    a = ap.parse_args()
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(6, 6), sharex=True)
    for d in a.run_dirs:
        ts = sp.timeseries(d)
        t = ts["time_s"] * 1e6
        ax.plot(t, 100 * ts["energy_error"], label=sp.label_of(d))
        ax2.plot(t, ts["kinetic_J"], label=f"kinetic ({sp.label_of(d)})")
        ax2.plot(t, ts["internal_J"], ls="--", label=f"internal ({sp.label_of(d)})")
        ax2.plot(t, ts["outflow_J"], ls=":", label=f"outflow ({sp.label_of(d)})")
    for s in (-0.6, 0.6):
        ax.axhline(s, color="gray", ls=":", lw=0.8)
    ax.set_ylabel("energy error (%)")
    ax.set_title(", ".join(sorted({sp.model_label(sp.symmetry_axis(d)) for d in a.run_dirs})),
                 fontsize=9)
    ax.legend(fontsize=8)
    ax2.set_xlabel("time (us)")
    ax2.set_ylabel("energy (J)")
    ax2.legend(fontsize=7)
    for x in (ax, ax2):
        x.grid(alpha=0.3)
    fig.tight_layout()
    out = a.out or os.path.join(a.run_dirs[0], "plots", "energy_error.png")
    os.makedirs(os.path.dirname(out) or ".", exist_ok=True)
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    main()
