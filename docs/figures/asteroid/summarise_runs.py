#!/usr/bin/python3
"""Table rows for docs/validation-asteroid.md and docs/validation-lab-variants.md from run
directories written by `shatter run` (run under /usr/bin/time -v, log in RUN_DIR.log).

Usage: summarise_runs.py --target-mass M --times T1 T2 RUN_DIR [RUN_DIR ...] [--plot-failure F.png]
       [--plot-energy F.png] [--time-unit s|us]
Per run: points, steps, largest fragment m/M (M = target mass) and speed |v| in the lab frame,
its semi-axes, 2nd largest m/M, fragment count, failure ratio at each T (interpolated in
timeseries.csv), max |energy error|, wall and CPU time, particle-steps per wall / CPU second."""

import argparse
import csv
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "tools"))
import shatter_plot as sp  # noqa: E402


def log_numbers(run_dir):
    text = open(run_dir.rstrip("/") + ".log").read()
    out = {}
    m = re.search(r"(\d+) points in (\d+) bodies", text)
    out["points"] = int(m.group(1)) if m else 0
    m = re.search(r"finished: t = .*?, (\d+) steps, ([\d.]+) s wall", text)
    if m:
        out["steps"], out["wall"] = int(m.group(1)), float(m.group(2))
    m = re.search(r"User time \(seconds\): ([\d.]+)", text)
    u = float(m.group(1)) if m else float("nan")
    m = re.search(r"System time \(seconds\): ([\d.]+)", text)
    out["cpu"] = u + (float(m.group(1)) if m else 0.0)
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", text)
    out["rss_mb"] = int(m.group(1)) / 1024 if m else float("nan")
    return out


def fragments(run_dir):
    path = os.path.join(run_dir, "fragments.csv")
    with open(path) as f:
        head = f.readline()
        rows = list(csv.DictReader(f))
    total = float(re.search(r"total_mass_kg=([\d.eE+-]+)", head).group(1))
    dust = float(re.search(r"dust_mass_kg=([\d.eE+-]+)", head).group(1))
    rows.sort(key=lambda r: -float(r["mass_kg"]))
    return rows, total, dust


def cross_section(run_dirs, labels, at, out, unit):
    """MPM paper Figs. 12-13: damage and speed of the points next to the symmetry plane."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    length = (1e-3, "km") if unit == "s" else (1e3, "mm")
    tscale = 1.0 if unit == "s" else 1e6
    fig, axes = plt.subplots(2, len(run_dirs), figsize=(3.4 * len(run_dirs), 6.4), squeeze=False)
    for k, (d, lab) in enumerate(zip(run_dirs, labels)):
        t, c, axis = sp.read_snapshot(sp.snapshot_at(d, at))
        normal = "xyz"[axis] if axis >= 0 else "z"
        plane = [q for q in "xyz" if q != normal]
        h = np.cbrt(np.median(c["volume0"]))
        layer = np.abs(c[normal]) < h
        u, v = c[plane[0]][layer] * length[0], c[plane[1]][layer] * length[0]
        speed = np.sqrt(c["vx"] ** 2 + c["vy"] ** 2 + c["vz"] ** 2)[layer]
        im = axes[0][k].scatter(u, v, c=c["damage"][layer], s=3, cmap="inferno", vmin=0, vmax=1)
        axes[0][k].set_title(f"{lab}: damage, t = {t * tscale:g} {unit}", fontsize=9)
        im2 = axes[1][k].scatter(u, v, c=speed, s=3, cmap="viridis", vmin=0,
                                 vmax=np.percentile(speed, 95) if speed.size else 1)
        axes[1][k].set_title(f"{lab}: |v| (m/s)", fontsize=9)
        for ax in (axes[0][k], axes[1][k]):
            ax.set_aspect("equal")
            ax.set_xlabel(f"{plane[0]} ({length[1]})")
            ax.set_ylabel(f"{plane[1]} ({length[1]})")
        fig.colorbar(im, ax=axes[0][k], shrink=0.8)
        fig.colorbar(im2, ax=axes[1][k], shrink=0.8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print("wrote", out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run_dirs", nargs="+")
    ap.add_argument("--target-mass", type=float, required=True)
    ap.add_argument("--times", type=float, nargs="*", default=[])
    ap.add_argument("--time-unit", default="s", choices=["s", "us"])
    ap.add_argument("--plot-failure")
    ap.add_argument("--plot-energy")
    ap.add_argument("--labels", nargs="*")
    ap.add_argument("--flaws", type=float, metavar="YOUNG",
                    help="print E x mean eps_min and E x mean eps_max per body from RUN_DIR/checkpoint.h5 "
                         "(MPM paper Table 7's sigma_min, sigma_max), E = YOUNG in Pa")
    ap.add_argument("--cross-section", help="PNG: damage and |v| on the symmetry plane, one column per run")
    ap.add_argument("--at", type=float, help="snapshot time for --cross-section (s)")
    a = ap.parse_args()
    scale = 1e6 if a.time_unit == "us" else 1.0
    labels = a.labels or [os.path.basename(d.rstrip("/")) for d in a.run_dirs]
    print("| run | points | steps | largest m/M | its speed (m/s) | its semi-axes a, b, c | its centre from the target centre | 2nd m/M |"
          " fragments | dust m/M | " + " | ".join(f"failure {t * scale:g} {a.time_unit}" for t in a.times)
          + " | max abs energy error | final energy error | wall (s) | CPU (s) | p-steps/s wall | p-steps/s CPU | RSS (MB) |")
    for d, lab in zip(a.run_dirs, labels):
        n = log_numbers(d)
        ts = sp.timeseries(d)
        fr, total, dust = fragments(d)
        big = fr[0] if fr else None
        second = float(fr[1]["mass_kg"]) / a.target_mass if len(fr) > 1 else 0.0
        fails = [np.interp(t, ts["time_s"], ts["failure_ratio"]) for t in a.times]
        ee = ts["energy_error"]
        ps = n["points"] * n.get("steps", 0)
        if big:
            v = np.sqrt(sum(float(big[k]) ** 2 for k in ("vx_m/s", "vy_m/s", "vz_m/s")))
            axes = "%.3g, %.3g, %.3g m" % tuple(float(big[k]) for k in ("a_m", "b_m", "c_m"))
            m = float(big["mass_kg"]) / a.target_mass
            r = "%.3g m" % np.sqrt(sum(float(big[k]) ** 2 for k in ("x_m", "y_m", "z_m")))
        else:
            v, axes, m, r = float("nan"), "-", 0.0, "-"
        print(f"| {lab} | {n['points']} | {n.get('steps', 0)} | {m:.3f} | {v:.3g} | {axes} | {r} | {second:.3f} | {len(fr)} |"
              f" {dust / a.target_mass:.3f} | " + " | ".join(f"{100 * f:.1f}%" for f in fails)
              + f" | {100 * np.max(np.abs(ee)):.2f}% | {100 * ee[-1]:.2f}% | {n.get('wall', float('nan')):.0f} |"
              f" {n['cpu']:.0f} | {ps / n.get('wall', np.nan):.3g} | {ps / n['cpu']:.3g} | {n['rss_mb']:.0f} |")
    if a.flaws:
        import h5py
        for d, lab in zip(a.run_dirs, labels):
            with h5py.File(os.path.join(d, "checkpoint.h5"), "r") as f:
                P = f["particles"]
                body, emin, emax, nf = (P[k][()] for k in ("body", "eps_min", "eps_max", "n_flaws"))
            for b in np.unique(body):
                m = body == b
                print(f"{lab} body {b}: {m.sum()} points, sigma_min = E <eps_min> = {a.flaws * emin[m].mean() / 1e6:.4g} MPa,"
                      f" sigma_max = E <eps_max> = {a.flaws * emax[m].mean() / 1e6:.4g} MPa, <n_flaws> = {nf[m].mean():.4g}")
    if a.cross_section:
        cross_section(a.run_dirs, labels, a.at, a.cross_section, a.time_unit)
    if a.plot_failure or a.plot_energy:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        unit = a.time_unit
        for what, out in (("failure_ratio", a.plot_failure), ("energy_error", a.plot_energy)):
            if not out:
                continue
            fig, ax = plt.subplots(figsize=(6.5, 4))
            for d, lab in zip(a.run_dirs, labels):
                ts = sp.timeseries(d)
                ax.plot(ts["time_s"] * scale, 100 * ts[what], label=lab)
            ax.set_xlabel(f"time ({unit})")
            ax.set_ylabel(("failure ratio" if what == "failure_ratio" else "energy error") + " (%)")
            if what == "failure_ratio" and unit == "us":
                ax.axhline(52, color="gray", ls="--", lw=0.8, label="MPM paper nominal, converged (52%)")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
            fig.tight_layout()
            fig.savefig(out, dpi=120)
            print("wrote", out)


if __name__ == "__main__":
    main()
