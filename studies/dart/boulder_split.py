#!/usr/bin/python3
"""Which property of the boulders raises beta (issue 32, session 20; docs/validation-dart.md,
"Session 20: boulders and seed ensembles", "Which property raises beta"): seed ensembles of boulder
variants (same fields, other boulder material) against the full boulders and the boulder-free run.

  boulder_split.py REFERENCE_RUN LABEL=STUDY_DIR [LABEL=STUDY_DIR ...]
                   [--times 0.01,0.02,0.03] [--column beta_launch] [--out FIGURE.png]

Each STUDY_DIR is a tools/study.py output directory (STUDY_DIR/base/seed<S>/); the first is the
one the others are paired with (the full boulders). REFERENCE_RUN is a run of the boulder-free
scene. Prints per time and variant the column as mean +- sample standard deviation (range), n;
the difference of the mean from the boulder-free run; and, over the seeds a variant shares with
the first study, the mean +- sd of the paired difference (variant - first, seed by seed: the same
boulder field, so the field-to-field spread drops out). Draws the column against time: each
variant's mean with a band of +- one sd, and the boulder-free run.
"""

import argparse
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, os.pardir, os.pardir, "python"))
sys.path.insert(0, os.path.join(HERE, os.pardir, os.pardir, "tools"))
sys.path.insert(0, HERE)
import boulder_ensemble as be  # noqa: E402
import plot_common as pc  # noqa: E402
import shatterpy as sp  # noqa: E402


def seeds_of(study_dir):
    return {int(os.path.basename(r)[4:]): sp.timeseries(r) for r in be.seed_runs(study_dir)}


def table(variants, ref, times, column):
    ref_ts = sp.timeseries(ref)
    first = variants[0][1]
    lines = [f"| t | variant | {column}: mean ± sd (min-max), n | minus no boulders | paired "
             f"with {variants[0][0]}: mean ± sd, n |", "|---|---|---|---|---|"]
    for t in times:
        r = be.at(ref_ts, column, t)
        lines.append(f"| {t * 1e3:g} ms | no boulders | {r:.4f}, 1 | 0 | - |")
        for label, runs in variants:
            v = np.array([be.at(ts, column, t) for ts in runs.values()])
            v = v[np.isfinite(v)]
            if v.size == 0:
                continue
            sd = f"{v.std(ddof=1):.4f}" if v.size > 1 else "-"
            paired = "-"
            if runs is not first:
                d = np.array([be.at(ts, column, t) - be.at(first[s], column, t)
                              for s, ts in runs.items() if s in first])
                d = d[np.isfinite(d)]
                if d.size:
                    dsd = f"{d.std(ddof=1):.4f}" if d.size > 1 else "-"
                    paired = f"{d.mean():+.4f} ± {dsd}, {d.size}"
            lines.append(f"| {t * 1e3:g} ms | {label} | {v.mean():.4f} ± {sd} "
                         f"({v.min():.4f}-{v.max():.4f}), {v.size} | {v.mean() - r:+.4f} | "
                         f"{paired} |")
    return "\n".join(lines)


def per_seed(variants, column):
    seeds = sorted(set().union(*(runs.keys() for _, runs in variants)))
    lines = ["| seed | " + " | ".join(label for label, _ in variants) + " |",
             "|---|" + "---|" * len(variants)]
    for s in seeds:
        cells = [f"{runs[s][column][-1]:.4f}" if s in runs else "-" for _, runs in variants]
        lines.append(f"| {s} | " + " | ".join(cells) + " |")
    return f"{column} at the end of each run:\n\n" + "\n".join(lines)


def draw(variants, ref, column, out):
    fig, ax = pc.subplots(1, 1, figsize=(7, 4.5))
    for label, runs in variants:
        t_end = min(ts["time_s"][-1] for ts in runs.values())
        t = np.linspace(0.0, t_end, 301)
        v = np.array([[be.at(ts, column, x) for x in t] for ts in runs.values()])
        m = v.mean(axis=0)
        line, = ax.plot(t * 1e3, m, lw=1.5, label=f"{label} (n = {len(runs)})")
        if len(runs) > 1:
            s = v.std(axis=0, ddof=1)
            ax.fill_between(t * 1e3, m - s, m + s, color=line.get_color(), alpha=0.2, lw=0)
    ax.set_title(f"{column}: seed mean ± 1 sd per boulder material (r-z, CPPR 3)", fontsize=9)
    be.finish(fig, ax, ref, column, out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.split("\n")[2:]))
    ap.add_argument("reference")
    ap.add_argument("studies", nargs="+", metavar="LABEL=STUDY_DIR")
    ap.add_argument("--out", default="")
    ap.add_argument("--times", default="0.01,0.02,0.03")
    ap.add_argument("--column", default="beta_launch", choices=be.COLUMNS)
    a = ap.parse_args()
    variants = []
    for spec in a.studies:
        label, _, path = spec.partition("=")
        runs = seeds_of(path)
        if not runs:
            sys.exit(f"{path}: no finished seed runs")
        variants.append((label, runs))
    print(table(variants, a.reference, [float(x) for x in a.times.split(",")], a.column))
    print()
    print(per_seed(variants, a.column))
    if a.out:
        draw(variants, a.reference, a.column, a.out)
        print(f"wrote {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
