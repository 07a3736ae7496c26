"""Crater depth and diameter of an axisymmetric (r-z) run, at every snapshot.

usage: crater.py RUN_DIR [RUN_DIR ...]   (prints CSV: run,time_s,t_aU,depth_m,diameter_m,...)
       as a module: crater.profile(...), crater.measure(run_dir)

Definition (the transient crater as iSALE studies measure it, e.g. Prieur et al. 2017, JGR
Planets 122, "The effect of target properties on transient crater scaling for simple craters";
the definition as stated here, not re-checked against the paper): the cavity's depth below the
pre-impact surface z = 0 on the axis, and its diameter at the pre-impact surface level, measured
on the material's surface profile. The profile is the top of the material column of each radial bin (width one
cell): the points of every body (projectile material lining the cavity counts as floor) are
binned in z cells of one cell size, and the column is followed up from the half-space's bottom
while at most one cell in a row is empty; its top is the highest point of the column plus half
the initial point spacing (an undisturbed surface reads z = 0). Ejecta above a gap of two empty
cells do not count. Depth = -top of the axis bin (0 <= r < h); diameter = twice the radius where
the profile, walked out from the axis, first reaches z = 0 (linear between bin centres).
Times are in units of a/U (projectile radius over impact speed), read from the scene.
"""
import glob
import os
import sys
import tomllib

import h5py
import numpy as np


def profile(r, z, h, spacing, z_bottom, r_max):
    """Top of the contiguous material column in each radial bin of width h (NaN if empty)."""
    nr = int(np.ceil(r_max / h))
    ir = np.clip((r / h).astype(int), 0, nr - 1)
    tops = np.full(nr, np.nan)
    for b in range(nr):
        zb = z[ir == b]
        if zb.size == 0:
            continue
        iz = np.floor((zb - z_bottom) / h).astype(int)
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
        in_column = (iz >= 0) & (iz <= top_cell)
        tops[b] = zb[in_column].max() + 0.5 * spacing
    return tops


def depth_and_diameter(tops, h):
    depth = -tops[0]
    if not depth > 0.0:
        return depth, np.nan  # no cavity yet (the projectile still above the surface)
    centres = (np.arange(tops.size) + 0.5) * h
    for b in range(1, tops.size):
        z0, z1 = tops[b - 1], tops[b]
        if np.isfinite(z0) and np.isfinite(z1) and z0 < 0.0 <= z1:
            return depth, 2.0 * (centres[b - 1] + (0.0 - z0) / (z1 - z0) * h)
    return depth, np.nan


def scene_of(run_dir):
    with open(os.path.join(run_dir, "scene.toml"), "rb") as f:
        s = tomllib.load(f)
    h = s["solver"]["cell_size"]
    proj = s["body"]["projectile"]
    a, speed = proj["radius"], abs(proj["velocity"][2])
    target = s["body"]["target"]
    return h, a, speed, target["lo"][2], target["hi"][0]


def measure(run_dir):
    """[(time, t in a/U, depth, diameter, points)] for every snapshot of run_dir."""
    h, a, speed, z_bottom, r_max = scene_of(run_dir)
    rows = []
    for snap in sorted(glob.glob(os.path.join(run_dir, "snapshots", "*.h5"))):
        with h5py.File(snap) as f:
            t = float(f.attrs["time"])
            pos = f["particles/position"][()]
        tops = profile(pos[:, 0], pos[:, 2], h, h / 2.0, z_bottom, r_max)
        d, dia = depth_and_diameter(tops, h)
        rows.append((t, t * speed / a, d, dia, len(pos)))
    return rows, a


if __name__ == "__main__":
    print("run,time_s,t_aU,depth_m,diameter_m,depth_a,diameter_a,points")
    for run in sys.argv[1:]:
        rows, a = measure(run)
        for t, ta, d, dia, n in rows:
            print(f"{run},{t:.4g},{ta:.3f},{d:.5g},{dia:.5g},{d / a:.4f},{dia / a:.4f},{n}")
