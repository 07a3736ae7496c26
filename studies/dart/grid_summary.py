#!/usr/bin/python3
"""Every point of the Raducan et al. 2019 grid compared so far: ours against iSALE's beta, trends.

Reads the reference (docs/figures/dart/raducan2019_beta.csv, iSALE-2D beta derived by
studies/dart/raducan2019_beta.py from sr516/iSALE_ejecta_data; derived numbers only) and a table
of our results (OURS.csv, one row per run: point, cohesion_Pa, porosity_pct, friction,
beta_launch, t_end_s, target_depth_m, cppr, session, target_radius_m (9 m where absent); written
by hand from the runs' records in docs/validation-dart.md, since the older runs are not kept) and
prints, as markdown:

  - per point: iSALE's beta, ours, the difference (ours / iSALE - 1) in %, target depth, time
    reached, and whether it is within 20%;
  - how many points are within 20% (the last CPPR 3 row of each point: older rows, e.g. a 7 m
    target before a 12 m one, or 0.3 s before a longer run, come first; a CPPR 5 row is a
    resolution check), and the same count over each point's finest resolution (its last row at
    the largest CPPR run);
  - the trends as ratios of beta - 1 between the ends of each series (friction f 0.2 to 1.2,
    porosity 10% to 40%, cohesion 1 to 100 kPa), ours against iSALE's: a ratio of 1 between the
    two codes means the trend is reproduced at its strength.

With --scatter S (session 23): S is the sample standard deviation of one run's beta_launch as a
fraction of its beta - 1, measured by an ensemble of perturbed runs of one point
(studies/dart/scatter_ensemble.py; the 10 kPa point, 9 m target, at 0.3 s); each row then also
gets +-2 S (beta - 1) in % of iSALE's beta and whether its in-or-out verdict holds across that
band ("robust") or not ("within 2 sd of the line"). Applying one point's relative scatter to the
others is an assumption, stated with the table. The plot then draws +-2 S (beta - 1) error bars.

With --plot FILE.png: beta against friction (with iSALE's 1, 10 and 100 kPa series), against
porosity and against cohesion, iSALE's points and ours (tools/plot_common.py conventions).

Usage: grid_summary.py REFERENCE.csv OURS.csv [--plot FILE.png] [--tolerance 0.2]
"""

import argparse
import csv
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import plot_common as pc  # noqa: E402  (tools/plot_common.py: Agg, dpi, common labels)

# The ends of each series (cohesion Pa, porosity %, friction): (from, to), the rest held fixed.
TRENDS = (
    ("friction f 0.2 to 1.2 (10 kPa, 20%)", (1e4, 20.0, 0.2), (1e4, 20.0, 1.2)),
    ("porosity 10% to 40% (10 kPa, f 0.6)", (1e4, 10.0, 0.6), (1e4, 40.0, 0.6)),
    ("cohesion 1 to 100 kPa (20%, f 0.6)", (1e3, 20.0, 0.6), (1e5, 20.0, 0.6)),
)


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def key(row):
    return (float(row["cohesion_Pa"]), float(row["porosity_pct"]), float(row["friction"]))


def reference(path):
    """iSALE's beta by (cohesion, porosity, friction); the nominal f 0.6 from the Porosity series
    and the suspect 100 kPa, 50% point left out."""
    out = {}
    for r in read_csv(path):
        k = key(r)
        if r.get("note"):
            continue
        if r["series"] == "Porosity" or k[2] != 0.6:
            out[k] = float(r["beta"])
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("reference")
    ap.add_argument("ours")
    ap.add_argument("--plot")
    ap.add_argument("--tolerance", type=float, default=0.2)
    ap.add_argument("--scatter", type=float, default=0.0,
                    help="one run's sd of beta_launch as a fraction of beta - 1")
    a = ap.parse_args()
    ref = reference(a.reference)
    ours = read_csv(a.ours)
    print("| point | Ydam0 | porosity | f | iSALE beta | ours (beta_launch) | difference | "
          "target radius x depth | time reached | CPPR | session |"
          + (" +-2 sd | verdict across +-2 sd |" if a.scatter else ""))
    print("|---|---|---|---|---|---|---|---|---|---|---|" + ("---|---|" if a.scatter else ""))
    best = {}  # the last CPPR 3 row of each point (the table lists older runs first)
    for r in ours:
        k = key(r)
        b_ref, b = ref[k], float(r["beta_launch"])
        diff = b / b_ref - 1.0
        ok = abs(diff) <= a.tolerance
        if float(r["cppr"]) == 3:
            best[k] = b
        print(f"| {r['point']} | {k[0] / 1e3:g} kPa | {k[1]:g}% | {k[2]:g} | {b_ref:.3f} | {b:.3f} "
              f"| {100 * diff:+.1f}%{'' if ok else ' (outside)'} "
              f"| {float(r.get('target_radius_m') or 9):g} x {float(r['target_depth_m']):g} m "
              f"| {float(r['t_end_s']):g} s | {float(r['cppr']):g} | {r['session']} |"
              + (band(b, b_ref, a) if a.scatter else ""))
    within = sum(abs(b / ref[k] - 1.0) <= a.tolerance for k, b in best.items())
    print(f"\nwithin {100 * a.tolerance:g}%: {within} of {len(best)} points (CPPR 3, the last run"
          " of each point)")
    finest = {}  # each point's last row at its largest CPPR
    for r in ours:
        k = key(r)
        if k not in finest or float(r["cppr"]) >= float(finest[k]["cppr"]):
            finest[k] = r
    fine_in = sum(abs(float(r["beta_launch"]) / ref[k] - 1.0) <= a.tolerance
                  for k, r in finest.items())
    above3 = ", ".join(f"{r['point']} CPPR {float(r['cppr']):g} at {float(r['t_end_s']):g} s"
                       for r in finest.values() if float(r["cppr"]) != 3)
    print(f"within {100 * a.tolerance:g}%: {fine_in} of {len(finest)} points (each point's finest"
          f" resolution, its last run{': ' + above3 if above3 else ''})")
    print("\n| trend | iSALE: (beta - 1) ratio | ours | ours / iSALE |")
    print("|---|---|---|---|")
    for name, k0, k1 in TRENDS:
        if k0 in best and k1 in best:
            r_ref = (ref[k0] - 1.0) / (ref[k1] - 1.0)
            r_ours = (best[k0] - 1.0) / (best[k1] - 1.0)
            print(f"| {name} | {ref[k0] - 1:.3f} / {ref[k1] - 1:.3f} = {r_ref:.2f} "
                  f"| {best[k0] - 1:.3f} / {best[k1] - 1:.3f} = {r_ours:.2f} | {r_ours / r_ref:.2f} |")
        else:
            print(f"| {name} | {'not run' if k0 not in best else ''}"
                  f"{'not run' if k1 not in best else ''} | | |")
    if a.plot:
        plot(ref, ours, a.plot, a.scatter)


def band(b, b_ref, a):
    """' +-X% | robust |': the +-2 sd band of one run in % of iSALE's beta and whether the
    in-or-out verdict at the tolerance holds across it."""
    half = 2 * a.scatter * (b - 1.0) / b_ref
    lo, hi = b / b_ref - 1.0 - half, b / b_ref - 1.0 + half
    inside = [abs(x) <= a.tolerance for x in (lo, hi, b / b_ref - 1.0)]
    robust = all(inside) or not any(inside)
    return f" +-{100 * half:.1f}% | {'robust' if robust else 'within 2 sd of the line'} |"


def plot(ref, ours, path, scatter=0.0):
    last, finer = {}, {}  # the last CPPR 3 run of each point, as counted in main(); the last finer
    for r in ours:
        if float(r["cppr"]) == 3:
            last[key(r)] = r
        else:
            finer[key(r)] = r
    ours, finer = list(last.values()), list(finer.values())
    fig, axes = pc.subplots(1, 3, figsize=(13, 4.2))
    panels = (("friction", 2, lambda k: k[1] == 20.0 and k[0] in (1e3, 1e4, 1e5)),
              ("porosity", 1, lambda k: k[2] == 0.6 and k[0] in (1e3, 1e4, 1e5)),
              ("cohesion", 0, lambda k: k[2] == 0.6 and k[1] in (10.0, 20.0, 40.0)))
    for ax, (name, axis, keep) in zip(axes, panels):
        # iSALE's series: one line per value of the quantity that is not on this panel's axis
        other = 0 if axis != 0 else 1
        groups = {}
        for k, b in ref.items():
            if keep(k):
                groups.setdefault(k[other], []).append((k[axis], b))
        for i, (g, pts) in enumerate(sorted(groups.items())):
            pts.sort()
            text = f"{g / 1e3:g} kPa" if other == 0 else f"{g:g}%"
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o:", color=f"C{i}", mfc="none",
                    label=f"iSALE {text}")
            mine = sorted((key(r)[axis], float(r["beta_launch"])) for r in ours
                          if float(r["cppr"]) == 3 and keep(key(r)) and key(r)[other] == g)
            if mine:
                ax.plot([p[0] for p in mine], [p[1] for p in mine], "s-", color=f"C{i}",
                        label=f"ours {text} (CPPR 3, last run)")
                if scatter:
                    ax.errorbar([p[0] for p in mine], [p[1] for p in mine],
                                yerr=[2 * scatter * (p[1] - 1.0) for p in mine], fmt="none",
                                color=f"C{i}", capsize=3, lw=1)
            fine = sorted((key(r)[axis], float(r["beta_launch"])) for r in finer
                          if keep(key(r)) and key(r)[other] == g)
            if fine:
                ax.plot([p[0] for p in fine], [p[1] for p in fine], "^", color=f"C{i}", ms=8,
                        label=f"ours {text} (CPPR > 3)")
        if name == "cohesion":
            ax.set_xscale("log")
        pc.label(ax, name, "beta")
        pc.legend(ax, fontsize=7)
    axes[0].set_title("Raducan et al. 2019 grid: iSALE-2D (open, 5 s) vs r-z MPM (filled, time"
                      " reached in the docs" + (", bars +-2 sd of one run)" if scatter else ")"),
                      fontsize=9, loc="left")
    pc.save(fig, path)


if __name__ == "__main__":
    main()
