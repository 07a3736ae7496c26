#!/usr/bin/python3
"""The exponent mu of the ejecta's mass against launch speed: our runs, iSALE's tracers, HH2011.

Housen & Holsapple 2011 (Icarus 211; "HH2011") write the ejecta faster than v, in the power-law
range between the near field of the impactor and the crater's rim, as

    M(>v) / m = A (v / U)^(-3 mu)

with mu the velocity exponent of the point-source coupling parameter, a constant of the material
class. This script fits mu to M(>v) by least squares in log-log (tools/beta.py's fit_mu, over
LO <= v/U <= HI, default 0.005 to 0.05) for

  - shatter runs with a [beta] table: NAME=RUN_DIR (RUN/ejecta_launch.csv: launch speed = the
    speed at the first sample above the count plane);
  - the iSALE-2D tracers of Raducan et al. 2019 (Icarus 329) with --isale PATH_TO_A_COPY of the
    repository sr516/iSALE_ejecta_data (CC BY-NC-SA 4.0; not shipped, derived numbers only):
    launch speed = sqrt(v_x^2 + v_y^2) where the tracer crossed 0.84 m, m_imp and U as
    studies/dart/raducan2019_beta.py; the points named POINT=Series/YdXeN/FILE (without .csv).

It also prints the local exponent over each decade-half of v/U (where the power law holds, the
local mu is flat). HH2011's class values (their Table 3, as tabulated by a third-party code that
cites it, not checked against the paper): sand mu 0.41, sand/fly ash 0.40, perlite/sand 0.35.

Usage: ejecta_mu.py [NAME=RUN ...] [--isale PATH POINT=Series/YdXeN/FILE ...] [--fit LO HI]
                    [--csv OUT.csv] [--plot OUT.png]
"""

import argparse
import csv
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
sys.path.insert(0, HERE)
import beta as beta_tool  # noqa: E402  (tools/beta.py)
import plot_common as pc  # noqa: E402  (tools/plot_common.py: Agg, dpi, common labels)
import raducan2019_beta as r19  # noqa: E402

EDGES = (0.2, 0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001)


def run_launches(run):
    """(m_imp, U, rows with speed_m_per_s and mass_kg) of a shatter run."""
    return beta_tool.read_launches(run)


def isale_launches(path):
    with open(path) as f:
        rows = [{"speed_m_per_s": math.hypot(float(r["v_x"]), float(r["v_y"])),
                 "mass_kg": float(r["m"])} for r in csv.DictReader(f)]
    return r19.M_IMP, r19.U_IMP, rows


def cumulative(rows, m_imp, speed, q):
    return sum(float(r["mass_kg"]) for r in rows if float(r["speed_m_per_s"]) >= q * speed) / m_imp


def local_mu(rows, m_imp, speed):
    out = []
    for hi, lo in zip(EDGES, EDGES[1:]):
        a, b = cumulative(rows, m_imp, speed, hi), cumulative(rows, m_imp, speed, lo)
        out.append(math.log(b / a) / (-3.0 * math.log(lo / hi)) if a > 0 and b > 0 else float("nan"))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("items", nargs="*", help="NAME=RUN_DIR, or POINT=Series/YdXeN/FILE with --isale")
    ap.add_argument("--isale", help="local copy of sr516/iSALE_ejecta_data")
    ap.add_argument("--fit", nargs=2, type=float, default=(0.005, 0.05), metavar=("LO", "HI"))
    ap.add_argument("--csv")
    ap.add_argument("--plot")
    a = ap.parse_args()
    table, curves = [], []
    for item in a.items:
        name, _, where = item.partition("=")
        if os.path.isdir(where):
            source, (m_imp, speed, rows) = "shatter", run_launches(where)
        elif a.isale:
            source, (m_imp, speed, rows) = "iSALE", isale_launches(
                os.path.join(a.isale, where + ".csv"))
        else:
            sys.exit(f"{item}: not a run directory, and no --isale copy given")
        mu, pre, n = beta_tool.fit_mu(rows, m_imp, speed, a.fit[0], a.fit[1], 0.0)
        table.append({"name": name, "source": source, "mu_fit": mu, "A_fit": pre, "points": n,
                      "M_over_m_total": cumulative(rows, m_imp, speed, 0.0),
                      **{f"mu_{hi:g}_{lo:g}": v for (hi, lo), v in
                         zip(zip(EDGES, EDGES[1:]), local_mu(rows, m_imp, speed))}})
        curves.append((name, source, m_imp, speed, rows))
    keys = list(table[0].keys())
    print(f"fit over {a.fit[0]:g} <= v/U <= {a.fit[1]:g}")
    print("  ".join(keys))
    for r in table:
        print("  ".join(f"{r[k]:.4g}" if isinstance(r[k], float) else str(r[k]) for k in keys))
    if a.csv:
        with open(a.csv, "w", newline="") as f:
            f.write(f"# mu fitted to M(>v)/m = A (v/U)^(-3 mu) over {a.fit[0]:g} <= v/U <= "
                    f"{a.fit[1]:g} (studies/dart/ejecta_mu.py); iSALE rows derived from"
                    " sr516/iSALE_ejecta_data (CC BY-NC-SA 4.0), derived numbers only\n")
            w = csv.DictWriter(f, fieldnames=keys)
            w.writeheader()
            for r in table:
                w.writerow({k: (f"{v:.5g}" if isinstance(v, float) else v) for k, v in r.items()})
    if a.plot:
        fig, ax = pc.subplots(figsize=(6.5, 4.5))
        qs = [10 ** (-4 + 0.05 * i) for i in range(81)]
        for name, source, m_imp, speed, rows in curves:
            ys = [cumulative(rows, m_imp, speed, q) for q in qs]
            ax.loglog(qs, ys, "--" if source == "iSALE" else "-", label=f"{name} ({source})")
        for mu, ls in ((0.41, ":"), (0.35, "-.")):
            x0, y0 = a.fit[1], 1.0
            ax.loglog([a.fit[0], a.fit[1]], [y0 * (a.fit[0] / x0) ** (-3 * mu), y0], "k" + ls,
                      lw=1, label=f"slope of mu {mu} (HH2011 class)")
        ax.axvspan(a.fit[0], a.fit[1], color="gray", alpha=0.1)
        pc.label(ax, "v_over_U", "M_over_m")
        pc.legend(ax, fontsize=7)
        pc.save(fig, a.plot)

if __name__ == "__main__":
    main()
