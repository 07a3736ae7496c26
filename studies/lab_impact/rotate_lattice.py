#!/usr/bin/python3
"""Turn one body's point lattice off the grid: rotate its points about a centre in a run's first
checkpoint (and its t = 0 snapshot), for `shatter resume` to continue (grid imprinting, issue 11
item 5: does an off-grid lattice alone change the crack directions?). Optionally move another
body (the projectile) along its own velocity, to undo a larger `impact.gap` used for the first
step so that nothing has touched the rotated body yet.

The scene builder fills every body on a lattice aligned with the grid (include/shatter/scene/
lattice.hpp), and no scene key turns it. A sphere's points rotated rigidly about its centre still
fill the same sphere with the same volumes, masses and flaws (each point keeps its own), only no
longer in rows along the grid axes. The recipe, for a body at rest that nothing has touched yet:

  shatter run SCENE --out RUN --set solver.end_time=1e-9 --set impact.gap=8e-3 ...
                     (one step, the projectile far enough away that no stencil reaches the target:
                      a t = 0 snapshot and a checkpoint)
  rotate_lattice.py RUN --body target --centre 0 0 0 --axis 1 2 3 --degrees 37 \
                    --advance projectile 5.6e-3    (the scene's gap, one cell (2.4 mm), restored)
  shatter resume RUN/checkpoint.h5 --out RUN --set solver.end_time=1e-4

Only positions are rotated: the body must be at rest and unstressed (checked: every velocity,
stress and damage entry of the body is zero, else the script refuses), so nothing else has a
direction to turn. The advanced body must be in uniform motion and unstressed (|stress| < 1 Pa; checked). Each rewritten dataset gets its crc32 attribute recomputed (zlib CRC-32 of the
values as stored, docs/outputs.md). The snapshot's `position` is rewritten too, so tools that read
the reference configuration from the t = 0 snapshot (crack_orientation.py) see the turned
lattice."""

import argparse
import glob
import os
import sys
import zlib

import h5py
import numpy as np


# The turn of crack_orientation.py's second frame (Rodrigues), so both tools turn alike.
from crack_orientation import rotation  # noqa: E402


def body_id(f, name):
    names = [n.decode() if isinstance(n, bytes) else str(n) for n in f["names/body"][:]] \
        if "names/body" in f else None
    if names is None:
        # checkpoints keep the resolved scene; bodies are numbered in its order of [body.*] tables
        scene = f["scene"][()].decode()
        names = [line.strip()[len("[body."):-1] for line in scene.splitlines()
                 if line.strip().startswith("[body.") and line.strip().count(".") == 1]
    if name not in names:
        sys.exit(f"rotate_lattice: no body '{name}' in {f.filename} (bodies: {names})")
    return names.index(name)


def rewrite(ds, values):
    ds[...] = values
    ds.attrs["crc32"] = np.int64(zlib.crc32(np.ascontiguousarray(ds[...]).tobytes()))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run")
    ap.add_argument("--body", default="target")
    ap.add_argument("--centre", type=float, nargs=3, default=[0.0, 0.0, 0.0])
    ap.add_argument("--axis", type=float, nargs=3, default=[1.0, 2.0, 3.0])
    ap.add_argument("--degrees", type=float, default=37.0)
    ap.add_argument("--advance", nargs=2, metavar=("BODY", "DISTANCE"),
                    help="move BODY by DISTANCE (m) along its velocity")
    args = ap.parse_args()
    R = rotation(args.axis, args.degrees)
    c = np.array(args.centre)

    with h5py.File(os.path.join(args.run, "checkpoint.h5"), "r+") as f:
        P = f["particles"]
        b = body_id(f, args.body)
        sel = P["body"][:] == b
        for col in ("vx", "vy", "vz", "sxx", "syy", "szz", "sxy", "sxz", "syz", "damage"):
            if np.any(P[col][:][sel] != 0.0):
                sys.exit(f"rotate_lattice: body '{args.body}' has non-zero {col} in the "
                         "checkpoint; rotate only a body at rest that nothing has touched")
        x = np.stack([P["x"][:], P["y"][:], P["z"][:]], axis=1)
        x[sel] = (x[sel] - c) @ R.T + c
        shift = None
        if args.advance:
            moved = P["body"][:] == body_id(f, args.advance[0])
            v = np.stack([P["vx"][:], P["vy"][:], P["vz"][:]], axis=1)[moved]
            # Its own free surface leaves round-off stress after the first step (measured 2.5e-6
            # Pa in the nylon sphere); 1 Pa is far below anything a contact would give.
            if np.ptp(v, axis=0).max() > 1e-9 * np.abs(v).max() or any(
                    np.abs(P[col][:][moved]).max() > 1.0 for col in ("sxx", "syy", "szz", "sxy")):
                sys.exit(f"rotate_lattice: body '{args.advance[0]}' is not in uniform, "
                         "unstressed motion; it has touched something already")
            shift = float(args.advance[1]) * v[0] / np.linalg.norm(v[0])
            x[moved] += shift
            print(f"checkpoint: {moved.sum()} points of '{args.advance[0]}' moved by "
                  f"{np.round(shift, 6)} m")
        for i, col in enumerate(("x", "y", "z")):
            rewrite(P[col], x[:, i])
        print(f"checkpoint: {sel.sum()} points of '{args.body}' rotated by {args.degrees} degrees "
              f"about {args.axis} through {args.centre}")

    snaps = sorted(glob.glob(os.path.join(args.run, "snapshots", "snapshot_*.h5")))
    if snaps:
        with h5py.File(snaps[0], "r+") as f:
            P = f["particles"]
            sel = P["body"][:] == body_id(f, args.body)
            pos = P["position"][:]
            pos[sel] = (pos[sel] - c) @ R.T + c
            if shift is not None:
                pos[P["body"][:] == body_id(f, args.advance[0])] += shift
            rewrite(P["position"], pos)
            print(f"{os.path.basename(snaps[0])}: the same points rotated (and moved)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
