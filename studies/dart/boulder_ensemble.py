#!/usr/bin/python3
"""The first seed ensemble of beta (issue 32, session 20; docs/validation-dart.md, "Session 20:
boulders and seed ensembles"): DART into raducan2024-weak-rz with random boulder fields, one
field per seed, against the same target without boulders.

  boulder_ensemble.py STUDY_DIR REFERENCE_RUN [--out docs/figures/dart/boulder_ensemble_s20.png]
                      [--times 0.002,0.005,0.01,0.02] [--column beta_launch]

STUDY_DIR is a tools/study.py output directory (STUDY_DIR/base/seed<S>/); REFERENCE_RUN a run of
the boulder-free scene. Prints, per time, beta (each beta column) as mean +- sample standard
deviation and range over the seeds beside the reference, and draws: left, the first seed's
boulder body in the r-z half-plane at t = 0; right, the chosen beta column against time for
every seed and the reference.
"""

import argparse
import glob
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, os.pardir, os.pardir, "python"))
sys.path.insert(0, os.path.join(HERE, os.pardir, os.pardir, "tools"))
import plot_common as pc  # noqa: E402
import shatterpy as sp  # noqa: E402

COLUMNS = ("beta", "beta_target", "beta_launch")


def seed_runs(study_dir):
    runs = sorted(glob.glob(os.path.join(study_dir, "*", "seed*", "study.done")),
                  key=lambda p: int(os.path.basename(os.path.dirname(p))[4:]))
    return [os.path.dirname(p) for p in runs]


def at(ts, col, t):
    return float(np.interp(t, ts["time_s"], ts[col])) if t <= ts["time_s"][-1] * (1 + 1e-9) \
        else float("nan")


def table(runs, ref, times):
    series = [sp.timeseries(r) for r in runs]
    ref_ts = sp.timeseries(ref)
    lines = ["| t | column | boulders: mean ± sd (min-max), n | no boulders | difference of the "
             "mean |", "|---|---|---|---|---|"]
    for t in times:
        for col in COLUMNS:
            v = np.array([at(ts, col, t) for ts in series])
            v = v[np.isfinite(v)]
            r = at(ref_ts, col, t)
            if v.size < 2:
                continue
            lines.append(f"| {t * 1e3:g} ms | {col} | {v.mean():.4f} ± {v.std(ddof=1):.4f} "
                         f"({v.min():.4f}-{v.max():.4f}), {v.size} | {r:.4f} | "
                         f"{v.mean() - r:+.4f} |")
    return "\n".join(lines)


def fields(runs, column):
    """Per seed: boulders placed, fraction reached (the run's resolved scene), the boulder share
    of the mass within 1 m of the impact point's column (r < 1 m, 0-2 m deep, t = 0), and the
    beta column at the end."""
    lines = ["| seed | boulders | fraction | boulder share, r < 1 m, 0-2 m deep | "
             f"{column} at the end |", "|---|---|---|---|---|"]
    for r in runs:
        scene = sp.scene(r) or {}
        table_ = next((b["boulders"] for b in scene.get("body", {}).values()
                       if "boulders" in b), {})
        first = sp.snapshots(r)[0]
        _, cols, _ = sp.read_snapshot(first)
        names, _ = sp.snapshot_names(first)
        ids = [i for i, n in enumerate(names) if n.endswith("_boulders")]
        near = (cols["x"] < 1.0) & (cols["z"] < 0.0) & (cols["z"] > -2.0)
        m = cols["mass"]
        share = m[near & np.isin(cols["body"].astype(int), ids)].sum() / m[near].sum()
        ts = sp.timeseries(r)
        lines.append(f"| {os.path.basename(r)[4:]} | {table_.get('placed', '-')} | "
                     f"{table_.get('fraction_placed', float('nan')):.4f} | {share:.3f} | "
                     f"{ts[column][-1]:.4f} |")
    return "\n".join(lines)


def draw(runs, ref, column, out):
    fig, (a0, a1) = pc.subplots(1, 2, figsize=(11, 4.5))
    first = sp.snapshots(runs[0])[0]
    _, cols, _ = sp.read_snapshot(first)
    names, _ = sp.snapshot_names(first)
    body = cols["body"].astype(int)
    boulder_ids = [i for i, n in enumerate(names) if n.endswith("_boulders")]
    sel = np.isin(body, boulder_ids)
    host = ~sel & (cols["z"] < 0.5)
    a0.scatter(cols["x"][host], cols["z"][host], s=0.3, c="0.8", lw=0)
    a0.scatter(cols["x"][sel], cols["z"][sel], s=0.3, c="k", lw=0)
    a0.set_aspect("equal")
    a0.set_xlabel("r (m)")
    a0.set_ylabel("z (m)")
    a0.set_title(f"{os.path.basename(runs[0])}: boulder rings (black) in r-z", fontsize=9)
    for r in runs:
        ts = sp.timeseries(r)
        a1.plot(ts["time_s"] * 1e3, ts[column], lw=0.8, label=os.path.basename(r))
    finish(fig, a1, ref, column, out)


def finish(fig, ax, ref, column, out):
    """The boulder-free run's curve (dashed) on ax, labels and legend; fig written to out."""
    ts = sp.timeseries(ref)
    ax.plot(ts["time_s"] * 1e3, ts[column], "k--", lw=1.5, label="no boulders")
    pc.label(ax, "t_ms", column)
    pc.legend(ax)
    pc.save(fig, out)  # (closes fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.split("\n")[2:]))
    ap.add_argument("study_dir")
    ap.add_argument("reference")
    ap.add_argument("--out", default="")
    ap.add_argument("--times", default="0.002,0.005,0.01,0.02")
    ap.add_argument("--column", default="beta_launch", choices=COLUMNS)
    a = ap.parse_args()
    runs = seed_runs(a.study_dir)
    if not runs:
        sys.exit(f"{a.study_dir}: no finished seed runs")
    print(table(runs, a.reference, [float(x) for x in a.times.split(",")]))
    print()
    print(fields(runs, a.column))
    if a.out:
        draw(runs, a.reference, a.column, a.out)
        print(f"wrote {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
