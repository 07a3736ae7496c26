#!/usr/bin/python3
"""Failure at 100 us, largest fragment m/M and its speed against the linear viscosity c_L, mean ±
sample standard deviation over flaw seeds, from ensembles_74ffd54_1.2mm.csv
(tools/ensemble.py --summarise --csv; docs/validation-lab-impact.md, "Artificial viscosity and
Benz-Asphaug flaws as ensembles"). SPH (same material library, 5 seeds, docs/validation-sph.md)
and the experiment drawn as lines.

Usage: plot_viscosity_ensembles.py CSV OUT.png"""

import csv
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    rows = list(csv.DictReader(open(sys.argv[1])))
    cl = {"t2-nominal": 0.06}
    for r in rows:
        m = re.fullmatch(r"c2\.4-cL([\d.]+)", r["ensemble"])
        if m:
            cl[r["ensemble"]] = float(m.group(1))
    keys = sorted(cl, key=cl.get)
    fig, ax = plt.subplots(1, 3, figsize=(12, 3.6))
    what = (("failure_100", 100, "failed at 100 us (%)", 73.9, None),
            ("largest_fraction", 1, "largest fragment m/M", 0.289, 0.31),
            ("largest_speed", 1, "its speed (m/s)", 1.55, 1.35))
    for a, (k, sc, lab, sph, exp) in zip(ax, what):
        x, m, s, n = [], [], [], []
        for e in keys:
            v = np.array([float(r[k]) * sc for r in rows if r["ensemble"] == e and r[k] not in ("", "nan")])
            if len(v):
                x.append(cl[e]), m.append(v.mean()), s.append(v.std(ddof=1) if len(v) > 1 else 0), n.append(len(v))
        a.errorbar(x, m, yerr=s, fmt="o-", capsize=3, label="MPM (shatter), mean ± sd")
        for xi, mi, ni in zip(x, m, n):
            a.annotate(f"{ni}", (xi, mi), textcoords="offset points", xytext=(4, 4), fontsize=7)
        a.axhline(sph, color="C1", ls="--", label="SPH, alpha = 1 (5 seeds)")
        if exp is not None:
            a.axhline(exp, color="k", ls=":", label="experiment (core)")
        a.axvline(0.6, color="0.7", lw=0.8)
        a.set_xscale("log")
        if k != "failure_100":
            a.set_ylim(bottom=0)
        a.set_xlabel("linear viscosity c_L")
        a.set_ylabel(lab)
    ax[0].legend(fontsize=7)
    fig.suptitle("Nominal lab impact, 1.2 mm, main 74ffd54: no c_L gives a core "
                 "(the largest fragment is > 5 mm off centre in every run); numbers: runs per point", fontsize=9)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=90)


if __name__ == "__main__":
    main()
