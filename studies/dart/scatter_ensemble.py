#!/usr/bin/python3
"""The scatter of beta_launch between runs of one scene that differ by a tiny perturbation (issue
32, session 23; docs/validation-dart.md, "Session 23").

MEMBER runs are the same scene with one perturbed input (session 23: raducan2019-10kpa.toml with
the impact speed 7000 (1 + k 1e-6) m/s, k = 0..3, set with --set body.impactor.velocity=...).
The script reads each RUN/timeseries.csv (beta_launch against time, linearly interpolated) and
prints, at the times of --times, every member's beta_launch, the mean and the sample standard
deviation (ddof 1) over the members, their range and the largest difference between two members;
with --compare LABEL=RUN (any number; split at the last "=") it puts single runs of the same point (other widths,
domains or binaries) beside the ensemble: their difference from the ensemble mean, in units of
the standard deviation of one run (a difference between two single runs has sqrt(2) times it).
With --reference (docs/figures/dart/raducan2019_beta.csv) and --point COHESION:POROSITY:FRICTION
each value is also given against iSALE-2D's final beta.

With --plot FILE.png: above, beta_launch(t) of every member, the mean +- one standard deviation
and the compared runs; below, each member minus the ensemble mean and each compared run minus it,
with the +-1 and +-2 standard deviation bands. With --csv FILE the table at --times.

Usage: scatter_ensemble.py MEMBER... [--compare LABEL=RUN ...] [--times 0.05 0.1 0.2 0.3]
       [--reference REF.csv --point 1e4:20:0.6] [--plot F.png [--title TEXT]] [--csv F.csv]
"""

import argparse
import math
import os
import statistics
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir,
                                "tools"))
import plot_common as pc  # noqa: E402  (tools/plot_common.py: Agg, dpi, common labels)
from target_width import at, read_reference, read_run  # noqa: E402  (this folder)


def series(run):
    """beta_launch against time of RUN: [(t, beta_launch)], sorted."""
    return read_run(run)[0]


def value(ts, t):
    """beta_launch at t, or nan past the run's end."""
    return at(ts, t) if t <= ts[-1][0] + 1e-9 else float("nan")


def stats(values):
    v = [x for x in values if not math.isnan(x)]
    if len(v) < 2:
        return float("nan"), float("nan"), float("nan"), float("nan"), len(v)
    return statistics.fmean(v), statistics.stdev(v), min(v), max(v), len(v)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("members", nargs="+")
    ap.add_argument("--compare", nargs="*", default=[], metavar="LABEL=RUN")
    ap.add_argument("--times", nargs="+", type=float, default=[0.05, 0.1, 0.15, 0.2, 0.25, 0.3])
    ap.add_argument("--reference")
    ap.add_argument("--point", default="1e4:20:0.6")
    ap.add_argument("--title", default="raducan2019-10kpa (9 m target), r-z MPM CPPR 3: runs with "
                    "impact speeds 1e-6 apart")
    ap.add_argument("--plot")
    ap.add_argument("--csv")
    a = ap.parse_args()
    members = [series(r) for r in a.members]
    names = [os.path.basename(r.rstrip("/")) for r in a.members]
    compared = [(c.rsplit("=", 1)[0], series(c.rsplit("=", 1)[1])) for c in a.compare]
    b_isale = None
    if a.reference:
        b_isale = float(read_reference(a.reference,
                                       tuple(float(v) for v in a.point.split(":")))["beta"])
    print(f"# {len(members)} members: " + ", ".join(
        f"{n} (to {ts[-1][0]:.4g} s)" for n, ts in zip(names, members))
        + (f"; iSALE final {b_isale:.3f}" if b_isale else ""))
    head = ["t (s)"] + names + ["mean +- std", "range", "max pair diff"] \
        + [f"{lab} - mean (std)" for lab, _ in compared]
    print("| " + " | ".join(head) + " |")
    print("|---" * len(head) + "|")
    rows = []
    for t in a.times:
        vals = [value(ts, t) for ts in members]
        mean, std, lo, hi, n = stats(vals)
        row = {"time_s": t, **{f"beta_launch_{nm}": v for nm, v in zip(names, vals)},
               "n": n, "mean": mean, "std": std, "min": lo, "max": hi}
        cells = [f"{t:g}"] + [f"{v:.4f}" if not math.isnan(v) else "" for v in vals]
        cells += [f"{mean:.4f} +- {std:.4f}" if n > 1 else "",
                  f"{lo:.4f}-{hi:.4f}" if n > 1 else "", f"{hi - lo:.4f}" if n > 1 else ""]
        for lab, ts in compared:
            v = value(ts, t)
            d = v - mean
            row[f"{lab}_minus_mean"] = d
            cells.append("" if math.isnan(d) else
                         f"{d:+.4f} ({d / std:+.1f})" if std > 0 else f"{d:+.4f}")
        if b_isale:
            row["mean_vs_isale_pct"] = 100 * (mean / b_isale - 1)
            row["std_pct_of_isale"] = 100 * std / b_isale
        rows.append(row)
        print("| " + " | ".join(cells) + " |")
    if b_isale:
        print("\nmean against iSALE: " + ", ".join(
            f"{r['time_s']:g} s {r['mean_vs_isale_pct']:+.1f}% (std {r['std_pct_of_isale']:.2f}%)"
            for r in rows if not math.isnan(r["mean"])))
    if a.csv:
        pc.write_csv(a.csv, "beta_launch of an ensemble of perturbed runs (mean, sample std) and "
                     "single runs against its mean; studies/dart/scatter_ensemble.py", rows)
    if a.plot:
        plot(members, names, compared, b_isale, a)


def plot(members, names, compared, b_isale, a):
    t_end = min(ts[-1][0] for ts in members)
    grid = [t_end * i / 300 for i in range(1, 301)]
    mean, std = [], []
    for t in grid:
        m, s, *_ = stats([value(ts, t) for ts in members])
        mean.append(m)
        std.append(s)
    fig, (ax, ax_d) = pc.subplots(2, 1, figsize=(7.5, 7.5), sharex=True)
    for i, ts in enumerate(members):
        ax.plot([t for t, _ in ts if t <= t_end], [b for t, b in ts if t <= t_end], color="C0",
                lw=0.6, alpha=0.7, label="members" if i == 0 else None)
    ax.fill_between(grid, [m - s for m, s in zip(mean, std)], [m + s for m, s in zip(mean, std)],
                    color="C0", alpha=0.25, label=f"mean +- std ({len(members)} members)")
    for j, (lab, ts) in enumerate(compared):
        ax.plot([t for t, _ in ts if t <= t_end], [b for t, b in ts if t <= t_end],
                color=f"C{j + 1}", lw=1.0, label=lab)
    if b_isale:
        ax.axhline(b_isale, color="k", ls=":", lw=1, label=f"iSALE-2D final (5 s) {b_isale:.3f}")
    pc.label(ax, None, "beta_launch")
    ax.set_title(a.title, fontsize=9)
    pc.legend(ax, loc="lower right")
    for i, ts in enumerate(members):
        ax_d.plot(grid, [value(ts, t) - m for t, m in zip(grid, mean)], color="C0", lw=0.6,
                  alpha=0.7, label="member - mean" if i == 0 else None)
    ax_d.fill_between(grid, [-s for s in std], std, color="C0", alpha=0.25, label="+-1 std")
    ax_d.fill_between(grid, [-2 * s for s in std], [2 * s for s in std], color="C0", alpha=0.1,
                      label="+-2 std")
    for j, (lab, ts) in enumerate(compared):
        ax_d.plot(grid, [value(ts, t) - m for t, m in zip(grid, mean)], color=f"C{j + 1}", lw=1.0,
                  label=f"{lab} - mean")
    ax_d.axhline(0, color="k", lw=0.5)
    ax_d.set_xlabel("time (s)")
    ax_d.set_ylabel("beta_launch - ensemble mean")
    pc.legend(ax_d, loc="lower left", ncol=2)
    pc.save(fig, a.plot)
    try:  # the noisy curves make a 230 kB RGBA PNG; a 64-colour palette keeps it ~60 kB
        from PIL import Image
        Image.open(a.plot).convert("RGB").quantize(colors=64).save(a.plot, optimize=True)
    except ImportError:
        pass


if __name__ == "__main__":
    main()
