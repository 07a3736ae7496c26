"""Crater size against porosity and friction in r-z (issue 29, "Crater scaling in porous targets").

usage: crater_sweep.py OUT_PREFIX LABEL=RUN_DIR [LABEL=RUN_DIR ...]
       crater_sweep.py --hh R0_OVER_A PHI1 PHI2 PHI3   (the HH2011 readings of the docs)
  LABEL is "phi,friction,U_km_s" (e.g. 0.2,1.5,5); RUN_DIR a run of
  scenes/porosity/crater-porous-basalt.toml. Writes OUT_PREFIX.csv (every snapshot of every run:
  depth, diameter and volume of the cavity), OUT_PREFIX-final.csv (the last snapshot of each run,
  with the growth of the diameter and the depth over the last 5 a/U) and OUT_PREFIX.png.

Crater: the transient cavity as studies/axisymmetric/crater.py measures it (depth below the
pre-impact surface on the axis, diameter where the surface profile crosses z = 0); volume: the
cavity below z = 0 inside that diameter, V = sum over radial bins of 2 pi r h max(0, -top).
Scaling: the strength-regime point-source law of Housen & Holsapple 2011 (Icarus 211, 856; the
form as reproduced by Raducan et al. 2021, arXiv:2105.01474), R (rho/m)^(1/3) = H2 (rho/delta)^((1 - 3 nu)/3) (Y / (rho U^2))^(-mu/2), gives
R ~ U^mu at fixed target and projectile: mu is measured from the pair of impact speeds of a
porosity (mu = ln(D(U1) / D(U2)) / ln(U1 / U2), at the same time in units of a/U).
"""
import csv
import math
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "axisymmetric"))
import crater  # noqa: E402  (studies/axisymmetric/crater.py)


def volume(tops, h, diameter):
    """Cavity volume below z = 0 inside radius diameter/2 (m^3)."""
    r = (np.arange(tops.size) + 0.5) * h
    inside = (r < 0.5 * diameter) & np.isfinite(tops)
    return float(np.sum(2.0 * np.pi * r[inside] * h * np.maximum(0.0, -tops[inside])))


def history(run_dir):
    """[(t_aU, depth/a, diameter/a, volume/a^3)] of every snapshot of run_dir."""
    h, a, speed, z_bottom, r_max = crater.scene_of(run_dir)
    rows = []
    snaps = sorted(os.listdir(os.path.join(run_dir, "snapshots")))
    for name in snaps:
        if not name.endswith(".h5"):
            continue
        with h5py.File(os.path.join(run_dir, "snapshots", name)) as f:
            t = float(f.attrs["time"])
            pos = f["particles/position"][()]
        tops = crater.profile(pos[:, 0], pos[:, 2], h, h / 2.0, z_bottom, r_max)
        d, dia = crater.depth_and_diameter(tops, h)
        v = volume(tops, h, dia) if np.isfinite(dia) else float("nan")
        rows.append((t * speed / a, d / a, dia / a, v / a**3))
    return rows


def main(prefix, specs):
    runs = []
    for spec in specs:
        label, run_dir = spec.split("=", 1)
        phi, fr, u = (float(x) for x in label.split(","))
        runs.append((phi, fr, u, run_dir, history(run_dir)))
    with open(prefix + ".csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["porosity", "friction", "U_km_s", "t_aU", "depth_a", "diameter_a", "volume_a3"])
        for phi, fr, u, _, rows in runs:
            for r in rows:
                w.writerow([phi, fr, u] + [f"{x:.4f}" for x in r])
    with open(prefix + "-final.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["porosity", "friction", "U_km_s", "t_aU", "depth_a", "diameter_a",
                    "volume_a3", "d_depth_last5", "d_diameter_last5"])
        for phi, fr, u, _, rows in runs:
            last = rows[-1]
            back = min(rows, key=lambda r: abs(r[0] - (last[0] - 5.0)))
            w.writerow([phi, fr, u] + [f"{x:.4f}" for x in last] +
                       [f"{last[1] - back[1]:+.4f}", f"{last[2] - back[2]:+.4f}"])
    plot(prefix + ".png", runs)


def plot(path, runs):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(14, 4.2))
    for phi, fr, u, _, rows in runs:
        t = [r[0] for r in rows]
        style = "-" if u == 5.0 else ":"
        lab = f"phi {phi:.0%}, f {fr:g}, {u:g} km/s"
        ax[0].plot(t, [r[2] for r in rows], style, label=lab)
        ax[1].plot(t, [r[1] for r in rows], style, label=lab)
    ax[0].set(xlabel="t (a/U)", ylabel="diameter at z = 0 (a)", title="cavity diameter")
    ax[1].set(xlabel="t (a/U)", ylabel="depth (a)", title="cavity depth")
    ax[0].legend(fontsize=7)
    base = [r for r in runs if r[1] == 1.5 and r[2] == 5.0]
    base.sort()
    if base:
        d0 = base[0][4][-1][2]
        phis = [r[0] for r in base]
        ax[2].plot(phis, [r[4][-1][2] / d0 for r in base], "o-", label="shatter: D / D(0 %)")
        ax[2].plot(phis, [r[4][-1][3] / base[0][4][-1][3] for r in base], "s--",
                   label="shatter: V / V(0 %)")
    ax[2].set(xlabel="porosity", ylabel="relative to the dense target",
              title="at the end time, 5 km/s, friction 1.5")
    ax[2].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


# Housen & Holsapple 2011 Table 3 strength-regime classes as reproduced by Hirata & Ikeya 2021
# (Icarus 364, Table B1) and Cheng et al. 2020 (Icarus 352, Table 3): porosity, mu, H2.
HH2011 = {"rock": (0.0, 0.55, 1.1), "weakly cemented basalt": (0.20, 0.46, 0.38),
          "sand/fly ash": (0.45, 0.40, 0.40), "perlite/sand": (0.60, 0.35, 0.81)}
NU = 0.4


def hh_readings(r0_over_a, phis):
    """R(phi)/R(0) of the HH2011 strength fit, Y fixed by the dense run through the rock class:
    (1) the same Y and H2 at every porosity, the class's mu; (2) the class's H2 as well."""
    mu0, h0 = HH2011["rock"][1], HH2011["rock"][2]
    k = (4.0 * math.pi / 3.0) ** (1.0 / 3.0)  # (rho/m)^(1/3) a for rho = delta
    pi3 = (r0_over_a / (k * h0)) ** (-2.0 / mu0)
    classes = [HH2011["weakly cemented basalt"], HH2011["sand/fly ash"], HH2011["perlite/sand"]]
    out = []
    for phi, (_, mu, h2) in zip(phis, classes):
        same = (1.0 - phi) ** (-1.0 / 3.0 + (1.0 - 3.0 * NU) / 3.0 + mu / 2.0) * pi3 ** (
            -(mu - mu0) / 2.0)
        out.append((phi, mu, same, same * h2 / h0))
    return pi3, out


if __name__ == "__main__":
    if sys.argv[1] == "--hh":  # crater_sweep.py --hh R0_OVER_A PHI1 PHI2 PHI3
        pi3, rows = hh_readings(float(sys.argv[2]), [float(x) for x in sys.argv[3:6]])
        print(f"Y/(rho U^2) from the dense run through the rock fit: {pi3:.3f}")
        for phi, mu, same, own in rows:
            print(f"phi {phi:.2f} mu {mu:.2f}: same Y and H2 {same:.3f}, class H2 {own:.3f}")
        sys.exit(0)
    main(sys.argv[1], sys.argv[2:])
