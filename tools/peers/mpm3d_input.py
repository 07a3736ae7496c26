#!/usr/bin/env python3
"""Write an MPM3D-F90 input file (.mpm) for the same particles as a shatter run.

MPM3D-F90 (github.com/xzhang66/MPM3D-F90) is the public base code of the MPM paper. This script
reads one shatter snapshot (positions, velocities, masses, densities and body index of every point)
and the run's scene.toml (cell size, domain, symmetry plane, viscosity, the bodies' materials)
plus the material catalogue, and writes the points as MPM3D-F90 "Particle point" bodies with
the same grid. It is for the peer speed comparison of docs/performance.md ("Peers"); the peer's
code and input files are not kept in this repository.

What is matched and what is only the nearest MPM3D-F90 offers (each printed to stderr):
  * points: one MPM3D-F90 body per shatter body, same order, positions, masses and velocities
    (a body's common velocity as "velo body", otherwise one "velo node" line per point);
    MPM3D-F90 takes the volume as mass / density (DataIn.f90, Initial), the density written is
    the body's snapshot density, so the volumes are shatter's.
  * grid: the same cell size and the scene's domain box (or --margin cells around the points),
    in MPM3D-F90 units mm, g, ms, N, MPa; shape "gimp" = uGIMP with the particle half-width of
    a quarter cell (Grid.f90, NShape_GIMP), which is shatter's ugimp at 2 points per cell;
    27 nodes per point in both.
  * a symmetry plane at lo (and slip or symmetry faces) -> "fixed" code 2 on that face: the
    normal grid velocity zeroed (Grid.f90 SetGridData; with gimp on the two outer node layers);
    code 1 clamps all three components (with gimp on two layers) and is written only for
    shatter's "fixed" faces. shatter's outflow faces have no MPM3D-F90 counterpart: free.
  * strength: shatter's linear_hardening (Y = yield + plastic_modulus * eps_p) -> "sjc"
    (simplified Johnson-Cook, Constitution.f90 M3DM5) with A = yield, B = plastic_modulus,
    n = 1, C = 0: the same yield law. Damage is not written (the compared run has none).
  * EOS: shatter's Tillotson -> the nearest MPM3D-F90 EOS, Mie-Grueneisen ("seos m 2"), with
    rho0 c0^2 = A (c0 = sqrt(A / rho0)), C2 = rho0 c0^2 (2 s - 1) = B (s = (B / A + 1) / 2) and
    gamma0 = a + b (Tillotson's compressed branch at low energy: p = A mu + B mu^2 + (a + b)
    rho E); MPM3D-F90's cubic term C3 = A (s - 1)(3 s - 1) has no Tillotson counterpart.
  * artificial viscosity: "bulk bq1 bq2" with bq1 = shatter's quadratic and bq2 = its linear
    coefficient: both codes use q = rho (c_Q (h d)^2 + c_L c h d) for compression
    (Constitution.f90 bulkq; docs/materials.md "Artificial viscosity").
  * time step: MPM3D-F90 uses dt = dtscale * h / (c_elastic + max |v|) (update_step.f90
    UpdateDT); --dtscale sets it (choose it to match shatter's dt, see docs/performance.md).

Usage (the snapshot of step 0 of a run, e.g. shatter run SCENE --set solver.end_time=1e-9):
  /usr/bin/python3 tools/peers/mpm3d_input.py RUN/snapshots/snapshot_000000.h5 \
      --scene RUN/scene.toml --materials data/materials.toml --end-time 5e-6 --dtscale 0.3 \
      -o OUT/lab.mpm
"""

import argparse
import sys
import tomllib

import h5py
import numpy as np

# shatter SI -> MPM3D-F90 units (mm, g, ms; N, MPa): length, mass, time, density, stress, speed
L = 1.0e3
M = 1.0e3
T = 1.0e3
RHO = M / L**3  # kg/m^3 -> g/mm^3
P = 1.0e-6  # Pa -> MPa
V = L / T  # m/s -> mm/ms (= 1)


def note(msg):
    print("mpm3d_input: " + msg, file=sys.stderr)


def read_tomls(*paths):
    """The parsed TOML files (a scene, the material catalogue)."""
    out = []
    for path in paths:
        with open(path, "rb") as f:
            out.append(tomllib.load(f))
    return out


def read_snapshot(path):
    """Positions, velocities, masses, densities, body indices, body names and time of a snapshot."""
    with h5py.File(path, "r") as f:
        pts = f["particles"]
        cols = [pts[c][...] for c in ("position", "velocity", "mass", "rho", "body")]
        names = [n.decode() for n in f["names/body"][...]]
        return (*cols, names, float(f.attrs["time"]))


def material_table(scene, materials, body):
    spec = scene["body"][body]["material"]
    if isinstance(spec, str):
        base = dict(materials[spec])
        name = spec
    else:
        name = spec.get("name")
        base = dict(materials[name]) if name else {}
        base.update({k: v for k, v in spec.items() if k != "name"})
    return name, base


def mpm3d_material(index, name, m, rho0_snapshot):
    eos = m.get("eos")
    strength = m.get("strength")
    if strength != "linear_hardening":
        raise SystemExit(f"material {name}: strength {strength!r} has no mapping (linear_hardening only)")
    if eos != "tillotson":
        raise SystemExit(f"material {name}: eos {eos!r} has no mapping (tillotson only)")
    rho0 = float(m["rho0"])
    A = float(m["A"])
    B = float(m["B"])
    c0 = np.sqrt(A / rho0)
    s = 0.5 * (B / A + 1.0)
    gamma0 = float(m["a"]) + float(m["b"])
    note(
        f"material {index} ({name}): sjc A={m['yield'] * P:g} MPa B={m['plastic_modulus'] * P:g} MPa n=1 C=0; "
        f"Mie-Grueneisen c0={c0:.1f} m/s s={s:.4f} gamma0={gamma0:g} (Tillotson A={A:g} B={B:g} a+b={gamma0:g}); "
        f"density {rho0_snapshot:g} kg/m^3 (snapshot)"
    )
    line = (
        f"  {index}  sjc  {rho0_snapshot * RHO:.9e}  {float(m['young']) * P:.9e}  {float(m['poisson']):.6f}"
        f"  {float(m['yield']) * P:.9e}  {float(m['plastic_modulus']) * P:.9e}  1.0  0.0  1.0"
    )
    seos = f"seos {index} 2 {c0 * V:.9e} {s:.9e} {gamma0:.9e} 0.0"
    return line, seos


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("snapshot", help="shatter snapshot (HDF5) with the initial points")
    ap.add_argument("--scene", required=True, help="the run's scene.toml (run directory)")
    ap.add_argument("--materials", required=True, help="material catalogue (data/materials.toml)")
    ap.add_argument("--end-time", type=float, required=True, help="simulated time, s")
    ap.add_argument("--dtscale", type=float, default=0.3, help="MPM3D-F90 dtscale (default 0.3)")
    ap.add_argument("--margin", type=int, default=-1,
                    help="grid = the points' box plus this many cells (default: the scene's domain)")
    ap.add_argument("--usf", action="store_true", help="USF instead of MUSL (default MUSL, as shatter)")
    ap.add_argument("-o", "--output", required=True, help="the .mpm file to write")
    a = ap.parse_args()

    scene, materials = read_tomls(a.scene, a.materials)
    solver = scene["solver"]
    if solver.get("method", "mpm") != "mpm":
        raise SystemExit("an MPM scene is needed")
    if solver.get("shape", "ugimp") != "ugimp":
        note(f"shatter shape {solver.get('shape')!r}: MPM3D-F90 gets gimp (uGIMP) anyway")
    h = float(solver["cell_size"])

    x, v, mass, rho, body, body_names, time = read_snapshot(a.snapshot)
    n = len(mass)
    if time != 0.0:
        note(f"snapshot time {time:g} s is not 0: its state (stress, energy) is not carried over")
    order = np.argsort(body, kind="stable")  # MPM3D-F90 bodies are contiguous ranges of points
    x, v, mass, rho, body = x[order], v[order], mass[order], rho[order], body[order]

    # grid
    if a.margin >= 0:
        # on shatter's grid lines (nodes at domain.lo + k h), so the shape functions are the same
        dlo = np.array(scene["domain"]["lo"], dtype=float)
        dhi = np.array(scene["domain"]["hi"], dtype=float)
        lo = dlo + np.floor((x.min(axis=0) - a.margin * h - dlo) / h) * h
        hi = x.max(axis=0) + a.margin * h
        lo, hi = np.maximum(lo, dlo), np.minimum(hi, dhi)
    else:
        lo = np.array(scene["domain"]["lo"], dtype=float)
        hi = np.array(scene["domain"]["hi"], dtype=float)
    cells = np.ceil((hi - lo) / h - 1e-9).astype(int)
    hi = lo + cells * h
    note(f"grid {cells[0]} x {cells[1]} x {cells[2]} cells of {h * L:g} mm "
         f"({np.prod(cells + 1)} nodes), box {lo * L} .. {hi * L} mm")

    fixed = [0] * 6
    plane = solver.get("symmetry_plane", "none")
    if plane != "none":
        fixed[2 * "xyz".index(plane)] = 2
        note(f"symmetry plane {plane} = lo -> fixed code 2 (normal velocity zero) on that face")
    dom = scene.get("domain", {})
    for k, face in enumerate(["x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi"]):
        kind = dom.get(face, dom.get("boundary", "none"))
        if kind == "fixed":
            fixed[k] = 1
        elif kind in ("slip", "symmetry"):
            fixed[k] = 2
        elif kind == "outflow":
            pass  # no counterpart: free

    visc = solver.get("viscosity", {})
    cq = float(visc.get("quadratic", 2.25))
    cl = float(visc.get("linear", 0.06))

    bodies = sorted(set(body.tolist()))
    mat_lines, eos_lines = [], []
    body_mat = {}
    for i, b in enumerate(bodies, start=1):
        name = body_names[b]
        mname, m = material_table(scene, materials, name)
        rho_b = rho[body == b]
        if np.ptp(rho_b) > 1e-9 * rho_b.mean():
            note(f"body {name}: density varies ({rho_b.min():g}..{rho_b.max():g}); the mean is written")
        line, seos = mpm3d_material(i, mname, m, float(rho_b.mean()))
        mat_lines.append(line)
        eos_lines.append(seos)
        body_mat[b] = i

    out = []
    w = out.append
    w(f"mpm3d *** shatter points ({a.snapshot}), written by tools/peers/mpm3d_input.py")
    w("! Unit: mm g N ms MPa")
    w("nbco 1")
    w(f"nbbo {len(bodies)}")
    w(f"nbmp {n}")
    w(f"nmat {len(bodies)}")
    w(f"spx {lo[0] * L:.9e} {hi[0] * L:.9e}")
    w(f"spy {lo[1] * L:.9e} {hi[1] * L:.9e}")
    w(f"spz {lo[2] * L:.9e} {hi[2] * L:.9e}")
    w(f"dcell {h * L:.9e}")
    w("gimp")
    w("usf on" if a.usf else "musl on")
    w("jaum on")
    w(f"bulk {cq:.9e} {cl:.9e}")
    w(f"dtscale {a.dtscale:.9e}")
    w(f"endtime {a.end_time * T:.9e}")
    w(f"outtime {10 * a.end_time * T:.9e}")
    w(f"rpttime {10 * a.end_time * T:.9e}")
    w("fixed " + " ".join(str(f) for f in fixed))
    w("material")
    out.extend(mat_lines)
    out.extend(eos_lines)
    pid = 0
    for b in bodies:
        sel = np.nonzero(body == b)[0]
        w(f"Particle point 1 {len(sel)}")
        mid = body_mat[b]
        for p in sel:
            pid += 1
            w(f"{pid} {mid} {mass[p] * M:.12e} {x[p, 0] * L:.12e} {x[p, 1] * L:.12e} {x[p, 2] * L:.12e}")
    w("velo")
    pid = 0
    for i, b in enumerate(bodies, start=1):
        sel = np.nonzero(body == b)[0]
        vb = v[sel]
        if np.all(vb == vb[0]):
            w(f"body {i} {vb[0, 0] * V:.12e} {vb[0, 1] * V:.12e} {vb[0, 2] * V:.12e}")
        else:
            for k, p in enumerate(sel):
                w(f"node {pid + k + 1} {v[p, 0] * V:.12e} {v[p, 1] * V:.12e} {v[p, 2] * V:.12e}")
        pid += len(sel)
    w("endv")
    w("endi")
    with open(a.output, "w") as f:
        f.write("\n".join(out) + "\n")
    note(f"{n} points in {len(bodies)} bodies ({', '.join(body_names[b] for b in bodies)}) -> {a.output}")


if __name__ == "__main__":
    main()
