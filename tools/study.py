#!/usr/bin/python3
"""Sweep any scene over flaw seeds and a grid of parameters, in parallel, restartable.

  study.py SCENE --out-dir DIR [--seeds 3] [--first-seed 1]
           [--grid KEY=V1,V2,...]... [--set KEY=VALUE]... [-j JOBS] [--threads 1]
           [--times T1,T2,...] [--lab] [--shatter build/release/shatter]
  study.py --summarise DIR

A scene with a random boulder field ([body.NAME.boulders], docs/scenes.md) draws it from
fracture.seed unless the table gives its own seed, so --seeds makes an ensemble over boulder
fields as well as over flaws.

Every combination of the --grid values (any key `shatter run --set` takes: impact.speed,
impact.angle, body.target.damage.weibull_k, a material parameter, ...) is run for each seed as
`shatter run SCENE --out DIR/<grid point>/seed<S> --overwrite --set fracture.seed=S --set KEY=V
...`. A finished run (its marker file study.done) is not repeated, so an interrupted study is
resumed by running the same command again; -j runs that many at once (the development machine
has 2 shared cores).

Per run, figures that any scene and either method gives (from its outputs alone):
  failure ratio (points with D >= the threshold, timeseries.csv) at the end and at --times
  (interpolated); for a scene with [beta], the momentum enhancement's columns beta,
  beta_target and beta_launch at the end and at --times (NaN past the run's end); the wall time;
  the largest fragment's share of the total mass and its speed, the number of fragments, the
  dust share (fragments.csv), the largest |relative energy error|, and every number the fragment
  table's header holds whose name contains "bound" (a bound remnant, when the run writes one). With --lab, also the lab-impact set of tools/ensemble.py (core, shells,
  failure at 40/100 us; needs a body named "target" with a centre; NaN otherwise, said so).

Writes DIR/study.csv (one row per run) and DIR/study.md (per grid point: mean +- sample standard
deviation over the seeds, and the range).
"""

import argparse
import concurrent.futures
import csv
import itertools
import math
import os
import re
import subprocess
import sys

import numpy as np

TOOLS = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(TOOLS, os.pardir, "python"))
import shatterpy as sp  # noqa: E402

DONE = "study.done"


def parse_grid(items):
    """[(key, [values as text])] from KEY=V1,V2 items, in the order given."""
    grid = []
    for item in items:
        key, sep, values = item.partition("=")
        if not sep or not key or not values:
            sys.exit(f"study.py: --grid {item!r}: expected KEY=V1,V2,...")
        grid.append((key.strip(), [v.strip() for v in values.split(",") if v.strip()]))
    return grid


def point_name(point):
    """A folder name for one grid point: key=value pairs joined by '_' (unsafe characters
    replaced), or 'base' for an empty grid."""
    if not point:
        return "base"
    return "_".join(re.sub(r"[^A-Za-z0-9.+=-]", "-", f"{k}={v}") for k, v in point)


def runs_of(grid, seeds):
    keys = [k for k, _ in grid]
    for values in itertools.product(*[v for _, v in grid]):
        point = list(zip(keys, values))
        for seed in seeds:
            yield point, seed


def run_one(args, point, seed):
    run_dir = os.path.join(args.out_dir, point_name(point), f"seed{seed}")
    if os.path.exists(os.path.join(run_dir, DONE)):
        return run_dir, 0, True
    os.makedirs(os.path.dirname(run_dir), exist_ok=True)
    cmd = [args.shatter, "run", args.scene, "--out", run_dir, "--threads", str(args.threads),
           "--overwrite", "--set", f"fracture.seed={seed}"]
    for s in args.set:
        cmd += ["--set", s]
    for k, v in point:
        cmd += ["--set", f"{k}={v}"]
    with open(run_dir + ".log", "w") as log:
        rc = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT)
    if rc == 0:
        with open(os.path.join(run_dir, DONE), "w") as f:
            f.write(" ".join(cmd) + "\n")
    return run_dir, rc, False


def fragment_header(path):
    """The numbers of the fragment table's first line ('# key=value ...')."""
    with open(path) as f:
        line = f.readline()
    out = {}
    for key, value in re.findall(r"([A-Za-z_]\w*)=(\S+)", line):
        try:
            out[key] = float(value)
        except ValueError:
            pass
    return out


def general_metrics(run_dir, times):
    """Figures every run gives, whatever the scene and the method."""
    ts = sp.timeseries(run_dir)
    t = ts["time_s"]
    m = {"t_end_s": float(t[-1]), "failure_end": float(ts["failure_ratio"][-1])}
    for want in times:
        m[f"failure_at_{want:g}s"] = float(np.interp(want, t, ts["failure_ratio"]))
    m["energy_error"] = float(np.max(np.abs(ts["energy_error"])))
    m.update(beta_metrics(ts, times))
    if "wall_s" in ts:
        m["wall_s"] = float(ts["wall_s"][-1])
    frag = os.path.join(run_dir, "fragments.csv")
    if os.path.exists(frag):
        head = fragment_header(frag)
        mass, speed, _ = sp.fragments(frag)
        total = head.get("total_mass_kg", float("nan"))
        big = int(np.argmax(mass)) if mass.size else None
        m["fragments"] = int(mass.size)
        m["largest_fraction"] = float(mass[big] / total) if big is not None else 0.0
        m["largest_speed"] = float(speed[big]) if big is not None else float("nan")
        m["dust_fraction"] = head.get("dust_mass_kg", float("nan")) / total
        for key, value in head.items():
            if "bound" in key:
                m[key] = value
    return m


BETA_COLUMNS = ("beta", "beta_target", "beta_launch")


def beta_metrics(ts, times):
    """The momentum enhancement of a run whose scene has [beta] (its time series' beta columns,
    docs/validation-dart.md): each at the end and at --times (interpolated; NaN past the end).
    {} for a run without them."""
    t = ts["time_s"]
    m = {}
    for col in BETA_COLUMNS:
        if col not in ts:
            continue
        m[f"{col}_end"] = float(ts[col][-1])
        for want in times:
            m[f"{col}_at_{want:g}s"] = (float(np.interp(want, t, ts[col]))
                                        if want <= t[-1] * (1 + 1e-9) else float("nan"))
    return m


def lab_metrics(run_dir):
    """tools/ensemble.py's lab-impact figures, or {} (and a note) for a scene they do not fit."""
    sys.path.insert(0, TOOLS)
    import ensemble
    if not ensemble.lab_applicable(run_dir):
        print(f"study.py: {run_dir}: no body 'target' with a centre and radius: lab-impact "
              "figures skipped", file=sys.stderr)
        return {}
    m = ensemble.summarise_run(run_dir, 5.0)
    return {f"lab_{k}": v for k, v in m.items() if k != "run"}


def summarise(out_dir, times=(), lab=False):
    rows = []
    for root, dirs, files in sorted(os.walk(out_dir)):
        dirs.sort()
        if DONE not in files:
            continue
        rel = os.path.relpath(root, out_dir)
        point, seed = os.path.split(rel)
        row = {"point": point, "seed": int(seed.removeprefix("seed"))}
        row.update(general_metrics(root, times))
        if lab:
            row.update(lab_metrics(root))
        rows.append(row)
    if not rows:
        sys.exit(f"study.py: no finished run under {out_dir}")
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with open(os.path.join(out_dir, "study.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, restval="")
        w.writeheader()
        w.writerows(rows)
    write_markdown(os.path.join(out_dir, "study.md"), rows, keys)
    return rows


def write_markdown(path, rows, keys):
    figures = [k for k in keys if k not in ("point", "seed") and all(
        isinstance(r.get(k, 0.0), (int, float)) for r in rows)]
    lines = ["| grid point | runs | " + " | ".join(figures) + " |",
             "|---|---|" + "---|" * len(figures)]
    for point in sorted({r["point"] for r in rows}):
        sel = [r for r in rows if r["point"] == point]
        cells = []
        for k in figures:
            v = np.array([float(r[k]) for r in sel if k in r], dtype=float)
            v = v[np.isfinite(v)]
            if v.size == 0:
                cells.append("-")
            elif v.size == 1:
                cells.append(f"{v[0]:.4g}")
            else:
                cells.append(f"{v.mean():.4g} ± {v.std(ddof=1):.2g} ({v.min():.4g}-{v.max():.4g})")
        lines.append(f"| {point} | {len(sel)} | " + " | ".join(cells) + " |")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.split("\n")[2:]))
    ap.add_argument("scene", nargs="?")
    ap.add_argument("--out-dir")
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--first-seed", type=int, default=1)
    ap.add_argument("--grid", action="append", default=[], metavar="KEY=V1,V2,...")
    ap.add_argument("--set", action="append", default=[], help="KEY=VALUE for every run")
    ap.add_argument("-j", "--jobs", type=int, default=1, help="runs at once (default 1)")
    ap.add_argument("--threads", type=int, default=1, help="threads per run (default 1)")
    ap.add_argument("--times", default="", help="failure ratio and beta also at these times (s)")
    ap.add_argument("--lab", action="store_true", help="also the lab-impact figures")
    ap.add_argument("--shatter", default="build/release/shatter")
    ap.add_argument("--summarise", metavar="DIR", help="only the tables of a study's runs")
    a = ap.parse_args(argv)
    times = [float(x) for x in a.times.split(",") if x.strip()]
    if a.summarise:
        summarise(a.summarise, times, a.lab)
        return 0
    if not a.scene or not a.out_dir:
        ap.error("SCENE and --out-dir are needed (or --summarise DIR)")
    grid = parse_grid(a.grid)
    seeds = range(a.first_seed, a.first_seed + a.seeds)
    todo = list(runs_of(grid, seeds))
    failed = 0
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        for run_dir, rc, skipped in pool.map(lambda ps: run_one(a, *ps), todo):
            state = "finished before" if skipped else ("done" if rc == 0 else f"FAILED rc={rc}")
            print(f"{run_dir}: {state}", flush=True)
            failed += rc != 0
    summarise(a.out_dir, times, a.lab)
    print(f"{len(todo) - failed} of {len(todo)} runs finished; tables in "
          f"{os.path.join(a.out_dir, 'study.md')} and study.csv")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
