"""Gravity-regime crater scaling in r-z (issue 29; docs/validation-porosity.md, "Session 17:
gravity-regime crater scaling").

usage: gravity_scaling.py OUT_PREFIX LABEL=RUN_DIR [LABEL=RUN_DIR ...]
  LABEL is "porosity,pi2,cppr,series" (e.g. 0.35,1e-3,5,L); RUN_DIR a run of
  scenes/porosity/gravity-crater.toml; series names the target material (a g = 0 run calibrates
  the two-term form of its own series and porosity). Writes OUT_PREFIX.csv (every snapshot: time, depth,
  diameter, volume, pi_V, cumulative ejected mass), OUT_PREFIX-table.csv (per run: the crater at
  its largest volume, at the end of ejection and at the end of the run, their pi_V against the
  fits) and OUT_PREFIX.png.

Crater: the cavity as studies/axisymmetric/crater.py measures it (depth below the pre-impact
surface z = 0 on the axis; diameter where the surface profile, walked out from the axis, crosses
z = 0) and its volume below z = 0 inside that diameter (crater_sweep.volume). The transient
crater is the snapshot of largest volume (the end of growth: after it the cavity shallows and
the volume falls); "final" is the last snapshot. The largest volume is the transient crater of
the iSALE scaling studies (Elbeshausen, Wuennemann & Collins 2009, Icarus 204, and those after
it, as recalled: their text was not found by this session's searches, only their abstracts).
End of excavation (session 19): the Earth Impact Effects Program's glossary (Collins, Melosh &
Marcus 2005, MAPS 40; http://impact.ese.ic.ac.uk/ImpactEffects/craterglos.html, entry
"Transient Crater"; the page of Melosh's crater-size program,
scientificpsychic.com/etc/timeline/projectile-size.html, has the same entry) defines the transient crater as the
cavity at the moment excavation ends, before collapse and modification begin, and says that the
laboratory-derived scaling relations are for that cavity, not for the collapsed one.
Excavation is the flow that throws target material out of the cavity, so its end is taken here
as the end of ejection: M_ej(t) is the cumulative mass of target points that have been seen, at
some snapshot up to t, higher than Z_EJECT = 0.5 a above the pre-impact surface and rising
(v_z > 0), each point counted once by its id (points that leave through the outflow top keep
counting; the projectile's points are not counted). The height keeps the heave of the free
surface around the crater (a few cells) out; 0.25 a and 1 a are reported as a sensitivity.
t_ex is the first snapshot with M_ej >= 0.98 M_ej(last snapshot); the ejection counts as ended
only where t_ex is at least 10 a/U before the run's end (else "ejection_ended" is False and
t_ex is a lower bound). The cavity volume at t_ex gives pi_V at the end of excavation. The
height and the 98 % are this script's choices (no source found gives a rule for snapshots).
Scaling (point source; Holsapple 1993, Annu. Rev. Earth Planet. Sci. 21, 333; the form with the
density ratio of Holsapple & Housen 2007 / Housen & Holsapple 2011, nu = 0.4):
  pi_V = rho V / m = K1 [pi_2 (rho/delta)^((6 nu - 2 - mu)/(3 mu))]^(-3 mu / (2 + mu)),
  pi_2 = 3.22 g a / U^2,
dry sand K1 = 0.24, mu = 0.41 (Holsapple 1993: pi_V = 0.24 pi_2^-0.51; = K1 0.132 of the
g a / U^2 form, 0.132 x 3.22^0.51 = 0.24) and the non-porous class (water, wet soils, rock in
the gravity regime) K1 = 0.2, mu = 0.55 (pi_V = 0.2 pi_2^-0.65; K1 0.095 of the other form).
The g a / U^2 constants (dry sand 0.132 / 0.41; wet soils, soft and hard rock 0.095 / 0.55) are
those of Holsapple's crater-size spreadsheet notes ("Notes on Crater Scaling Results", after
Holsapple 1993 and Schmidt & Housen 1987), read in session 18 (docs/validation-porosity.md).
rho is the target's bulk density, delta and m the projectile's density and mass. rho is taken at
rest, rho_s0 (1 - porosity): the density of the free surface; a porous target whose lithostatic
start puts it on its crush curve (session 20) is denser below (its own figures in
docs/validation-porosity.md, "Session 20").
Runs at g = 0 (LABEL pi2 = 0) give the crater without gravity; with them, the fit's two-term
(gravity-strength transition) form of Holsapple 1993 / Holsapple & Housen 2007,
  pi_V = K1 [pi_2 (rho/delta)^((6 nu - 2 - mu)/(3 mu)) + S]^(-3 mu / (2 + mu)),
is also evaluated, S (the strength term, (K2 pi_3)^((2 + mu)/2) for a cohesive target) fixed by
the g = 0 run of the same porosity: pi_V(g = 0) = K1 S^(-3 mu / (2 + mu)).
"""
import csv
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import crater_sweep  # noqa: E402  (history: depth, diameter, volume of every snapshot)

Z_EJECT = 0.5  # a: the height above the pre-impact surface that counts a point as ejected
EX_FRACTION = 0.98  # end of ejection: M_ej reaches this fraction of its last value
RHO_MATRIX = 2700.0  # kg/m^3: granular_basalt's matrix (scenes/porosity/materials.toml)
RHO_PROJ = 2700.0  # kg/m^3: the basalt projectile
NU = 0.4
FITS = {"dry sand (K1 0.24, mu 0.41)": (0.24, 0.41),
        "non-porous (K1 0.2, mu 0.55)": (0.2, 0.55)}


def ejection(run_dir, heights=(Z_EJECT, 0.25, 1.0)):
    """{height: [(t_aU, M_ej / m)]}: cumulative ejected target mass over the projectile's mass."""
    import glob
    import h5py
    h, a, speed, _, _ = crater_sweep.crater.scene_of(run_dir)
    seen = {z: {} for z in heights}
    out = {z: [] for z in heights}
    m_proj = None
    for snap in sorted(glob.glob(os.path.join(run_dir, "snapshots", "*.h5"))):
        with h5py.File(snap) as f:
            t = float(f.attrs["time"]) * speed / a
            names = [n.decode() if isinstance(n, bytes) else n for n in f["names/body"][()]]
            body = f["particles/body"][()]
            mass = f["particles/mass"][()]
            if m_proj is None:
                m_proj = float(mass[body == names.index("projectile")].sum())
            tgt = body == names.index("target")
            z = f["particles/position"][()][tgt, 2]
            vz = f["particles/velocity"][()][tgt, 2]
            ids = f["particles/id"][()][tgt]
            mass = mass[tgt]
        for zh in heights:
            sel = (z > zh * a) & (vz > 0.0)
            seen[zh].update(zip(ids[sel].tolist(), mass[sel].tolist()))
            out[zh].append((t, sum(seen[zh].values()) / m_proj))
    return out


def end_of_ejection(ej):
    """(t_ex, ended) from [(t, M_ej)]: first time M_ej >= EX_FRACTION of its last value."""
    last_t, last = ej[-1]
    t_ex = next(t for t, mej in ej if mej >= EX_FRACTION * last)
    return t_ex, (last > 0.0 and t_ex <= last_t - 10.0)


def pi_v_fit(k1, mu, pi2, rho_ratio):
    """Holsapple's gravity-regime pi_V at pi_2 and rho/delta."""
    inner = pi2 * rho_ratio ** ((6.0 * NU - 2.0 - mu) / (3.0 * mu))
    return k1 * inner ** (-3.0 * mu / (2.0 + mu))


def strength_term(k1, mu, pi_v0):
    """S of the two-term form from the crater at g = 0."""
    return (pi_v0 / k1) ** (-(2.0 + mu) / (3.0 * mu))


def pi_v_two_term(k1, mu, pi2, rho_ratio, S):
    inner = pi2 * rho_ratio ** ((6.0 * NU - 2.0 - mu) / (3.0 * mu)) + S
    return k1 * inner ** (-3.0 * mu / (2.0 + mu))


def fit_for(phi):
    """The fit a porosity is compared with: dry sand (35 %) for porous targets, else non-porous."""
    return "dry sand (K1 0.24, mu 0.41)" if phi > 0.3 else (
        "non-porous (K1 0.2, mu 0.55)" if phi == 0.0 else None)


def main(prefix, specs):
    runs = []
    for spec in specs:
        label, run_dir = spec.split("=", 1)
        phi, pi2, cppr, series = label.split(",")
        runs.append((float(phi), float(pi2), int(cppr), run_dir, crater_sweep.history(run_dir),
                     series, ejection(run_dir)))
    m_over_a3 = 4.0 / 3.0 * math.pi * RHO_PROJ  # projectile mass / a^3
    with open(prefix + ".csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["series", "porosity", "pi2", "cppr", "t_aU", "depth_a", "diameter_a",
                    "volume_a3", "pi_V", "M_ej_over_m"])
        for phi, pi2, cppr, _, hist, series, ej in runs:
            rho = RHO_MATRIX * (1.0 - phi)
            for (t, d, dia, v), (_, mej) in zip(hist, ej[Z_EJECT]):
                w.writerow([series, phi, pi2, cppr, f"{t:.2f}", f"{d:.4f}", f"{dia:.4f}", f"{v:.3f}",
                            f"{rho * v / m_over_a3:.4f}", f"{mej:.4f}"])
    table = []
    pi_v0 = {}  # (series, porosity, cppr) -> pi_V of the g = 0 crater (transient)
    for phi, pi2, cppr, run_dir, hist, series, _ in runs:
        if pi2 == 0.0:
            ok = [r for r in hist if np.isfinite(r[3])]
            pi_v0[(series, phi, cppr)] = RHO_MATRIX * (1.0 - phi) * max(r[3] for r in ok) / m_over_a3
    for phi, pi2, cppr, run_dir, hist, series, ej in runs:
        rho = RHO_MATRIX * (1.0 - phi)
        ok = [r for r in hist if np.isfinite(r[3])]
        tr = max(ok, key=lambda r: r[3])
        fin = ok[-1]
        t_ex, ended = end_of_ejection(ej[Z_EJECT])
        ex = min(ok, key=lambda r: abs(r[0] - t_ex))
        pv, pv_fin = rho * tr[3] / m_over_a3, rho * fin[3] / m_over_a3
        pv_ex = rho * ex[3] / m_over_a3
        row = {"series": series, "porosity": phi, "pi2": pi2, "cppr": cppr, "t_transient_aU": tr[0],
               "depth_a": tr[1], "diameter_a": tr[2], "volume_a3": tr[3], "pi_V": pv,
               "t_final_aU": fin[0], "diameter_final_a": fin[2], "pi_V_final": pv_fin,
               "t_ex_aU": t_ex, "ejection_ended": ended, "depth_ex_a": ex[1],
               "diameter_ex_a": ex[2], "volume_ex_a3": ex[3], "pi_V_ex": pv_ex,
               "M_ej_over_m": ej[Z_EJECT][-1][1]}
        for zh in sorted(ej):
            if zh != Z_EJECT:
                row[f"t_ex_aU_at_{zh:g}a"] = end_of_ejection(ej[zh])[0]
        for name, (k1, mu) in FITS.items():
            key = "sand" if "sand" in name else "nonporous"
            if pi2 > 0.0:
                fit = pi_v_fit(k1, mu, pi2, rho / RHO_PROJ)
                row["fit_" + key] = fit
                row["ratio_" + key] = pv / fit
                row["ratio_final_" + key] = pv_fin / fit
                row["ratio_ex_" + key] = pv_ex / fit
            else:
                row["fit_" + key] = row["ratio_" + key] = row["ratio_final_" + key] = math.nan
                row["ratio_ex_" + key] = math.nan
            if (series, phi, cppr) in pi_v0:
                S = strength_term(k1, mu, pi_v0[(series, phi, cppr)])
                two = pi_v_two_term(k1, mu, pi2, rho / RHO_PROJ, S)
                row["two_term_" + key] = two
                row["ratio_two_term_" + key] = pv / two
            else:
                row["two_term_" + key] = row["ratio_two_term_" + key] = math.nan
        table.append(row)
    with open(prefix + "-table.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(table[0].keys()))
        w.writeheader()
        for row in table:
            w.writerow({k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in row.items()})
    for row in table:
        print(", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}"
                        for k, v in row.items()))
    plot(prefix, runs, table)


def plot(prefix, runs, table):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    with_ejection = any("t_ex_aU" in r for r in table)
    fig, axes = plt.subplots(1, 3 if with_ejection else 2, figsize=(16 if with_ejection else 11, 4.8))
    ax, bx = axes[0], axes[1]
    p2 = np.logspace(-4, -2, 50)
    for (name, (k1, mu)), ls in zip(FITS.items(), ["-", "--"]):
        for phi, col in ((0.35, "C1"), (0.0, "C0")):
            if fit_for(phi) == name:
                rho = RHO_MATRIX * (1.0 - phi)
                ax.plot(p2, pi_v_fit(k1, mu, p2, rho / RHO_PROJ), ls, color=col, label=name)
    colours = {0.0: "C0", 0.2: "C2", 0.35: "C1"}
    for phi, col in ((0.35, "C1"), (0.0, "C0")):
        for name, (k1, mu) in FITS.items():
            if fit_for(phi) != name:
                continue
            # The two-term form with S from the g = 0 run of the first series given (series L
            # at 5 CPPR in session 17's figure), where that run stopped growing.
            g0 = [r for r in table if r["pi2"] == 0.0 and r["porosity"] == phi]
            if g0:
                rho = RHO_MATRIX * (1.0 - phi)
                S = strength_term(k1, mu, g0[0]["pi_V"])
                ax.plot(p2, pi_v_two_term(k1, mu, p2, rho / RHO_PROJ, S), ":", color=col,
                        label=name.split(" (")[0] + f" two-term, S from series {g0[0]['series']}'s"
                        f" g = 0 run ({g0[0]['cppr']} CPPR)")
    markers = {"L": "o", "Lp": "^", "D": "s", "LT": "D", "LS": "v", "LSu1": "X"}
    # session 20's series in their own colours with CURVES_OF = "all": LS (sand crush curve) red,
    # LSu1 (the same at U = 1 km/s) green
    series_colour = {"LS": "C3", "LSu1": "C2"} if os.environ.get("CURVES_OF") == "all" else {}
    for row in table:
        if row["pi2"] == 0.0:
            continue
        c = series_colour.get(row["series"], colours.get(row["porosity"], "k"))
        mk = markers.get(row["series"], "x")
        ms = {5: 6, 10: 9}.get(row["cppr"], 13)
        # a 20 CPPR point sits at the same pi_2 as its 10 CPPR one: shift it a little right
        x = row["pi2"] * (1.08 if row["cppr"] >= 20 else 1.0)
        ax.plot(x, row["pi_V"], mk, color=c, ms=ms)
        ax.plot(x, row["pi_V_final"], mk, color=c, mfc="none", ms=ms)
        if "pi_V_ex" in row:
            ax.plot(x, row["pi_V_ex"], mk, color=c, fillstyle="left", ms=ms)
    for phi, c in colours.items():
        if any(r["porosity"] == phi for r in table):
            ax.plot([], [], "o", color=c, label=f"porosity {phi:.0%}")
    for sname, mk in markers.items():
        if not any(r["series"] == sname for r in table):
            continue
        ax.plot([], [], mk, color="grey",
                label=f"series {sname}: filled largest volume, "
                + ("half end of ejection, " if with_ejection else "") + "open final")
    ax.plot([], [], "o", color="grey", ms=9, label="small: 5, large: 10, largest: 20 CPPR")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("pi_2 = 3.22 g a / U^2")
    ax.set_ylabel("pi_V = rho V / m")
    ax.legend(fontsize=6.5)
    ax.grid(True, which="both", alpha=0.3)
    # The growth curves of the first series given, and every g = 0 run; with CURVES_OF = "all"
    # (environment) those of every series.
    main_series = runs[0][5]
    every = os.environ.get("CURVES_OF") == "all"
    rows = {(r["series"], r["porosity"], r["pi2"], r["cppr"]): r for r in table}
    for phi, pi2, cppr, _, hist, series, ej in runs:
        if series != main_series and pi2 != 0.0 and not every:
            continue
        h = np.array([r for r in hist if np.isfinite(r[3])])
        ls = {0.0: (0, (1, 1)), 3e-4: ":", 1e-3: "--", 3e-3: "-"}.get(pi2, "-.")
        lw = {5: 1.0, 10: 1.6}.get(cppr, 2.6)
        col = series_colour.get(series, colours.get(phi, "k"))
        label = f"{series} {phi:.0%}, pi_2 {pi2:g}, {cppr} CPPR"
        bx.plot(h[:, 0], h[:, 3], linestyle=ls, color=col, lw=lw, label=label)
        row = rows[(series, phi, pi2, cppr)]
        bx.plot(row["t_transient_aU"], row["volume_a3"], "o", color=col, ms=5)
        if with_ejection:
            bx.plot(row["t_ex_aU"], row["volume_ex_a3"], "x", color=col, ms=8, mew=2)
            e = np.array(ej[Z_EJECT])
            axes[2].plot(e[:, 0], e[:, 1], linestyle=ls, color=col, lw=lw, label=label)
            axes[2].plot(row["t_ex_aU"], np.interp(row["t_ex_aU"], e[:, 0], e[:, 1]), "x",
                         color=col, ms=8, mew=2)
    bx.plot([], [], "o", color="grey", ms=5, label="largest volume")
    if with_ejection:
        bx.plot([], [], "x", color="grey", ms=8, mew=2, label="end of ejection (98 % of M_ej)")
    bx.set_xlabel("t (a/U)")
    bx.set_ylabel("cavity volume below z = 0 (a^3)")
    bx.legend(fontsize=6)
    bx.grid(True, alpha=0.3)
    if with_ejection:
        axes[2].set_xlabel("t (a/U)")
        axes[2].set_ylabel(f"M_ej / m: target mass seen > {Z_EJECT:g} a above z = 0, rising")
        axes[2].legend(fontsize=6)
        axes[2].grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(prefix + ".png", dpi=110)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2:])
