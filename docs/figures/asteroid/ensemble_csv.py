#!/usr/bin/python3
"""Per-run CSV and ensemble rows of asteroid seed ensembles (docs/validation-asteroid.md).

Usage:
  ensemble_csv.py --csv OUT.csv CASE=DIR [CASE=DIR ...]

DIR is a tools/ensemble.py output folder (seed<S>/ run folders, seed<S>.time from /usr/bin/time -v).
Per run: the failure ratio at 5.638 s (one crossing time), 6, 10 and 15 s, linearly interpolated
in timeseries.csv (empty past the run's end); the fragments of fragments.csv (the run's own
fragment search, half model mirrored); the largest fragment's mass over the target mass of
Table 5 (2.2091e16 kg), its speed |v| in the lab frame and its centre's distance from the target
centre (the origin); the second largest m/M; the largest |energy error|; CPU = user + system.
Prints one markdown row per case: mean ± sample standard deviation (min-max) over the runs.
The CSV's columns are those of ensembles_500m.csv plus steps of the run, 2nd m/M and semi-axes."""

import argparse
import csv
import os
import re
import sys

import numpy as np

TARGET_MASS = 2.2091e16
TIMES = (5.638, 6.0, 10.0, 15.0)


def run_figures(case, d, seed):
    run = os.path.join(d, f"seed{seed}")
    with open(os.path.join(run, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    t = np.array([float(r["time_s"]) for r in rows])
    fail = np.array([float(r["failure_ratio"]) for r in rows])
    err = np.array([float(r["energy_error"]) for r in rows])
    with open(os.path.join(run, "fragments.csv")) as f:
        lines = [x for x in f if not x.startswith("#")]
    frs = sorted(csv.DictReader(lines), key=lambda r: -float(r["mass_kg"]))
    big = frs[0] if frs else None
    timef = open(os.path.join(d, f"seed{seed}.time")).read()
    cpu = sum(float(re.search(rf"{k} time \(seconds\): ([\d.]+)", timef).group(1)) for k in ("User", "System"))
    out = {"case": case, "seed": seed, "end_time_s": t[-1], "steps": int(rows[-1]["step"])}
    for T in TIMES:
        out[f"failure_{T:g}s"] = float(np.interp(T, t, fail)) if T <= t[-1] + 1e-9 else ""
    out["fragments"] = len(frs)
    if big:
        out["largest_fraction"] = float(big["mass_kg"]) / TARGET_MASS
        out["largest_speed_m_per_s"] = float(np.sqrt(sum(float(big[k]) ** 2 for k in ("vx_m/s", "vy_m/s", "vz_m/s"))))
        out["largest_centre_from_target_centre_km"] = float(
            np.sqrt(sum(float(big[k]) ** 2 for k in ("x_m", "y_m", "z_m")))) / 1e3
        out["largest_semi_axes_km"] = " x ".join(f"{float(big[k]) / 1e3:.1f}" for k in ("a_m", "b_m", "c_m"))
    else:
        out.update(largest_fraction=0.0, largest_speed_m_per_s="", largest_centre_from_target_centre_km="",
                   largest_semi_axes_km="")
    out["second_fraction"] = float(frs[1]["mass_kg"]) / TARGET_MASS if len(frs) > 1 else 0.0
    out["max_abs_energy_error"] = float(np.max(np.abs(err)))
    out["cpu_s"] = round(cpu, 1)
    return out


def stat(vals, fmt, scale=1.0, unit=""):
    v = np.array([float(x) * scale for x in vals if x != ""])
    if len(v) == 0:
        return "-"
    sd = v.std(ddof=1) if len(v) > 1 else 0.0
    f = lambda x: fmt.format(x) + unit  # noqa: E731
    n = f" [{len(v)} runs]" if len(v) != len(vals) else ""
    return f"{f(v.mean())} ± {f(sd)} ({f(v.min())}-{f(v.max())}){n}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("cases", nargs="+", help="CASE=DIR")
    ap.add_argument("--csv", required=True)
    a = ap.parse_args()
    allrows = []
    for c in a.cases:
        case, d = c.split("=", 1)
        seeds = sorted(int(x[4:]) for x in os.listdir(d) if re.fullmatch(r"seed\d+", x)
                       and os.path.exists(os.path.join(d, x, "fragments.csv")))
        rs = [run_figures(case, d, s) for s in seeds]
        allrows += rs
        if not rs:
            continue
        g = lambda k: [r[k] for r in rs]  # noqa: E731
        fails = " | ".join(stat(g(f"failure_{T:g}s"), "{:.3f}", 100, "%") for T in TIMES)
        print(f"| {case} | {len(rs)} (seeds {','.join(map(str, seeds))}) | {fails} | "
              f"{stat(g('largest_fraction'), '{:.4f}')} | {stat(g('largest_speed_m_per_s'), '{:.1f}')} | "
              f"{stat(g('largest_centre_from_target_centre_km'), '{:.1f}')} | {stat(g('second_fraction'), '{:.4f}')} | "
              f"{stat(g('fragments'), '{:.1f}')} | {stat(g('max_abs_energy_error'), '{:.2f}', 100, '%')} | "
              f"{min(g('cpu_s')):.0f}-{max(g('cpu_s')):.0f} s | {min(g('steps'))}-{max(g('steps'))} |")
    keys = list(allrows[0].keys()) if allrows else []
    with open(a.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in allrows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    return 0


if __name__ == "__main__":
    sys.exit(main())
