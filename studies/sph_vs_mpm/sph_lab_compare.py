#!/usr/bin/python3
"""Laboratory impact, SPH beside MPM (issue 10 "Laboratory impact"): tables and figures from
finished seed ensembles of tools/ensemble.py (one directory per method and resolution, seed<S>/
runs inside).

Per ensemble, mean +- sample std (and range) over its seeds of:
  failure ratio (timeseries.csv failure_ratio: points with D >= fracture.threshold) at
  10, 20, 40 and 100 us (linear interpolation);
  the largest fragment of the run's own catalogue (fragments.csv, the scene's fragment method:
  grid density by default), its mass over the target's mass (x 2 for a half model, as
  tools/ensemble.py), its speed and its centre's distance from the target centre, and how many runs have a core (its centre within
  --core-radius of the target centre, tools/ensemble.py's definition);
  with --fof, the largest fragment by BA95 Sec. 4.4 (friends-of-friends, one-layer damaged
  veneer) on each run's last snapshot through `shatter fragments`: for SPH runs friends within
  one smoothing length (--h-factor, the runs' solver.sph.h_factor), for MPM runs the module's
  1.5-spacing link; its mass over the total mass (target + 0.2 g projectile), its speed and the
  core count; once per --static-strength value (Pa; 0 = no pre-pass; BA95's pre-pass fails an
  undamaged point whose largest principal stress reaches it).

--plot-failure FILE: failure ratio against time per ensemble, mean line and min-max band.
--labels: one row / legend label per directory (default: the directory names).

Usage:
  sph_lab_compare.py DIR [DIR ...] [--labels L ...] [--fof] [--static-strength 0 19.43e6]
                     [--plot-failure FILE.png] [--shatter build/release/shatter] [--h-factor 1.2]
"""

import argparse
import csv
import glob
import os
import statistics
import subprocess

import numpy as np

TIMES_US = (10.0, 20.0, 40.0, 100.0)


def timeseries(run_dir):
    t, f = [], []
    with open(os.path.join(run_dir, "timeseries.csv")) as fh:
        for row in csv.DictReader(fh):
            t.append(float(row["time_s"]) * 1e6)
            f.append(float(row["failure_ratio"]))
    return np.array(t), np.array(f)


def failure_at(run_dir, t_us):
    t, f = timeseries(run_dir)
    return float(np.interp(t_us, t, f)) if len(t) and t_us <= t[-1] * 1.0001 else float("nan")


def is_sph(run_dir):
    with open(os.path.join(run_dir, "scene.toml")) as fh:
        return 'method = "sph"' in fh.read()


def largest_of(csv_path, core_radius_mm, denominator=None):
    """(mass fraction, speed, centre's distance from the target centre in mm) of the largest
    fragment of a fragment table. The mass is over `denominator` (kg) if given, else over the
    table's total mass. The target centre is the origin, as in scenes/lab-impact.toml."""
    with open(csv_path) as fh:
        header = fh.readline()
        total = float(header.split("total_mass_kg=")[1].split()[0])
        rows = list(csv.DictReader(fh))
    if not rows:
        return 0.0, float("nan"), float("nan")
    big = max(rows, key=lambda r: float(r["mass_kg"]))
    speed = float(np.linalg.norm([float(big[k]) for k in ("vx_m/s", "vy_m/s", "vz_m/s")]))
    offset = 1e3 * float(np.linalg.norm([float(big[k]) for k in ("x_m", "y_m", "z_m")]))
    return float(big["mass_kg"]) / (denominator or total), speed, offset


def own_catalogue(run_dir, core_radius_mm):
    """The run's own catalogue, mass over the target's mass as tools/ensemble.py reports it."""
    import plot_lab_convergence as lab  # noqa: E402 (tools/ on the path: this file's folder)
    import shatter_plot as sp
    files = sp.snapshots(run_dir)
    _, first, axis = sp.read_snapshot(files[0])
    tb = lab.target_body(first)
    mirror = 2.0 if axis >= 0 else 1.0
    target_mass = mirror * first["mass"][first["body"].astype(int) == tb].sum()
    return largest_of(os.path.join(run_dir, "fragments.csv"), core_radius_mm, target_mass)


def fof_largest(run_dir, shatter, h_factor, static_strength, core_radius_mm):
    snaps = sorted(glob.glob(os.path.join(run_dir, "snapshots", "snapshot_*.h5")))
    tag = "" if static_strength <= 0 else f"-s{static_strength:g}"
    prefix = os.path.join(run_dir, "fof" + tag)
    if not os.path.exists(prefix + ".csv"):
        cmd = [shatter, "fragments", snaps[-1], "--method", "friends_of_friends", "--prefix",
               prefix, "--quiet"]
        if is_sph(run_dir):
            cmd += ["--smoothing-factor", str(h_factor)]
        if static_strength > 0:
            cmd += ["--static-strength", str(static_strength)]
        subprocess.run(cmd, check=True)
    return largest_of(prefix + ".csv", core_radius_mm)


def fmt(vals, f):
    vals = [v for v in vals if v == v]
    if not vals:
        return "-"
    if len(vals) == 1:
        return f.format(vals[0])
    return (f + " ± " + f + " (" + f + "-" + f + ")").format(
        statistics.mean(vals), statistics.stdev(vals), min(vals), max(vals))


def runs_of(d):
    return sorted((r for r in glob.glob(os.path.join(d, "seed*")) if os.path.isdir(r)),
                  key=lambda p: int(os.path.basename(p)[4:]))


def plot_failure(dirs, labels, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    colours = ["tab:blue", "tab:red", "tab:green", "tab:purple", "tab:orange", "tab:brown"]
    grid = np.linspace(0.0, 100.0, 401)
    for k, (d, lab) in enumerate(zip(dirs, labels)):
        curves = []
        for r in runs_of(d):
            t, f = timeseries(r)
            curves.append(np.interp(grid, t, f, right=np.nan))
        c = 100.0 * np.array(curves)
        col = colours[k % len(colours)]
        ax.fill_between(grid, np.nanmin(c, 0), np.nanmax(c, 0), color=col, alpha=0.25, lw=0)
        ax.plot(grid, np.nanmean(c, 0), color=col, lw=1.5, label=f"{lab} ({len(curves)} seeds)")
    ax.axhline(52.0, color="grey", ls=":", lw=1.0)
    ax.text(99, 53, "MPM paper, nominal: ~52 %", ha="right", va="bottom", fontsize=8,
            color="grey")
    ax.set_xlabel("t (us)")
    ax.set_ylabel("failure ratio (% of target points with D >= 0.9)")
    ax.set_xlim(0, 100)
    ax.set_ylim(0, 100)
    ax.legend(fontsize=8, loc="lower right")
    ax.set_title("Laboratory impact, nominal case: mean (line) and range over flaw seeds",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    print("wrote", path)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--labels", nargs="+")
    ap.add_argument("--fof", action="store_true")
    ap.add_argument("--static-strength", type=float, nargs="+", default=[0.0],
                    help="Pa, one FoF column group each (0 = no pre-pass)")
    ap.add_argument("--shatter", default="build/release/shatter")
    ap.add_argument("--h-factor", type=float, default=1.2)
    ap.add_argument("--core-radius", type=float, default=5.0, help="mm (default 5)")
    ap.add_argument("--plot-failure")
    args = ap.parse_args()
    labels = args.labels or [os.path.basename(os.path.normpath(d)) for d in args.dirs]
    if len(labels) != len(args.dirs):
        raise SystemExit("--labels needs one label per directory")
    head = ["ensemble", "runs"] + [f"failure {t:g} us" for t in TIMES_US]
    head += ["largest m/M (own catalogue)", "its speed (m/s)", "its centre off (mm)", "cores"]
    if args.fof:
        for s in args.static_strength:
            tag = "FoF" if s <= 0 else f"FoF, static {s / 1e6:g} MPa"
            head += [f"{tag}: largest m/M", "its speed (m/s)", "its centre off (mm)", "cores"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for d, lab in zip(args.dirs, labels):
        runs = runs_of(d)
        cells = [lab, str(len(runs))]
        for t in TIMES_US:
            cells.append(fmt([100.0 * failure_at(r, t) for r in runs], "{:.1f}%"))
        own = [own_catalogue(r, args.core_radius) for r in runs]
        cells += [fmt([m for m, _, _ in own], "{:.3f}"), fmt([v for _, v, _ in own], "{:.2f}"),
                  fmt([o for _, _, o in own], "{:.1f}"),
                  f"{sum(o <= args.core_radius for _, _, o in own)}/{len(own)}"]
        if args.fof:
            for s in args.static_strength:
                res = [fof_largest(r, args.shatter, args.h_factor, s, args.core_radius)
                       for r in runs]
                cells += [fmt([m for m, _, _ in res], "{:.3f}"),
                          fmt([v for _, v, _ in res], "{:.2f}"),
                          fmt([o for _, _, o in res], "{:.1f}"),
                          f"{sum(o <= args.core_radius for _, _, o in res)}/{len(res)}"]
        print("| " + " | ".join(cells) + " |")
    if args.plot_failure:
        plot_failure(args.dirs, labels, args.plot_failure)


if __name__ == "__main__":
    import sys
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "tools"))
    main()
