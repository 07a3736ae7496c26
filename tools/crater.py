#!/usr/bin/python3
"""Crater diameter, depth and volume of a head-on impact into a flat target, at every snapshot.

usage: crater.py RUN_DIR [RUN_DIR ...] [--last] [--surface Z] [--csv FILE]

Prints CSV: run,time_s,t_aU,depth_m,diameter_m,volume_m3,depth_a,diameter_a,volume_a3,points
(t_aU: time in impactor radii a over impact speed U; *_a: in units of a, a^3). Works on
axisymmetric (r-z) runs and on 3-D runs of a half-space struck along -z (a half model too): in
3-D, r is the distance from the vertical line through the impactor's centre at the first
snapshot (moved onto the symmetry plane of a half model), and the crater is taken as
axisymmetric about it (the azimuthal highest point of each radial ring counts).

Definition (the transient crater measured against the pre-impact surface, as iSALE studies of
cratering do, e.g. Prieur et al. 2017, JGR Planets 122; Raducan et al. 2019, Icarus 329, give
crater radii in this family, but their text was not at hand to check their exact measure):
  - the material's surface profile: in each radial ring of width h (the cell size) the points of
    every body (impactor material lining the cavity counts as floor) are binned in z cells of h,
    the column is followed up from the target's bottom (or from the ring's lowest point where
    the impact pushed material below it) while at most one cell in a row is empty, and its top
    is its highest point plus half the point spacing (an undisturbed surface reads its true
    level), placed at that point's radius. Ejecta above two or more empty cells are not surface;
  - the pre-impact surface z_s: the median top of the target's profile at the first snapshot
    (or --surface);
  - depth = z_s - top of the axis ring (0 <= r < h);
  - diameter = twice the radius where the profile, walked out from the axis, first rises to z_s
    (linear between its points): the crater's crossing of the pre-impact surface;
  - volume = the cavity below z_s inside that radius: the integral of 2 pi r (z_s - top(r)),
    the profile linear between its points, flat from the axis to the first, zero at the
    crossing (points above z_s add nothing).
Accuracy (tests/tools, a paraboloid): depth to half a point spacing, diameter to a cell,
volume to ~pi R^2 spacing / 2 (the highest point of a ring sits up to a spacing above the mean).
A rim higher than z_s, material compacted below it, and ejecta in flight are not in the volume.
"""

import argparse
import csv
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import shatter_plot as sp  # noqa: E402  (the shatterpy readers)


def profile_points(r, z, h, spacing, z_bottom, r_max):
    """(radius, top) of the contiguous material column in each radial ring of width h (NaN if
    empty): top = its highest point plus half the point spacing, radius = that point's r."""
    nr = int(np.ceil(r_max / h))
    ir = np.clip((r / h).astype(int), 0, nr - 1)
    tops, radii = np.full(nr, np.nan), np.full(nr, np.nan)
    for b in range(nr):
        sel = ir == b
        zb, rb = z[sel], r[sel]
        if zb.size == 0:
            continue
        # from the target's bottom, or from the ring's lowest point where the impact has pushed
        # material below it (a target too shallow for its crater)
        iz = np.floor((zb - min(z_bottom, zb.min())) / h).astype(int)
        occupied = np.zeros(iz.max() + 2, bool)
        occupied[iz[iz >= 0]] = True
        top_cell, empty_run = -1, 0
        for c, filled in enumerate(occupied):
            if filled:
                top_cell, empty_run = c, 0
            else:
                empty_run += 1
                if empty_run >= 2:
                    break
        if top_cell < 0:
            continue
        column = np.flatnonzero((iz >= 0) & (iz <= top_cell))
        k = column[np.argmax(zb[column])]
        tops[b], radii[b] = zb[k] + 0.5 * spacing, rb[k]
    return radii, tops


def profile(r, z, h, spacing, z_bottom, r_max):
    """Top of the contiguous material column in each radial ring of width h (NaN if empty)."""
    return profile_points(r, z, h, spacing, z_bottom, r_max)[1]


def depth_and_diameter(tops, h, surface=0.0, radii=None):
    """(depth, diameter) against the pre-impact surface; diameter NaN without a cavity. The
    profile's radii are the ring centres unless given (profile_points: where each top is)."""
    depth = surface - tops[0]
    if not depth > 0.0:
        return depth, np.nan  # no cavity yet (the impactor still above the surface)
    at = (np.arange(tops.size) + 0.5) * h if radii is None else radii
    for b in range(1, tops.size):
        z0, z1 = tops[b - 1], tops[b]
        if np.isfinite(z0) and np.isfinite(z1) and z0 < surface <= z1:
            return depth, 2.0 * (at[b - 1] + (surface - z0) / (z1 - z0) * (at[b] - at[b - 1]))
    return depth, np.nan


def volume(radii, tops, diameter, surface=0.0):
    """Cavity volume below the surface inside radius R = diameter / 2: the integral of
    2 pi r (surface - top(r)) from 0 to R, the profile linear between its points, constant from
    the axis to the first, zero at R (module docstring)."""
    if not np.isfinite(diameter):
        return np.nan
    big_r = 0.5 * diameter
    inside = radii < big_r
    if not np.all(np.isfinite(tops[inside])):
        return np.nan  # an empty ring inside the crater: the profile does not define it
    r = np.concatenate([[0.0], radii[inside], [big_r]])
    f = np.maximum(0.0, surface - np.concatenate([tops[:1], tops[inside], [surface]]))
    r0, r1, f0, f1 = r[:-1], r[1:], f[:-1], f[1:]
    # exact integral of r f(r) over each segment with f linear (trapezoid in r f would not be)
    return float(2.0 * np.pi * np.sum((r1 - r0) / 6.0 * (r0 * (2 * f0 + f1) + r1 * (f0 + 2 * f1))))


def geometry(run_dir, first_cols, symmetry=-1, surface=None):
    """What the measure needs from the run's resolved scene and its first snapshot (columns and
    symmetry-plane axis, as shatterpy.read_snapshot gives them)."""
    scene = sp.scene(run_dir)
    if scene is None:
        sys.exit(f"{run_dir}: no scene.toml (not a run directory?)")
    h = float(scene["solver"]["cell_size"])
    rz = scene["solver"].get("geometry") == "axisymmetric"
    body = first_cols["body"].astype(int)
    target = int(np.argmax(np.bincount(body, weights=first_cols["mass"])))
    names, _ = sp.snapshot_names(sp.snapshots(run_dir)[0])
    tb = scene["body"].get(names[target], {}) if names else {}
    spacing = h / float(tb.get("points_per_cell", 2))
    others = [n for i, n in enumerate(names) if i != target and n in scene["body"]]
    imp_name = scene.get("beta", {}).get("impactor") or (others or [""])[0]
    imp = scene["body"].get(imp_name, {})
    vel = np.asarray(imp.get("velocity", [np.nan] * 3), float)
    if np.all(np.isfinite(vel)) and np.hypot(vel[0], vel[1]) > 1e-6 * abs(vel[2]):
        sys.exit(f"{run_dir}: the impactor's velocity {list(vel)} is not along -z: crater.py "
                 "measures head-on craters only")
    axis = (0.0, 0.0)
    if not rz:
        # The impactor's own points when its name is known: other bodies (a boulder field)
        # spread over the target and would move the axis.
        sel = body == names.index(imp_name) if imp_name in names else body != target
        axis = (float(np.average(first_cols["x"][sel], weights=first_cols["mass"][sel])),
                float(np.average(first_cols["y"][sel], weights=first_cols["mass"][sel])))
        if symmetry in (0, 1):  # a half model: the impact axis lies in its symmetry plane
            axis = tuple(0.0 if k == symmetry else axis[k] for k in range(2))
    g = dict(h=h, spacing=spacing, rz=rz, axis=axis, target=target,
             a=float(imp.get("radius", np.nan)), speed=float(np.linalg.norm(vel)))
    r, z = radial(first_cols, g)
    on = body == target
    g["z_bottom"] = float(z[on].min() - 0.5 * spacing)
    g["r_max"] = float(r[on].max() + 0.5 * spacing)
    if surface is None:
        tops = profile(r[on], z[on], h, spacing, g["z_bottom"], g["r_max"])
        surface = float(np.nanmedian(tops))
    g["surface"] = surface
    return g


def radial(cols, g):
    """(r, z) of every point: r-z runs store r as x; 3-D runs the distance from the axis."""
    if g["rz"]:
        return cols["x"], cols["z"]
    return np.hypot(cols["x"] - g["axis"][0], cols["y"] - g["axis"][1]), cols["z"]


def measure_snapshot(cols, g):
    """(depth, diameter, volume) of one snapshot's columns."""
    r, z = radial(cols, g)
    radii, tops = profile_points(r, z, g["h"], g["spacing"], g["z_bottom"], g["r_max"])
    depth, dia = depth_and_diameter(tops, g["h"], g["surface"], radii)
    return depth, dia, volume(radii, tops, dia, g["surface"])


def measure(run_dir, surface=None, last=False):
    """(geometry, [dict per snapshot]) of run_dir; with last=True the last snapshot only."""
    files = sp.snapshots(run_dir)
    if not files:
        sys.exit(f"{run_dir}: no snapshots")
    _, first, symmetry = sp.read_snapshot(files[0])
    g = geometry(run_dir, first, symmetry, surface)
    rows = []
    for path in files[-1:] if last else files:
        t, cols, _ = sp.read_snapshot(path)
        depth, dia, vol = measure_snapshot(cols, g)
        rows.append(dict(time_s=t, t_aU=t * g["speed"] / g["a"], depth_m=depth, diameter_m=dia,
                         volume_m3=vol, depth_a=depth / g["a"], diameter_a=dia / g["a"],
                         volume_a3=vol / g["a"] ** 3, points=len(cols["x"])))
    return g, rows


COLUMNS = ["run", "time_s", "t_aU", "depth_m", "diameter_m", "volume_m3", "depth_a",
           "diameter_a", "volume_a3", "points"]


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", metavar="RUN_DIR")
    ap.add_argument("--last", action="store_true", help="the last snapshot only")
    ap.add_argument("--surface", type=float, default=None,
                    help="pre-impact surface z (m); default: from the first snapshot")
    ap.add_argument("--csv", help="also write the table to this file")
    args = ap.parse_args()
    table = []
    for run in args.runs:
        g, rows = measure(run, args.surface, args.last)
        print(f"# {run}: pre-impact surface z = {g['surface']:.6g} m, cell {g['h']:.4g} m, "
              f"impactor radius {g['a']:.4g} m", file=sys.stderr)
        table += [dict(run=run, **row) for row in rows]
    write_table(sys.stdout, table)
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            write_table(f, table)


def write_table(stream, table):
    w = csv.writer(stream, lineterminator="\n")
    w.writerow(COLUMNS)
    for row in table:
        w.writerow([row["run"]] + [f"{row[k]:.6g}" for k in COLUMNS[1:-1]] + [row["points"]])


if __name__ == "__main__":
    main()
