#!/usr/bin/python3
"""The laboratory impact's core across resolutions: when and where the runs of different point
spacings part (docs/validation-lab-impact.md, "Resolution study", issue 16 item 4).

Usage: lab_core_history.py RUN_DIR [RUN_DIR ...] [--shatter BIN] [--out FIG.png] [--csv FILE]

Each RUN_DIR is a finished `shatter run` of scenes/lab-impact.toml (half model). For every
snapshot from 10 us on, `shatter fragments` (the scene's threshold, grid_density as the run) finds
the fragments; the script records the failure ratio, the largest fragment's mass fraction, speed,
spin about z and distance from the target centre, and, for the last snapshot, where the largest
fragment's points started: its mass per shell of initial distance from the target centre and
per shell of initial distance from the impact point, so that the core of a fine run can be laid
over a coarse one's. Points of the fragment are matched to the snapshot by position (the
`--ss-particles` file holds the mirrored body, in its own order).

Writes a figure (--out) with four panels (largest fragment m/M and speed against time, the
failure ratio against time, the final core's mass per initial radius) and a CSV (--csv) with one
row per run and snapshot; prints both tables. Each run's results are cached in
RUN_DIR/core_history.json.
"""

import argparse
import sys
import csv
import json
import os
import subprocess
import tempfile
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# The readers (shatter_plot) are among the user's tools.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "tools"))
import shatter_plot as sp  # noqa: E402


def scene_of(run_dir):
    with open(os.path.join(run_dir, "scene.toml"), "rb") as f:
        return tomllib.load(f)


def position_keys(xyz):
    """Hashable keys of positions rounded to 10 nm (the .ss file stores them in AU)."""
    return [tuple(r) for r in np.round(xyz * 1e8).astype(np.int64)]


def fragments_of(shatter, snapshot, threshold, workdir):
    """(fragment table, colour per snapshot point) of one snapshot: colour 3 = largest fragment."""
    prefix = os.path.join(workdir, "f")
    subprocess.run([shatter, "fragments", snapshot, "--threshold", str(threshold), "--prefix",
                    prefix, "--ss-particles", "--quiet"], check=True)
    table, meta = sp.fragment_table(prefix + ".csv")
    _, ss = sp.read_ss(prefix + "_particles.ss")
    _, cols, _ = sp.read_snapshot(snapshot)
    where = {k: i for i, k in enumerate(position_keys(ss["pos"]))}
    index = np.array([where[k] for k in position_keys(np.c_[cols["x"], cols["y"], cols["z"]])])
    return table, ss["color"][index], cols


def history(run_dir, shatter):
    scene = scene_of(run_dir)
    threshold = scene.get("fracture", {}).get("threshold", 0.9)
    files = sp.snapshots(run_dir)
    t0, first, axis = sp.read_snapshot(files[0])
    mirror = 2.0 if axis >= 0 else 1.0
    body = first["body"].astype(int)
    tb = int(np.argmax(np.bincount(body, weights=first["mass"])))
    target = body == tb
    target_mass = mirror * first["mass"][target].sum()
    centre = np.array(scene["body"]["target"]["centre"])
    radius = scene["body"]["target"]["radius"]
    pos0 = np.c_[first["x"], first["y"], first["z"]]
    proj = pos0[~target].mean(axis=0)
    if axis >= 0:
        proj[axis] = centre[axis]  # the half model holds one half of the projectile
    impact = centre + radius * (proj - centre) / np.linalg.norm(proj - centre)
    r0 = dict(zip(first["id"].astype(np.int64), np.linalg.norm(pos0 - centre, axis=1)))
    d0 = dict(zip(first["id"].astype(np.int64), np.linalg.norm(pos0 - impact, axis=1)))
    ts = sp.timeseries(run_dir)
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for path in files:
            t = sp.read_snapshot_time(path)
            if t < 9.5e-6:
                continue
            table, colour, cols = fragments_of(shatter, path, threshold, work)
            order = np.argsort(-table["mass_kg"])
            big = order[0]
            v = np.array([table[f"v{a}_m/s"][big] for a in "xyz"])
            x = np.array([table[f"{a}_m"][big] for a in "xyz"])
            rows.append({
                "run": run_dir, "cell_mm": 1e3 * scene["solver"]["cell_size"],
                "t_us": 1e6 * t,
                "failure": float(np.interp(t, ts["time_s"], ts["failure_ratio"])),
                "largest": table["mass_kg"][big] / target_mass,
                "second": table["mass_kg"][order[1]] / target_mass if len(order) > 1 else 0.0,
                "speed": float(np.linalg.norm(v)), "vx": v[0], "vy": v[1],
                "spin_z": table["wz_rad/s"][big],
                "offset_mm": 1e3 * float(np.linalg.norm(x - centre)),
            })
            last = (colour, cols)
    colour, cols = last
    in_core = (colour == 3) & (cols["body"].astype(int) == tb)
    ids = cols["id"][in_core].astype(np.int64)
    mass = mirror * cols["mass"][in_core]
    r_edges = np.arange(0.0, radius + 1e-9, 1.5e-3)
    d_edges = np.arange(0.0, 2 * radius + 1e-9, 3.0e-3)
    # Intact target per shell of initial radius at the end (what could belong to a core).
    sel = cols["body"].astype(int) == tb
    intact = cols["damage"][sel] < threshold
    r_all = np.array([r0[i] for i in cols["id"][sel].astype(np.int64)])
    shell_all = np.histogram(r_all, r_edges, weights=mirror * cols["mass"][sel])[0]
    shell_intact = np.histogram(r_all[intact], r_edges, weights=mirror * cols["mass"][sel][intact])[0]
    composition = {
        "r_edges_mm": 1e3 * r_edges,
        "core_by_r": np.histogram([r0[i] for i in ids], r_edges, weights=mass)[0] / target_mass,
        "intact_by_r": shell_intact / np.maximum(shell_all, 1e-300),
        "d_edges_mm": 1e3 * d_edges,
        "core_by_d": np.histogram([d0[i] for i in ids], d_edges, weights=mass)[0] / target_mass,
        "cell_mm": rows[-1]["cell_mm"],
    }
    return rows, composition


def cached_history(run_dir, shatter):
    """history(), kept in RUN_DIR/core_history.json (the fragment search on every snapshot of a
    0.6 mm run takes minutes); delete the file to recompute."""
    path = os.path.join(run_dir, "core_history.json")
    if os.path.exists(path) and os.path.getmtime(path) > os.path.getmtime(
            os.path.join(run_dir, "fragments.csv")):
        with open(path) as f:
            rows, comp = json.load(f)
        return rows, {k: (np.array(v) if isinstance(v, list) else v) for k, v in comp.items()}
    rows, comp = history(run_dir, shatter)
    with open(path, "w") as f:
        json.dump([rows, {k: (v.tolist() if isinstance(v, np.ndarray) else v)
                          for k, v in comp.items()}], f)
    return rows, comp


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dirs", nargs="+")
    ap.add_argument("--shatter", default="build/release/shatter")
    ap.add_argument("--out", default="out/lab-core-history.png")
    ap.add_argument("--csv", default="out/lab-core-history.csv")
    ap.add_argument("--labels", nargs="*", help="legend labels, one per RUN_DIR (default: spacing)")
    a = ap.parse_args()
    runs = [cached_history(d, a.shatter) for d in a.run_dirs]
    labels = a.labels or [f"{c['cell_mm'] / 2:.1f} mm" for _, c in runs]
    for d in (os.path.dirname(a.out), os.path.dirname(a.csv)):
        if d:
            os.makedirs(d, exist_ok=True)
    keys = ["run", "cell_mm", "t_us", "failure", "largest", "second", "speed", "vx", "vy",
            "spin_z", "offset_mm"]
    with open(a.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for rows, _ in runs:
            for r in rows:
                w.writerow({k: (f"{r[k]:.6g}" if isinstance(r[k], float) else r[k]) for k in keys})
    print("| run | t (us) | failure | largest m/M | speed (m/s) | spin z (rad/s) | centre offset (mm) |")
    print("|---|---|---|---|---|---|---|")
    for (rows, _), name in zip(runs, labels):
        for r in rows:
            print(f"| {name} | {r['t_us']:.0f} | {100 * r['failure']:.1f}% | {r['largest']:.3f} | "
                  f"{r['speed']:.2f} | {r['spin_z']:+.1f} | {r['offset_mm']:.1f} |")
    print("\nfinal largest fragment (m/M) by initial distance from the target centre (mm):")
    for (_, c), name in zip(runs, labels):
        mids = 0.5 * (c["r_edges_mm"][1:] + c["r_edges_mm"][:-1])
        print(name, " ".join(f"{m:.0f}:{v:.3f}" for m, v in zip(mids, c["core_by_r"])))
        print(name, "intact", " ".join(f"{m:.0f}:{v:.2f}" for m, v in zip(mids, c["intact_by_r"])))
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5))
    for k, ((rows, c), name) in enumerate(zip(runs, labels)):
        t = [r["t_us"] for r in rows]
        style = dict(color=f"C{k % 10}", marker="o", ms=3, label=name)
        axes[0, 0].plot(t, [r["largest"] for r in rows], **style)
        axes[0, 1].plot(t, [r["speed"] for r in rows], **style)
        axes[1, 0].plot(t, [100 * r["failure"] for r in rows], **style)
        mids = 0.5 * (c["r_edges_mm"][1:] + c["r_edges_mm"][:-1])
        axes[1, 1].plot(mids, 100 * c["intact_by_r"], **style)
    axes[0, 0].set_ylabel("largest fragment m/M")
    axes[0, 1].set_ylabel("its speed (m/s)")
    axes[1, 0].set_ylabel("failure ratio, D >= 0.9 (%)")
    for ax in (axes[0, 0], axes[0, 1], axes[1, 0]):
        ax.set_xlabel("time (us)")
    axes[1, 1].set_xlabel("initial distance from the target centre (mm)")
    axes[1, 1].set_ylabel("intact (D < 0.9) at the end, % of the shell's mass")
    for ax in axes.flat:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("modified Lundborg Y0 = 60 MPa: the largest fragment and the failure across "
                 "point spacings")
    fig.tight_layout()
    fig.savefig(a.out, dpi=100)


if __name__ == "__main__":
    main()
