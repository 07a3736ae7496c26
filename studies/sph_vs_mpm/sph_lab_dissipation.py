#!/usr/bin/python3
"""How much of the laboratory impact's elastic wave energy each method keeps, and the failure
ratio it ends with (docs/validation-sph.md, "Why the methods part").

Usage:
  sph_lab_dissipation.py --off RUN:LABEL [RUN:LABEL ...] --on RUN:LABEL [RUN:LABEL ...]
                         [--rmin 0.01] [--out FILE.png]

--off: runs of scenes/lab-impact.toml with an undamaged target
(--set body.target.damage.weibull_k=1e20) and snapshots every 0.5-2 us. Per snapshot, the
kinetic energy of the target points that started more than --rmin from the impact point
(the body and its elastic waves; the crater's fast ejecta, which carry most of the kinetic
energy and none of the waves, are left out; the same points in every run). Beyond 10 mm the
rock stays elastic (compression < 1.5 GPa against the 3.5 GPa yield), so once the wave is in
(~10 us) this energy only trades with strain energy and what the body receives from the
crater; its decay is numerical dissipation (the artificial viscosity).
--on: runs with damage; their failure ratio against time (timeseries.csv).
Prints the wave kinetic energy at 10, 20, 30, 40 us and its ratio 40 us / 10 us; plots both.
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "tools"))
import shatter_plot as sp  # noqa: E402


def wave_energy(run, rmin):
    files = sp.snapshots(run)
    _, first, axis = sp.read_snapshot(files[0])
    target, _, _, _, imp = sp.impact_geometry(first, axis, sp.scene(run))
    pos0 = np.stack([first["x"], first["y"], first["z"]], 1)
    far = (first["body"].astype(int) == target) & (np.linalg.norm(pos0 - imp, axis=1) > rmin)
    keep = np.sort(first["id"][far].astype(np.int64))
    t_out, e_out = [], []
    for f in files:
        t, c, _ = sp.read_snapshot(f)
        sel = np.isin(c["id"].astype(np.int64), keep)
        v2 = c["vx"][sel] ** 2 + c["vy"][sel] ** 2 + c["vz"][sel] ** 2
        t_out.append(t)
        e_out.append(0.5 * np.sum(c["mass"][sel] * v2))
    return np.array(t_out), np.array(e_out)


def split(arg):
    run, _, label = arg.partition(":")
    return run, label or os.path.basename(run.rstrip("/"))


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--off", nargs="+", default=[])
    ap.add_argument("--on", nargs="+", default=[])
    ap.add_argument("--rmin", type=float, default=0.01)
    ap.add_argument("--out")
    a = ap.parse_args()
    curves_off, curves_on = [], []
    print(f"| undamaged run | kinetic energy (J, half model) of the target points starting "
          f"> {1e3 * a.rmin:g} mm from the impact point at 10 / 20 / 30 / 40 us | 40 us / 10 us |")
    print("|---|---|---|")
    for arg in a.off:
        run, lab = split(arg)
        t, e = wave_energy(run, a.rmin)
        at = [np.interp(x * 1e-6, t, e) if t[-1] >= x * 1e-6 - 1e-9 else np.nan
              for x in (10, 20, 30, 40)]
        print(f"| {lab} | " + " / ".join(f"{v:.1f}" for v in at) + f" | {at[3] / at[0]:.2f} |")
        curves_off.append((lab, t, e))
    print("\n| damaged run | failure ratio at 10 / 12 / 14 / 16 / 18 / 20 / 30 / 40 us |")
    print("|---|---|")
    for arg in a.on:
        run, lab = split(arg)
        d = np.genfromtxt(os.path.join(run, "timeseries.csv"), delimiter=",", names=True)
        t, f = d["time_s"], d["failure_ratio"]
        at = [f"{100 * np.interp(x * 1e-6, t, f):.1f}" if t[-1] >= x * 1e-6 - 1e-9 else "-"
              for x in (10, 12, 14, 16, 18, 20, 30, 40)]
        print(f"| {lab} | " + " / ".join(at) + " |")
        curves_on.append((lab, t, f))
    if a.out:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(11, 4))
        for lab, t, f in curves_on:
            # Defaults solid, variants dashed; SPH blue-ish, MPM red-ish by label.
            ax[0].plot(1e6 * t, 100 * f, label=lab, lw=1.6 if "default" in lab else 1.0,
                       ls="-" if "default" in lab else "--")
        ax[0].set_xlabel("t (us)")
        ax[0].set_ylabel("failure ratio (%)")
        ax[0].set_title("damage on: failed (D >= 0.9)", fontsize=10)
        ax[0].axvspan(12, 20, color="0.9", zorder=0)
        ax[0].legend(fontsize=7)
        for lab, t, e in curves_off:
            ax[1].plot(1e6 * t, e, label=lab, lw=1.2)
        ax[1].set_xlabel("t (us)")
        ax[1].set_ylabel(f"KE of target points > {1e3 * a.rmin:g} mm from impact (J)")
        ax[1].set_title("damage off: elastic wave energy kept", fontsize=10)
        ax[1].legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(a.out, dpi=80)


if __name__ == "__main__":
    main()
