#!/usr/bin/env python3
"""Write an OpenSPH input (for tools/peers/opensph_labimpact.cpp) with the same particles as a shatter run.

OpenSPH (github.com/pavelsevecek/OpenSPH, Sevecek et al.) is the SPH peer of issue 35. This script reads
one shatter snapshot (positions, velocities, masses, densities and body index of every point) and the
run's resolved scene.toml plus the material catalogue, and writes a plain-text file that the driver
opensph_labimpact.cpp (built against OpenSPH's core library by tools/peers/opensph/CMakeLists.txt,
not part of shatter's build) reads. It is
for the peer speed comparison of docs/performance.md ("Peers (session 22)"); the peer's code, its build
and the input files are not kept in this repository.

What is matched and what is only the nearest OpenSPH offers (the choices; each is also printed):
  * points: the snapshot's positions, velocities and masses, body by body; OpenSPH's h is
    h_factor (m / rho)^(1/3) with shatter's solver.sph.h_factor (default 1.2), as shatter's
    (docs/validation-sph.md "smoothing length"); kernel: the cubic spline with support 2h in both.
  * symmetry plane z (the half model): OpenSPH's SymmetricBoundary duplicates each particle near the
    plane three times and keeps the copy's velocity unreflected (Boundary.cpp, SymmetricBoundary::
    initialize), so it is not a mirror. The default (--mirror) writes the FULL model instead: every
    point and its image z -> -z, vz -> -vz (points on the plane are not doubled). OpenSPH then runs
    twice the points without ghosts while shatter runs the half model with its mirror particles
    (docs/validation-sph.md "boundaries"); rates are per particle-step, energies are halved back.
  * EOS: Tillotson in both, with rho0, A, B, a, b, alpha, beta, E0, Eiv, Ecv of the catalogue.
    OpenSPH takes A from its bulk-modulus key (Eos.cpp TillotsonEos), selects the expanded branch by
    rho <= rho0 and u (shatter's rho_iv has no OpenSPH key) and clamps c^2 >= A / (4 rho0).
  * strength: shatter's linear_hardening Y = yield + plastic_modulus eps_p -> OpenSPH's von Mises
    with the elasticity limit = yield (no hardening: basalt's plastic modulus is 5.3 MPa against a
    3.5 GPa yield; nylon's 2.2 MPa against 10 MPa) and the melt energy set to 1e30 J/kg, so that
    OpenSPH's thermal softening Y (1 - u / u_melt) is off, as shatter has none. Shear modulus
    G = E / (2 (1 + nu)) from the catalogue's E and nu.
  * damage: [body.X.damage] grady_kipp -> OpenSPH's scalar Grady-Kipp with the same Weibull k and m;
    OpenSPH draws its flaws by Benz & Asphaug's sequential assignment (ln N flaws per particle on
    average, its own random numbers); shatter's total_flaws (n_tot) has no OpenSPH key. OpenSPH
    derives Young's modulus for the flaw thresholds from its bulk modulus (= Tillotson A) and G.
  * artificial viscosity: OpenSPH's standard (Monaghan) viscosity with shatter's solver.sph alpha and
    beta (default 1 and 2; OpenSPH's own defaults are 1.5 and 3).
  * integrator and time step: chosen in the driver (--integrator leapfrog: OpenSPH's drift-kick-drift
    with one derivative evaluation per step, rates at the midpoint configuration, as shatter's
    staggered leapfrog; --criterion collision: the Courant (number 0.2, dt = 0.2 h / c) and
    divergence criteria of OpenSPH's own collision presets). dt_initial and dt_max are written here.
  * domain faces: shatter's outflow box has no OpenSPH counterpart here: none (vacuum); no point
    leaves the box in the compared time.

Usage (the snapshot of step 0 of a run, e.g. shatter run SCENE --set solver.end_time=1e-9):
  /usr/bin/python3 tools/peers/opensph_input.py RUN/snapshots/snapshot_000000.h5 \\
      --scene RUN/scene.toml --materials data/materials.toml --end-time 5e-6 -o OUT/lab.osph
"""

import argparse
import math
import sys

import numpy as np

from mpm3d_input import material_table, read_snapshot, read_tomls


def note(msg):
    print("opensph_input: " + msg, file=sys.stderr)


def body_params(name, m, damage):
    if m.get("eos") != "tillotson":
        raise SystemExit(f"material {name}: eos {m.get('eos')!r} has no mapping (tillotson only)")
    if m.get("strength") != "linear_hardening":
        raise SystemExit(f"material {name}: strength {m.get('strength')!r} has no mapping (linear_hardening only)")
    shear = m["young"] / (2.0 * (1.0 + m["poisson"]))
    p = {
        "rho0": m["rho0"],
        "A": m["A"],
        "B": m["B"],
        "a": m["a"],
        "b": m["b"],
        "alpha": m["alpha"],
        "beta": m["beta"],
        "E0": m["E0"],
        "Eiv": m["Eiv"],
        "Ecv": m["Ecv"],
        "shear": shear,
        "yield": m["yield"],
        "melt": 1.0e30,
        "damage": 0,
    }
    note(
        f"{name}: Tillotson as catalogued (rho_iv {m.get('rho_iv')} dropped); von Mises Y = {m['yield']:.4g} Pa "
        f"(plastic modulus {m.get('plastic_modulus', 0):.4g} Pa dropped), G = {shear:.4g} Pa, melt softening off"
    )
    if damage:
        if damage.get("model") != "grady_kipp":
            raise SystemExit(f"damage model {damage.get('model')!r} has no mapping (grady_kipp only)")
        p.update(damage=1, weibull_k=damage["weibull_k"], weibull_m=damage["weibull_m"])
        note(
            f"{name}: scalar Grady-Kipp, k = {damage['weibull_k']:.4g}, m = {damage['weibull_m']}; "
            f"total_flaws {damage.get('total_flaws')} dropped (OpenSPH assigns its own flaws)"
        )
    return p


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("snapshot")
    ap.add_argument("--scene", required=True, help="the run's resolved scene.toml")
    ap.add_argument("--materials", required=True, help="data/materials.toml")
    ap.add_argument("--end-time", type=float, required=True)
    ap.add_argument("--dt-initial", type=float, default=1.0e-9)
    ap.add_argument("--dt-max", type=float, default=1.0e-7)
    ap.add_argument("--no-mirror", action="store_true", help="write the half model only (no z images)")
    ap.add_argument("-o", "--output", required=True)
    args = ap.parse_args()

    scene, materials = read_tomls(args.scene, args.materials)
    solver = scene["solver"]
    sph = solver.get("sph", {})
    h_factor = sph.get("h_factor", 1.2)
    alpha = sph.get("alpha", 1.0)
    beta = sph.get("beta", 2.0)
    if sph.get("viscosity_switch", "none") != "none" or sph.get("continuity", "standard") != "standard":
        raise SystemExit("only the default continuity and no viscosity switch are mapped")
    mirror = solver.get("symmetry_plane", "none") == "z" and not args.no_mirror
    if solver.get("symmetry_plane", "none") not in ("none", "z"):
        raise SystemExit("only a z symmetry plane is mapped")

    x, v, m, rho, body, names, time = read_snapshot(args.snapshot)
    if time != 0.0:
        note(f"warning: snapshot time {time} s, not 0")

    lines = [
        "# OpenSPH input written by tools/peers/opensph_input.py",
        f"# snapshot {args.snapshot}, scene {args.scene}, mirror {mirror}",
        f"end_time {args.end_time!r}",
        f"h_factor {h_factor!r}",
        f"av_alpha {alpha!r}",
        f"av_beta {beta!r}",
        f"dt_initial {args.dt_initial!r}",
        f"dt_max {args.dt_max!r}",
    ]
    total = 0
    for b, name in enumerate(names):
        sel = body == b
        if not sel.any():
            continue
        mat_name, mat = material_table(scene, materials, name)
        params = body_params(f"{name} ({mat_name})", mat, scene["body"][name].get("damage"))
        bx, bv, bm, brho = x[sel], v[sel], m[sel], rho[sel]
        if mirror:
            off = bx[:, 2] > 0.0
            ix = bx[off].copy()
            ix[:, 2] *= -1.0
            iv = bv[off].copy()
            iv[:, 2] *= -1.0
            on_plane = int((~off).sum())
            if on_plane:
                note(f"{name}: {on_plane} points on z = 0 are not doubled")
            bx = np.concatenate([bx, ix])
            bv = np.concatenate([bv, iv])
            bm = np.concatenate([bm, bm[off]])
            brho = np.concatenate([brho, brho[off]])
        n = len(bm)
        total += n
        h = h_factor * np.cbrt(bm / brho)
        note(f"{name}: {n} points, h {h.min():.4g}-{h.max():.4g} m, mass {bm.sum():.6g} kg")
        lines.append(f"body {name} n {n} " + " ".join(f"{k} {val!r}" for k, val in params.items()))
        cols = np.column_stack([bx, bv, bm, brho])
        lines.extend(" ".join(repr(float(c)) for c in row) for row in cols)
    with open(args.output, "w") as f:
        f.write("\n".join(lines) + "\n")
    ke = 0.5 * float((m * (v**2).sum(axis=1)).sum())
    note(
        f"wrote {args.output}: {total} points; kinetic energy of the snapshot {ke:.6g} J "
        f"({'the full model has twice this' if mirror else 'half model'}); h_factor {h_factor}, "
        f"alpha {alpha}, beta {beta}"
    )
    if math.isnan(ke):
        raise SystemExit("NaN in the snapshot")


if __name__ == "__main__":
    main()
