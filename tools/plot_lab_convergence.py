#!/usr/bin/python3
"""Laboratory impact (Nakamura & Fujiwara 1991) across resolutions: the MPM paper's Fig. 5 and the
error against the experiment against run time.

Usage: plot_lab_convergence.py RUN_DIR [RUN_DIR ...] [--out-dir DIR] [--table FILE.md]

Each RUN_DIR is a finished `shatter run` of scenes/lab-impact.toml (timeseries.csv, snapshots,
fragments.csv, scene.toml). Draws into --out-dir:
  failure_ratio.png      failure ratio (points with D >= threshold) against time, one line per run
  error_vs_walltime.png  |largest fragment mass fraction - 0.31| / 0.31 and |speed - 1.35| / 1.35
                         against wall time, with the MPM paper's and the SPH run's errors
  damage_vs_radius.png   failure ratio at the end against the initial distance from the target
                         centre (a core: an intact centre under a failed shell)
  energy_error.png       relative total-energy error against time
  damage_vs_impact_distance.png  failed points at 10 and 20 us against the initial distance from
                         the impact point (how far the direct wave fails the target)
  cross_sections.png     damage and speed on the symmetry plane at the end, one column per run
                         (the MPM paper's Fig. 6)
and writes a markdown table of the figures per run (--table, default OUT_DIR/summary.md)."""

import argparse
import csv
import os
import tomllib

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import shatter_plot as sp

# shared/reference/lab-impact-nakamura1991.md: (largest fragment mass / target mass, its speed m/s).
EXPERIMENT = (0.31, 1.35)  # Nakamura & Fujiwara 1991
SPH = (0.30, 1.352)  # Benz & Asphaug 1994
MPM_PAPER = (0.246, 2.056)  # Yan et al., nominal case
PAPER_FAILURE_100US = 0.52  # MPM paper Sec. 4.1.1, converged failure ratio at 100 us


def scene_of(run_dir):
    with open(os.path.join(run_dir, "scene.toml"), "rb") as f:
        return tomllib.load(f)


def target_body(cols):
    """Body index of the target: the heaviest body."""
    body = cols["body"].astype(int)
    return int(np.argmax(np.bincount(body, weights=cols["mass"])))


def summarise(run_dir):
    scene = scene_of(run_dir)
    ts = sp.timeseries(run_dir)
    files = sp.snapshots(run_dir)
    _, first, axis = sp.read_snapshot(files[0])
    t_end, last, _ = sp.read_snapshot(files[-1])
    mirror = 2.0 if axis >= 0 else 1.0
    tb = target_body(first)
    in_target = first["body"].astype(int) == tb
    target_mass = mirror * first["mass"][in_target].sum()
    threshold = scene.get("fracture", {}).get("threshold", 0.9)

    frag_csv = os.path.join(run_dir, "fragments.csv")
    mass, speed, _ = sp.fragments(frag_csv)
    order = np.argsort(-mass)
    mass, speed = mass[order], speed[order]
    # Where the largest fragment sits: a core lies near the target centre (Fig. 6 of the paper).
    with open(frag_csv) as f:
        f.readline()  # "# total_mass_kg=..."
        rows = list(csv.DictReader(f))
    big = {k: float(rows[order[0]][k]) for k in ("x_m", "y_m", "z_m")} if rows else None

    # Failure against the initial distance from the target centre, matched by particle id.
    centre = np.array(scene["body"]["target"]["centre"])
    radius = scene["body"]["target"]["radius"]
    r0_by_id = dict(zip(first["id"].astype(np.int64),
                        np.linalg.norm(np.stack([first["x"], first["y"], first["z"]], 1) - centre, axis=1)))
    # Failure against the distance from the impact point (the target surface point nearest to the
    # projectile's initial centre), at 10 and 20 us: how far the direct wave fails the target.
    pos0 = np.stack([first["x"], first["y"], first["z"]], 1)
    proj = pos0[~in_target].mean(axis=0)
    if axis >= 0:
        proj[axis] = centre[axis]  # the half model holds the upper half of the projectile
    impact = centre + radius * (proj - centre) / np.linalg.norm(proj - centre)
    d_imp_by_id = dict(zip(first["id"].astype(np.int64), np.linalg.norm(pos0 - impact, axis=1)))
    d_edges = np.linspace(0.0, 2.0 * radius, 11)
    fail_by_d = {}
    for t_want in (10e-6, 20e-6):
        path = sp.snapshot_at(run_dir, t_want)
        t_got, snap, _ = sp.read_snapshot(path)
        sel = snap["body"].astype(int) == tb
        dist = np.array([d_imp_by_id[i] for i in snap["id"][sel].astype(np.int64)])
        bins = np.clip(np.digitize(dist, d_edges) - 1, 0, len(d_edges) - 2)
        bad = snap["damage"][sel] >= threshold
        fail_by_d[round(t_got * 1e6)] = np.array(
            [bad[bins == k].mean() if np.any(bins == k) else np.nan for k in range(len(d_edges) - 1)])

    last_t = last["body"].astype(int) == tb
    r0 = np.array([r0_by_id[i] for i in last["id"][last_t].astype(np.int64)])
    failed = last["damage"][last_t] >= threshold
    edges = np.linspace(0.0, radius, 11)
    shell = np.clip(np.digitize(r0, edges) - 1, 0, len(edges) - 2)
    fail_by_r = np.array([failed[shell == k].mean() if np.any(shell == k) else np.nan
                          for k in range(len(edges) - 1)])

    offset_mm = (np.linalg.norm([big["x_m"], big["y_m"], big["z_m"]] - centre) * 1e3
                 if big is not None else np.nan)
    steps = ts["step"][-1]
    wall = ts["wall_s"][-1]
    n_run = len(first["mass"])  # points the run advanced (half model: one half)
    cell = scene["solver"]["cell_size"]
    return {
        "dir": run_dir,
        "cell_mm": cell * 1e3,
        "spacing_mm": cell * 1e3 / 2.0,
        "n_target_full": int(round(mirror * in_target.sum())),
        "n_run": n_run,
        "steps": int(steps),
        "wall_s": wall,
        "pstep_per_s": n_run * steps / wall,
        "cpu_s": cpu_seconds(run_dir),
        "t_end_us": t_end * 1e6,
        "time_us": ts["time_s"] * 1e6,
        "failure": ts["failure_ratio"],
        "failure_40": np.interp(40e-6, ts["time_s"], ts["failure_ratio"]),
        "failure_end": ts["failure_ratio"][-1],
        "energy_error": ts["energy_error"],
        "max_abs_energy_error": float(np.max(np.abs(ts["energy_error"]))),
        "largest_fraction": mass[0] / target_mass if len(mass) else 0.0,
        "largest_speed": speed[0] if len(speed) else np.nan,
        "largest_offset_mm": offset_mm,
        "second_fraction": mass[1] / target_mass if len(mass) > 1 else 0.0,
        "fragments": len(mass),
        "r_edges_mm": edges * 1e3,
        "fail_by_r": fail_by_r,
        "d_edges_mm": d_edges * 1e3,
        "fail_by_d": fail_by_d,
    }


def cpu_seconds(run_dir):
    """User + system CPU time from `/usr/bin/time -v -o RUN_DIR.time` if present, else None. On
    a shared machine the wall time of a one-thread run measures the load; CPU time does not."""
    path = os.path.normpath(run_dir) + ".time"
    if not os.path.exists(path):
        return None
    total = 0.0
    with open(path) as f:
        for line in f:
            if line.strip().startswith(("User time", "System time")):
                total += float(line.split(":")[-1])
    return total


def rel_err(value, ref):
    return abs(value - ref) / ref


def label(s):
    return s.get("label") or f"{s['spacing_mm']:.1f} mm ({s['n_target_full']:,} pts)"


def plot_failure(runs, out):
    fig, ax = plt.subplots(figsize=(5.5, 3.8))
    for s in runs:
        ax.plot(s["time_us"], 100 * s["failure"], label=label(s))
    ax.axhline(100 * PAPER_FAILURE_100US, color="gray", ls="--", lw=0.8,
               label="MPM paper at 100 us (52%)")
    ax.set_xlabel("time (us)")
    ax.set_ylabel("failure ratio, D >= 0.9 (% of target points)")
    ax.set_ylim(0, 100)
    custom = any(s.get("label") for s in runs)
    ax.legend(fontsize=8, title=None if custom else "point spacing", title_fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    plt.close(fig)


def plot_error_vs_wall(runs, out):
    fig, axes = plt.subplots(1, 2, figsize=(8.5, 3.6), sharex=True)
    wall = np.array([s["wall_s"] for s in runs])
    for ax, key, k, name in ((axes[0], "largest_fraction", 0, "largest fragment mass fraction"),
                             (axes[1], "largest_speed", 1, "largest fragment speed")):
        err = np.array([rel_err(s[key], EXPERIMENT[k]) for s in runs])
        ax.plot(wall, 100 * err, "o-", color="C0", label="shatter, wall time")
        cpu = np.array([s["cpu_s"] if s["cpu_s"] else np.nan for s in runs])
        if np.any(np.isfinite(cpu)):
            ax.plot(cpu, 100 * err, "s--", color="C0", mfc="none", label="shatter, CPU time")
        for s, e in zip(runs, err):
            ax.annotate(f"{s['spacing_mm']:.1f} mm", (s["wall_s"], 100 * e), fontsize=7,
                        textcoords="offset points", xytext=(4, 4))
        ax.axhline(100 * rel_err(MPM_PAPER[k], EXPERIMENT[k]), color="C1", ls="--", lw=0.9,
                   label="MPM paper (0.8 mm)")
        ax.axhline(100 * rel_err(SPH[k], EXPERIMENT[k]), color="C2", ls=":", lw=0.9,
                   label="SPH (Benz & Asphaug)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_ylim(0.05, 500)
        ax.set_xlabel("run time (s, one thread)")
        ax.set_ylabel(f"error vs experiment (%)")
        ax.set_title(name, fontsize=9)
        ax.grid(alpha=0.3, which="both")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    plt.close(fig)


def plot_damage_vs_radius(runs, out):
    fig, ax = plt.subplots(figsize=(5.5, 3.8))
    for s in runs:
        mid = 0.5 * (s["r_edges_mm"][1:] + s["r_edges_mm"][:-1])
        ax.plot(mid, 100 * s["fail_by_r"], "o-", ms=3, label=label(s))
    ax.set_xlabel("initial distance from the target centre (mm)")
    ax.set_ylabel("failed points at the end (%)")
    ax.set_ylim(0, 100)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    plt.close(fig)


def plot_damage_vs_impact_distance(runs, out):
    fig, axes = plt.subplots(1, 2, figsize=(8.5, 3.5), sharey=True)
    for k, ax in enumerate(axes):
        for j, s in enumerate(runs):
            t_us = sorted(s["fail_by_d"])[k]
            mid = 0.5 * (s["d_edges_mm"][1:] + s["d_edges_mm"][:-1])
            ax.plot(mid, 100 * s["fail_by_d"][t_us], "o-", ms=3, color=f"C{j}", label=label(s))
            ax.set_title(f"t = {t_us} us", fontsize=9)
        ax.axvline(30.0, color="gray", ls=":", lw=0.8)  # the target centre is 30 mm away
        ax.set_xlabel("initial distance from the impact point (mm)")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("failed points (%)")
    axes[0].set_ylim(0, 100)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    plt.close(fig)


def plot_energy(runs, out):
    fig, ax = plt.subplots(figsize=(5.5, 3.5))
    for s in runs:
        ax.plot(s["time_us"], 100 * s["energy_error"], label=label(s))
    ax.axhline(0.6, color="gray", ls="--", lw=0.8, label="MPM paper bound (0.6%)")
    ax.axhline(-0.6, color="gray", ls="--", lw=0.8)
    ax.set_xlabel("time (us)")
    ax.set_ylabel("total energy error (%)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    plt.close(fig)


def plot_cross_sections(runs, out, vmax_speed=10.0):
    fig, axes = plt.subplots(2, len(runs), figsize=(3.1 * len(runs), 5.6), squeeze=False)
    for k, s in enumerate(runs):
        t, c, axis = sp.read_snapshot(sp.snapshots(s["dir"])[-1])
        normal = "xyz"[axis] if axis >= 0 else "z"
        u_name, v_name = [n for n in "xyz" if n != normal]
        layer = np.abs(c[normal]) < s["spacing_mm"] * 1e-3  # the layer next to the plane
        u, v = 1e3 * c[u_name][layer], 1e3 * c[v_name][layer]
        speed = np.sqrt(c["vx"] ** 2 + c["vy"] ** 2 + c["vz"] ** 2)[layer]
        size = 2.0 * (s["spacing_mm"] / 1.2) ** 2
        im = axes[0][k].scatter(u, v, c=c["damage"][layer], s=size, cmap="inferno", vmin=0, vmax=1,
                                rasterized=True)
        axes[0][k].set_title(f"{s['spacing_mm']:.1f} mm, damage, {t * 1e6:.0f} us", fontsize=8)
        im2 = axes[1][k].scatter(u, v, c=speed, s=size, cmap="viridis", vmin=0, vmax=vmax_speed,
                                 rasterized=True)
        axes[1][k].set_title(f"|v| (m/s, clipped at {vmax_speed:g})", fontsize=8)
        for ax in (axes[0][k], axes[1][k]):
            ax.set_aspect("equal")
            ax.set_xlim(-40, 40)
            ax.set_ylim(-40, 40)
            ax.tick_params(labelsize=7)
    fig.colorbar(im, ax=axes[0].tolist(), shrink=0.8)
    fig.colorbar(im2, ax=axes[1].tolist(), shrink=0.8)
    fig.savefig(out, dpi=90)
    plt.close(fig)


def cpu_txt(s):
    return f"{s['cpu_s']:.0f} s" if s["cpu_s"] else "-"


def cpu_rate(s):
    return f"{s['n_run'] * s['steps'] / s['cpu_s']:.3g}" if s["cpu_s"] else "-"


def table(runs):
    head = ("| spacing (cell) | target points (full sphere) | largest fragment m/M | its speed (m/s) | "
            "its centre from target centre | 2nd m/M | fragments | failure 40 us | failure at end | max energy error | steps | "
            "wall time | CPU time | particle-steps/s (wall) | particle-steps/CPU-s |")
    rows = [head, "|" + "---|" * 15]
    for s in runs:
        rows.append(
            f"| {s.get('label') or ''} {s['spacing_mm']:.1f} mm ({s['cell_mm']:.1f} mm) | {s['n_target_full']:,} | "
            f"{s['largest_fraction']:.3f} | {s['largest_speed']:.2f} | {s['largest_offset_mm']:.1f} mm | "
            f"{s['second_fraction']:.3f} | "
            f"{s['fragments']} | {100 * s['failure_40']:.1f}% | {100 * s['failure_end']:.1f}% "
            f"({s['t_end_us']:.0f} us) | {100 * s['max_abs_energy_error']:.2f}% | {s['steps']} | "
            f"{s['wall_s']:.0f} s | {cpu_txt(s)} | {s['pstep_per_s']:.3g} | {cpu_rate(s)} |")
    rows.append(f"| experiment | | {EXPERIMENT[0]} | {EXPERIMENT[1]} | core | | | | | | | | | | |")
    rows.append(f"| SPH (Benz & Asphaug 1994) | | {SPH[0]} | {SPH[1]} | core | | | | | | | | | | |")
    rows.append(f"| MPM paper (0.8 mm) | 230,144 | {MPM_PAPER[0]} | {MPM_PAPER[1]} | core | | | | "
                f"{100 * PAPER_FAILURE_100US:.0f}% (100 us) | < 0.6% | | | | | |")
    return "\n".join(rows) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run_dirs", nargs="+")
    ap.add_argument("--out-dir", default="out/lab-convergence")
    ap.add_argument("--table", help="markdown table (default OUT_DIR/summary.md)")
    ap.add_argument("--labels", nargs="*", help="legend labels, one per RUN_DIR (default: spacing)")
    a = ap.parse_args()
    runs = [summarise(d) for d in a.run_dirs]
    for s, name in zip(runs, a.labels or []):
        s["label"] = name
    runs.sort(key=lambda s: -s["cell_mm"])
    os.makedirs(a.out_dir, exist_ok=True)
    plot_failure(runs, os.path.join(a.out_dir, "failure_ratio.png"))
    plot_error_vs_wall(runs, os.path.join(a.out_dir, "error_vs_walltime.png"))
    plot_damage_vs_radius(runs, os.path.join(a.out_dir, "damage_vs_radius.png"))
    plot_energy(runs, os.path.join(a.out_dir, "energy_error.png"))
    plot_damage_vs_impact_distance(runs, os.path.join(a.out_dir, "damage_vs_impact_distance.png"))
    plot_cross_sections(runs, os.path.join(a.out_dir, "cross_sections.png"))
    text = table(runs)
    with open(a.table or os.path.join(a.out_dir, "summary.md"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
