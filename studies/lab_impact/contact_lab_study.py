"""Contact on the laboratory impact (issue 11 item 3, docs/verification.md "Contact"): runs
scenes/lab-impact.toml at 1.2 mm spacing (cell 2.4 mm) over flaw seeds with the single shared
velocity field and with multi-velocity-field contact (frictionless and mu = 0.5), one run at a
time, and tabulates failure ratio at 40 / 100 us, largest fragment (mass fraction, speed),
energy error, and the force the projectile exerts on the target (normal: along the axis into
the target, negative = pull; tangential: along the projectile's velocity component parallel to
the surface) from the projectile momentum in 0.25 us snapshots of a 10 us run.

    python3 studies/lab_impact/contact_lab_study.py BUILD/shatter OUTDIR [--seeds 1 2 3] [--analyse-only]
"""
import argparse
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "tools"))
import shatter_plot as sp  # noqa: E402

CONFIGS = {
    "single": [],
    "multi_mu0": ['solver.contact="multi_field"', "solver.friction=0.0"],
    "multi_mu05": ['solver.contact="multi_field"', "solver.friction=0.5"],
}
BASE = ["solver.cell_size=2.4e-3"]


def run(shatter, out, sets):
    if os.path.exists(os.path.join(out, "timeseries.csv")) and os.path.exists(
            os.path.join(out, "scene.toml")):
        return
    cmd = ["nice", "-n", "5", shatter, "run", "scenes/lab-impact.toml", "--threads", "2",
           "--quiet", "--overwrite", "--out", out]
    for s in BASE + sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True)


def at(ts, key, t):
    return float(np.interp(t, ts["time_s"], ts[key]))


def forces(run_dir):
    files = sp.snapshots(run_dir)
    _, first, axis = sp.read_snapshot(files[0])
    target, _, _, n_in, _ = sp.impact_geometry(first, axis, sp.scene(run_dir))
    d = np.array([1.0, 0.0, 0.0])
    t_dir = d - (d @ n_in) * n_in
    t_dir /= np.linalg.norm(t_dir)
    ts, pn, pt = [], [], []
    for path in files:
        t, c, _ = sp.read_snapshot(path)
        b = c["body"].astype(int) != target
        p = c["mass"][b] @ np.stack([c["vx"][b], c["vy"][b], c["vz"][b]], 1)
        ts.append(t)
        pn.append(p @ n_in)
        pt.append(p @ t_dir)
    ts = np.array(ts)
    fn = -np.gradient(np.array(pn), ts)
    ft = -np.gradient(np.array(pt), ts)
    w = (ts >= 5e-6) & (ts <= 7.3e-6)
    return {"peak_normal_kN": fn.max() / 1e3, "t_peak_us": ts[np.argmax(fn)] * 1e6,
            "min_normal_5_7us_kN": fn[w].min() / 1e3, "min_normal_kN": fn.min() / 1e3,
            "t_min_normal_us": ts[np.argmin(fn)] * 1e6,
            "mean_tangential_0_10us_kN": np.trapz(ft, ts) / (ts[-1] - ts[0]) / 1e3,
            "max_abs_tangential_kN": np.abs(ft).max() / 1e3,
            "tangential_impulse_mNs": (pt[0] - pt[-1]) * 1e3,
            "normal_impulse_mNs": (pn[0] - pn[-1]) * 1e3}


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("shatter")
    ap.add_argument("outdir")
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--analyse-only", action="store_true")
    a = ap.parse_args()
    rows = {}
    for name, sets in CONFIGS.items():
        fdir = os.path.join(a.outdir, f"{name}_force")
        if not a.analyse_only:
            run(a.shatter, fdir, sets + ["solver.end_time=10e-6", "output.snapshot_every=0.25e-6",
                                         'output.columns=["x","y","z","vx","vy","vz","mass","body"]',
                                         "output.fragments=false", "output.checkpoint_every=0"])
        f = forces(fdir)
        for seed in a.seeds:
            d = os.path.join(a.outdir, f"{name}_s{seed}")
            if not a.analyse_only:
                run(a.shatter, d, sets + [f"fracture.seed={seed}"])
            ts = sp.timeseries(d)
            mass, speed, total = sp.fragments(os.path.join(d, "fragments.csv"))
            k = int(np.argmax(mass))
            rows.setdefault(name, []).append(
                [at(ts, "failure_ratio", 40e-6), at(ts, "failure_ratio", 100e-6), mass[k] / total,
                 speed[k], ts["energy_error"][-1], ts["outflow_J"][-1]])
        r = np.array(rows[name])
        print(f"\n{name}: seeds {a.seeds}")
        for j, lab in enumerate(["failure 40us", "failure 100us", "largest m/M", "its speed m/s",
                                 "energy error", "outflow J"]):
            print(f"  {lab:14s} mean {r[:, j].mean():.4f} sd {r[:, j].std(ddof=1) if len(r) > 1 else 0:.4f}"
                  f" range {r[:, j].min():.4f} .. {r[:, j].max():.4f}")
        print("  force (seed 1):", {k: round(v, 2) for k, v in f.items()})


if __name__ == "__main__":
    main()
