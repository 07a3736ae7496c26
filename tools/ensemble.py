#!/usr/bin/python3
"""Run one scene over N flaw seeds through the CLI and report the scatter of the outcome.

A single laboratory-impact run scatters by ~10% in core mass and ~30% in speed from the flaw
draw alone (issue 11), so validation figures are ensemble figures: mean, standard deviation and
range over seeds.

Usage:
  ensemble.py SCENE --out-dir DIR [--seeds 5] [--first-seed 1] [--jobs 1] [--threads 1]
              [--set key=value ...] [--shatter build/release/shatter] [--label NAME]
  ensemble.py --summarise DIR [DIR ...] [--reference DIR] [--csv FILE]
              (tables of finished ensembles, one row each)

Each run is `shatter run SCENE --out DIR/seed<S> --threads T --overwrite --set fracture.seed=S
--set ...` under `/usr/bin/time -v -o DIR/seed<S>.time` (its CPU time) and `nice -n 5`; a run
whose fragments.csv exists already is not repeated (delete it to rerun). --jobs runs that many at
once (default 1: the development machine has 2 shared cores; use the cores you have).

Per run (tools/plot_lab_convergence.py summarise(), the readers of tools/shatter_plot.py):
  failure ratio (points with D >= the scene's fracture.threshold) at 40 us and at 100 us
  (interpolated in timeseries.csv), the largest fragment's mass over the target mass and its
  speed, the distance of its centre of mass from the target centre, whether it is a core, and
  the largest |relative total-energy error| over the run.
  the failed share of the target's points in three shells of their starting distance from the
  target centre (inner r0 < R/3, middle R/3-2R/3, outer 2R/3-R; by point count, half model as
  run), at the end of the run: what tells a core from a hollow survivor or a far-side crescent.
  the failed share of the target points that lie, at the end, within R/3 of the largest
  fragment's centre of mass: low for a solid fragment, high for a hollow one.
A *central* largest fragment is one whose centre lies within --core-radius (default 5 mm) of the
target centre: the definition of docs/validation-lab-variants.md ("a central core (within 5 mm of
the target centre)"); docs/validation-lab-impact.md's core-shaped fragments sit within 4 mm,
its no-core largest fragments 13-17 mm out. A *core* (issue 27) is more: a central largest
fragment that is intact at its middle, at most --core-failed (default 0.5) of the points within
R/3 of its centre failed. A hollow survivor (its centre of mass near the target centre, its
middle failed) is central but not a core.

Writes DIR/ensemble.csv (one row per run, then mean, std, min, max rows) and DIR/ensemble.md (a
markdown table of mean +- std and range, and the per-run rows). Standard deviations are sample
standard deviations (ddof = 1).

--summarise with --reference REF_DIR also compares each ensemble's mean largest m/M with REF_DIR's
(e.g. a variant against the nominal case over the same seeds): the ratio of the means and their
difference in standard errors, (m - m_ref) / sqrt(s^2 / n + s_ref^2 / n_ref) (unpaired, sample
standard deviations). --csv FILE writes every run of every ensemble (one row per run, its
ensemble's name in the first column): the per-run figures that docs cite."""

import argparse
import concurrent.futures
import csv
import os
import shutil
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_lab_convergence as lab  # noqa: E402  (summarise(): one run's figures)

# (key, header, format) of the per-run quantities, in table order.
QUANTITIES = (
    ("failure_40", "failure 40 us", "{:.1%}"),
    ("failure_100", "failure 100 us", "{:.1%}"),
    ("largest_fraction", "largest m/M", "{:.3f}"),
    ("largest_speed", "its speed (m/s)", "{:.2f}"),
    ("largest_offset_mm", "its centre from target centre (mm)", "{:.1f}"),
    ("energy_error", "max energy error", "{:.2%}"),
    ("failed_inner", "failed r0 < R/3", "{:.1%}"),
    ("failed_middle", "failed R/3-2R/3", "{:.1%}"),
    ("failed_outer", "failed 2R/3-R", "{:.1%}"),
    ("failed_near_largest", "failed within R/3 of the largest's centre", "{:.1%}"),
)


def run_one(args, seed):
    run_dir = os.path.join(args.out_dir, f"seed{seed}")
    if os.path.exists(os.path.join(run_dir, "fragments.csv")):
        return run_dir, 0
    cmd = ["nice", "-n", str(args.nice), "/usr/bin/time", "-v", "-o", run_dir + ".time",
           args.shatter, "run", args.scene, "--out", run_dir, "--threads", str(args.threads),
           "--overwrite", "--set", f"fracture.seed={seed}"]
    for s in args.set:
        cmd += ["--set", s]
    with open(run_dir + ".log", "w") as log:
        rc = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT)
    return run_dir, rc


def shell_failure(run_dir):
    """Failed share (D >= the scene's fracture.threshold) of the target's points at the run's last
    snapshot in the inner, middle and outer thirds of the target radius, by the points' starting
    distance from the target centre (matched by id to the first snapshot)."""
    scene = lab.scene_of(run_dir)
    files = lab.sp.snapshots(run_dir)
    _, first, _ = lab.sp.read_snapshot(files[0])
    _, last, _ = lab.sp.read_snapshot(files[-1])
    tb = lab.target_body(first)
    centre = np.array(scene["body"]["target"]["centre"], dtype=float)
    radius = float(scene["body"]["target"]["radius"])
    threshold = scene.get("fracture", {}).get("threshold", 0.9)
    in0 = first["body"].astype(int) == tb
    pos0 = np.stack([first["x"], first["y"], first["z"]], 1)[in0]
    r0_by_id = dict(zip(first["id"][in0].astype(np.int64), np.linalg.norm(pos0 - centre, axis=1)))
    sel = last["body"].astype(int) == tb
    ids = last["id"][sel].astype(np.int64)
    r0 = np.array([r0_by_id.get(i, np.nan) for i in ids])
    failed = last["damage"][sel] >= threshold
    out = []
    for lo, hi in ((0.0, 1.0 / 3.0), (1.0 / 3.0, 2.0 / 3.0), (2.0 / 3.0, np.inf)):
        m = (r0 >= lo * radius) & (r0 < hi * radius)
        out.append(float(failed[m].mean()) if np.any(m) else np.nan)
    # Around the largest fragment's centre of mass (fragments.csv: largest first; whole body,
    # so on a symmetry plane its centre lies in the plane and the half model's points suffice).
    with open(os.path.join(run_dir, "fragments.csv")) as f:
        f.readline()
        rows = list(csv.DictReader(f))
    near = np.nan
    if rows:
        big = max(rows, key=lambda r: float(r["mass_kg"]))
        c = np.array([float(big[k]) for k in ("x_m", "y_m", "z_m")])
        pos = np.stack([last["x"][sel], last["y"][sel], last["z"][sel]], 1)
        m = np.linalg.norm(pos - c, axis=1) < radius / 3.0
        near = float(failed[m].mean()) if np.any(m) else np.nan
    out.append(near)
    return out


def lab_applicable(run_dir):
    """Whether the lab-impact figures fit the run: a body named "target" with a centre and a
    radius (the scene as resolved, RUN/scene.toml)."""
    target = lab.scene_of(run_dir).get("body", {}).get("target", {})
    return "centre" in target and "radius" in target


def general_run(run_dir):
    """The figures any scene gives (tools/study.py), in this table's keys; the lab-only ones
    (shells, core, offset) are NaN and the run is neither central nor a core."""
    import study
    ts = lab.sp.timeseries(run_dir)
    g = study.general_metrics(run_dir, ())
    nan = float("nan")
    return {
        "failed_inner": nan, "failed_middle": nan, "failed_outer": nan,
        "failed_near_largest": nan, "central": False, "run": os.path.basename(run_dir),
        "failure_40": float(np.interp(40e-6, ts["time_s"], ts["failure_ratio"])),
        "failure_100": float(np.interp(100e-6, ts["time_s"], ts["failure_ratio"])),
        "largest_fraction": g.get("largest_fraction", nan),
        "largest_speed": g.get("largest_speed", nan), "largest_offset_mm": nan,
        "energy_error": g["energy_error"], "core": False, "cpu_s": nan,
        "t_end_us": g["t_end_s"] * 1e6,
    }


def summarise_run(run_dir, core_radius_mm, core_failed=0.5):
    if not lab_applicable(run_dir):
        # Another scene (an asteroid of the user's own): no KeyError, the general figures.
        print(f"ensemble.py: {run_dir}: no body 'target' with a centre and radius: lab-impact "
              "figures (shells, core, offset) are NaN; see tools/study.py", file=sys.stderr)
        return general_run(run_dir)
    s = lab.summarise(run_dir)
    t = s["time_us"]
    inner, middle, outer, near = shell_failure(run_dir)
    central = bool(s["largest_offset_mm"] <= core_radius_mm)
    return {
        "failed_inner": inner,
        "failed_middle": middle,
        "failed_outer": outer,
        "failed_near_largest": near,
        "central": central,
        "run": os.path.basename(run_dir),
        "failure_40": float(np.interp(40.0, t, s["failure"])),
        "failure_100": float(np.interp(100.0, t, s["failure"])),
        "largest_fraction": s["largest_fraction"],
        "largest_speed": s["largest_speed"],
        "largest_offset_mm": s["largest_offset_mm"],
        "energy_error": s["max_abs_energy_error"],
        "core": central and near <= core_failed,
        "cpu_s": s["cpu_s"],
        "t_end_us": s["t_end_us"],
    }


def statistics(rows):
    """Mean, sample std, min and max of each quantity. A run without fragments (the whole target
    failed) has no largest-fragment speed or position: those are over the runs that have one
    (nan when none has)."""
    out = {}
    for key, _, _ in QUANTITIES:
        v = np.array([r[key] for r in rows], dtype=float)
        v = v[np.isfinite(v)]
        if len(v) == 0:
            out[key] = (np.nan,) * 4
            continue
        out[key] = (v.mean(), v.std(ddof=1) if len(v) > 1 else 0.0, v.min(), v.max())
    out["cores"] = sum(r["core"] for r in rows)
    out["central"] = sum(r["central"] for r in rows)
    out["n"] = len(rows)
    return out


def write_csv(path, rows, stats):
    keys = ["run"] + [k for k, _, _ in QUANTITIES] + ["central", "core", "cpu_s", "t_end_us"]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(keys)
        for r in rows:
            w.writerow([r[k] for k in keys])
        for i, name in enumerate(("mean", "std", "min", "max")):
            w.writerow([name] + [stats[k][i] for k, _, _ in QUANTITIES] +
                       [stats["central"] if name == "mean" else "",
                        stats["cores"] if name == "mean" else "", "", ""])


def cell(stats, key, fmt):
    m, sd, lo, hi = stats[key]
    return f"{fmt.format(m)} ± {fmt.format(sd)} ({fmt.format(lo)}-{fmt.format(hi)})"


def summary_header():
    head = (["ensemble", "runs"] + [h + ", mean ± std (range)" for _, h, _ in QUANTITIES] +
            ["central", "cores"])
    return "| " + " | ".join(head) + " |\n|" + "---|" * len(head) + "\n"


def summary_row(label, stats):
    cells = [label, str(stats["n"])] + [cell(stats, k, f) for k, _, f in QUANTITIES]
    cells.append(f"{stats['central']}/{stats['n']}")
    cells.append(f"{stats['cores']}/{stats['n']}")
    return "| " + " | ".join(cells) + " |\n"


def write_markdown(path, label, rows, stats):
    with open(path, "w") as f:
        f.write(summary_header())
        f.write(summary_row(label, stats))
        f.write("\n| run | " + " | ".join(h for _, h, _ in QUANTITIES) +
                " | central | core | CPU s |\n")
        f.write("|---|" + "---|" * (len(QUANTITIES) + 3) + "\n")
        for r in rows:
            vals = [fmt.format(r[k]) for k, _, fmt in QUANTITIES]
            cpu = f"{r['cpu_s']:.0f}" if r["cpu_s"] is not None else "-"
            f.write(f"| {r['run']} | " + " | ".join(vals) +
                    f" | {'yes' if r['central'] else 'no'} | {'yes' if r['core'] else 'no'}"
                    f" | {cpu} |\n")


def comparison(stats, ref, key="largest_fraction"):
    """(ratio of means, difference in standard errors) of `key` against a reference ensemble."""
    m, sd = stats[key][:2]
    mr, sdr = ref[key][:2]
    se = np.sqrt(sd**2 / stats["n"] + sdr**2 / ref["n"])
    return m / mr, ((m - mr) / se if se > 0 else np.nan)


def write_runs_csv(path, table):
    keys = [k for k, _, _ in QUANTITIES] + ["central", "core", "cpu_s", "t_end_us"]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["ensemble", "run"] + keys)
        for name, rows in table:
            for r in rows:
                w.writerow([name, r["run"]] + [r[k] for k in keys])


def finished_runs(ens_dir):
    return sorted((os.path.join(ens_dir, d) for d in os.listdir(ens_dir)
                   if d.startswith("seed") and os.path.isdir(os.path.join(ens_dir, d)) and
                   os.path.exists(os.path.join(ens_dir, d, "fragments.csv"))),
                  key=lambda p: int(os.path.basename(p)[4:]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene", nargs="?")
    ap.add_argument("--out-dir")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--first-seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=1, help="runs at once (default 1)")
    ap.add_argument("--threads", type=int, default=1, help="threads per run (default 1)")
    ap.add_argument("--nice", type=int, default=5)
    ap.add_argument("--set", action="append", default=[], help="key=value, passed to shatter run")
    ap.add_argument("--shatter", default="build/release/shatter")
    ap.add_argument("--label", help="row label (default: the output directory's name)")
    ap.add_argument("--core-radius", type=float, default=5.0, help="mm (default 5)")
    ap.add_argument("--core-failed", type=float, default=0.5,
                    help="largest failed share within R/3 of a core's centre (default 0.5)")
    ap.add_argument("--summarise", nargs="+", metavar="DIR",
                    help="only tabulate finished ensembles, one row each")
    ap.add_argument("--reference", metavar="DIR",
                    help="with --summarise: compare each ensemble's largest m/M with this one's")
    ap.add_argument("--csv", metavar="FILE",
                    help="with --summarise: write every run's figures to FILE")
    args = ap.parse_args()

    if args.summarise:
        name = lambda d: os.path.basename(os.path.normpath(d))  # noqa: E731
        table = [(name(d), [summarise_run(r, args.core_radius, args.core_failed)
                            for r in finished_runs(d)]) for d in args.summarise]
        table = [(n, rows) for n, rows in table if rows]
        sys.stdout.write(summary_header())
        for n, rows in table:
            sys.stdout.write(summary_row(n, statistics(rows)))
        if args.reference:
            ref_rows = [summarise_run(r, args.core_radius, args.core_failed)
                        for r in finished_runs(args.reference)]
            if len(ref_rows) < 2:
                ap.error(f"--reference: fewer than 2 finished runs in '{args.reference}'")
            ref = statistics(ref_rows)
            sys.stdout.write(f"\n| ensemble | largest m/M against {name(args.reference)}: "
                             "ratio of means | difference in standard errors |\n|---|---|---|\n")
            for n, rows in table:
                ratio, z = comparison(statistics(rows), ref)
                sys.stdout.write(f"| {n} | {ratio:.2f} | {z:+.1f} |\n")
        if args.csv:
            write_runs_csv(args.csv, table)
        return 0

    if not args.scene or not args.out_dir:
        ap.error("SCENE and --out-dir are required (or --summarise DIR ...)")
    if args.seeds < 1 or args.jobs < 1:
        ap.error("--seeds and --jobs must be >= 1")
    if shutil.which(args.shatter) is None and not os.path.exists(args.shatter):
        ap.error(f"--shatter: no executable at '{args.shatter}'")
    os.makedirs(args.out_dir, exist_ok=True)
    seeds = range(args.first_seed, args.first_seed + args.seeds)
    failed = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for run_dir, rc in pool.map(lambda s: run_one(args, s), seeds):
            print(f"{run_dir}: {'ok' if rc == 0 else f'FAILED (exit {rc}, see {run_dir}.log)'}",
                  flush=True)
            if rc != 0:
                failed.append(run_dir)
    if failed:
        print(f"{len(failed)} run(s) failed; no table written", file=sys.stderr)
        return 1
    rows = [summarise_run(os.path.join(args.out_dir, f"seed{s}"), args.core_radius,
                          args.core_failed) for s in seeds]
    stats = statistics(rows)
    label = args.label or os.path.basename(os.path.normpath(args.out_dir))
    write_csv(os.path.join(args.out_dir, "ensemble.csv"), rows, stats)
    write_markdown(os.path.join(args.out_dir, "ensemble.md"), label, rows, stats)
    sys.stdout.write(summary_header() + summary_row(label, stats))
    return 0


if __name__ == "__main__":
    sys.exit(main())
