#!/usr/bin/python3
"""Cratering in San Marcos gabbro (Benz & Asphaug 1995 Sec. 5.3, Fig. 6): damage and the
compressional wave speed c_p = sqrt((K + 4 mu (1 - D)/3) / rho0) against distance r from the
impact point, from the last snapshot of runs of scenes/sph/gabbro-crater.toml.

Two gauges, both on the target body only:
  shells: mean D and mean c_p of the points in shells 1 cm thick around the impact point;
  cubes:  the target cut into 1 cm cubes as Ahrens & Rubin (1993) cut theirs; each cube's c_p
          from its points' mean D, plotted at the distance of the cube's centre (the scatter of
          BA95 Fig. 6's laboratory points comes from this kind of gauge).
The transition radius r_50 is where the shell-mean D falls through 0.5 (linear interpolation
from the inside out; BA95: the transition zone is centred near r = 4 cm).

Runs are grouped by --label (one per run directory, e.g. "SPH" "SPH" "MPM"); a group of several
runs (flaw seeds) gives mean +- sample std per shell.

Usage:
  gabbro_crater_profile.py RUN [RUN ...] --label L [L ...] [--plot FILE.png] [--table]
                          [--K 71e9] [--mu 35.9e9] [--rho0 2940] [--impact 0 0 0]
"""

import argparse
import glob
import os
import statistics

import h5py
import numpy as np

SHELL = 0.01  # m
R_MAX = 0.20  # m: shells out to the cube's half width below the impact point and beyond


def last_snapshot(run):
    snaps = sorted(glob.glob(os.path.join(run, "snapshots", "snapshot_*.h5")))
    if not snaps:
        raise SystemExit(f"{run}: no snapshots/snapshot_*.h5")
    return snaps[-1]


def load_target(run, body="target"):
    path = last_snapshot(run)
    with h5py.File(path, "r") as f:
        names = [n.decode() for n in f["names/body"][:]]
        if body not in names:
            raise SystemExit(f"{path}: no body named {body!r} (bodies: {names})")
        p = f["particles"]
        sel = p["body"][:] == names.index(body)
        # Reference positions: damage is mapped where the material started (the experiment's
        # cubes were cut from the final, barely moved target; displacements here are < 1 mm
        # outside the crater).
        x = p["position"][:][sel]
        d = p["damage"][:][sel]
        t = float(f.attrs["time"])
    return x, d, t


def cp_of(d, K, mu, rho0):
    return np.sqrt((K + 4.0 * mu * (1.0 - d) / 3.0) / rho0)


def shells(x, d, impact, K, mu, rho0):
    r = np.linalg.norm(x - impact, axis=1)
    edges = np.arange(0.0, R_MAX + 1e-12, SHELL)
    mid, dm, cpm = [], [], []
    for lo, hi in zip(edges[:-1], edges[1:]):
        s = (r >= lo) & (r < hi)
        if s.sum() == 0:
            continue
        mid.append(0.5 * (lo + hi))
        dm.append(d[s].mean())
        cpm.append(cp_of(d[s], K, mu, rho0).mean())
    return np.array(mid), np.array(dm), np.array(cpm)


def cubes(x, d, impact, K, mu, rho0):
    key = np.floor(x / SHELL).astype(np.int64)
    uniq, inv = np.unique(key, axis=0, return_inverse=True)
    inv = inv.ravel()
    dsum = np.bincount(inv, weights=d)
    cnt = np.bincount(inv)
    dmean = dsum / cnt
    centre = (uniq + 0.5) * SHELL
    # Cubes cut by the symmetry plane z = 0 lie wholly in z > 0 here (the lattice starts there).
    r = np.linalg.norm(centre - impact, axis=1)
    return r, cp_of(dmean, K, mu, rho0)


def r50(mid, dm):
    for i in range(1, len(mid)):
        if dm[i - 1] >= 0.5 > dm[i]:
            return float(mid[i - 1] + (dm[i - 1] - 0.5) / (dm[i - 1] - dm[i]) * (mid[i] - mid[i - 1]))
    return float("nan")


def fmt(vals, f):
    vals = [v for v in vals if v == v]
    if not vals:
        return "-"
    if len(vals) == 1:
        return f.format(vals[0])
    return (f + " ± " + f).format(statistics.mean(vals), statistics.stdev(vals))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--label", nargs="+", required=True)
    ap.add_argument("--plot")
    ap.add_argument("--table", action="store_true")
    ap.add_argument("--K", type=float, default=71.0e9, help="bulk modulus (Tillotson A), Pa")
    ap.add_argument("--mu", type=float, default=35.9e9, help="shear modulus, Pa")
    ap.add_argument("--rho0", type=float, default=2940.0)
    ap.add_argument("--impact", type=float, nargs=3, default=[0.0, 0.0, 0.0])
    args = ap.parse_args()
    if len(args.label) != len(args.runs):
        raise SystemExit("--label needs one label per run")
    impact = np.array(args.impact)
    groups = {}
    for run, lab in zip(args.runs, args.label):
        x, d, t = load_target(run)
        mid, dm, cpm = shells(x, d, impact, args.K, args.mu, args.rho0)
        rc, cpc = cubes(x, d, impact, args.K, args.mu, args.rho0)
        groups.setdefault(lab, []).append(dict(run=run, t=t, mid=mid, dm=dm, cpm=cpm, rc=rc,
                                               cpc=cpc, r50=r50(mid, dm),
                                               failed=float((d >= 0.9).mean()),
                                               n=len(d)))

    cp0 = cp_of(0.0, args.K, args.mu, args.rho0)
    if args.table:
        probe = (0.02, 0.04, 0.06, 0.08, 0.10)
        head = (["method", "runs", "points", "t (us)", "failed (D>=0.9)", "r_50 (cm)"] +
                [f"c_p/c_p0 at {100 * r:g} cm" for r in probe])
        print("| " + " | ".join(head) + " |")
        print("|" + "---|" * len(head))
        for lab, rs in groups.items():
            row = [lab, str(len(rs)), str(rs[0]["n"]), f"{rs[0]['t'] * 1e6:.0f}",
                   fmt([100 * r["failed"] for r in rs], "{:.1f} %"),
                   fmt([100 * r["r50"] for r in rs], "{:.1f}")]
            for pr in probe:
                row.append(fmt([float(np.interp(pr, r["mid"], r["cpm"])) / cp0 for r in rs],
                               "{:.2f}"))
            print("| " + " | ".join(row) + " |")
        print(f"\nc_p0 = {cp0:.0f} m/s (K = {args.K:.3g} Pa, mu = {args.mu:.3g} Pa, "
              f"rho0 = {args.rho0:g} kg/m^3)")

    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
        colours = ["tab:blue", "tab:red", "tab:green", "tab:purple"]
        for (lab, rs), c in zip(groups.items(), colours):
            for i, r in enumerate(rs):
                ax[1].scatter(100 * r["rc"], r["cpc"] / 1000.0, s=3, color=c, alpha=0.15,
                              label=f"{lab}: 1 cm cubes" if i == 0 else None)
            mid = rs[0]["mid"]
            n = min(len(r["mid"]) for r in rs)
            dm = np.array([r["dm"][:n] for r in rs])
            cpm = np.array([r["cpm"][:n] for r in rs])
            lab_n = f"{lab} ({len(rs)} seed{'s' if len(rs) > 1 else ''})"
            ax[0].plot(100 * mid[:n], dm.mean(0), "-o", ms=3, color=c, label=lab_n)
            ax[1].plot(100 * mid[:n], cpm.mean(0) / 1000.0, "-", lw=2, color=c,
                       label=f"{lab_n}: shell mean")
            if len(rs) > 1:
                ax[0].fill_between(100 * mid[:n], dm.min(0), dm.max(0), color=c, alpha=0.2)
        for a in ax:
            a.axvline(4.0, color="k", ls=":", lw=1)
            a.set_xlabel("distance from impact point r (cm)")
            a.set_xlim(0, 20)
        ax[0].set_ylabel("mean damage D in 1 cm shells")
        ax[0].set_ylim(-0.02, 1.02)
        ax[1].set_ylabel("c_p = sqrt((K + 4 mu (1-D)/3)/rho) (km/s)")
        ax[1].axhline(cp0 / 1000.0, color="grey", lw=0.8)
        ax[0].legend(fontsize=8)
        ax[1].legend(fontsize=8, loc="lower right")
        t = next(iter(groups.values()))[0]["t"]
        fig.suptitle(f"San Marcos gabbro, 0.143 g steel at 5.2 km/s (BA95 Sec. 5.3), "
                     f"t = {t * 1e6:.0f} us; dotted: BA95's transition zone r = 4 cm",
                     fontsize=10)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=110)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
