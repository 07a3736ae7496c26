#!/usr/bin/python3
"""Mass that leaves an r-z run's domain, by the face it leaves through (issue 32, session 23;
docs/validation-dart.md, "Session 23").

The raducan2019 scenes have outflow faces: a point that crosses the side (r = domain.hi x), the
bottom (z = domain.lo z) or the top (z = domain.hi z) is removed. For RUN it reads the snapshots
(RUN/snapshots/snapshot_*.h5: id, position, mass, body) and the domain (RUN/scene.toml) and
assigns every point present in one snapshot and gone in the next to the face nearest to its last
position there. Prints, at every --every-th snapshot and the last, the target mass gone through
each face so far (kg and % of the target's mass at t = 0), the target's largest r and lowest z
(and their distance to the side and bottom faces). The top face takes the ejecta (counted by
beta_launch when they cross the count plane below it); what the side and bottom take is the
finite target leaving the domain.

Usage: faces_lost.py RUN [--every 4] [--body target]
"""

import argparse
import glob
import os
import tomllib

import h5py
import numpy as np


def load(path, body_name):
    with h5py.File(path, "r") as f:
        p = f["particles"]
        ids, pos, mass, body = p["id"][:], p["position"][:], p["mass"][:], p["body"][:]
        names = [n.decode() if isinstance(n, bytes) else str(n) for n in f["names"]["body"][:]]
        t = float(f.attrs["time"])
    sel = body == names.index(body_name)
    return t, ids[sel], pos[sel], mass[sel]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run")
    ap.add_argument("--every", type=int, default=4)
    ap.add_argument("--body", default="target")
    a = ap.parse_args()
    with open(os.path.join(a.run, "scene.toml"), "rb") as f:
        dom = tomllib.load(f)["domain"]
    r_hi, z_lo, z_hi = dom["hi"][0], dom["lo"][2], dom["hi"][2]
    snaps = sorted(glob.glob(os.path.join(a.run, "snapshots", "snapshot_*.h5")))
    t0, ids0, _, m0 = load(snaps[0], a.body)
    m_total = float(m0.sum())
    gone = {"side": 0.0, "bottom": 0.0, "top": 0.0}
    print(f"# {a.run}: domain r < {r_hi:g} m, {z_lo:g} < z < {z_hi:g} m; {a.body} "
          f"{len(ids0)} points, {m_total:.4g} kg at t = {t0:g} s")
    print("| t (s) | through side | through bottom | through top | target's max r (to side) "
          "| target's min z (to bottom) |")
    print("|---|---|---|---|---|---|")
    prev = load(snaps[0], a.body)
    for k, path in enumerate(snaps[1:], start=1):
        cur = load(path, a.body)
        left = ~np.isin(prev[1], cur[1])
        if left.any():
            r, z, m = prev[2][left, 0], prev[2][left, 2], prev[3][left]
            d = np.stack([r_hi - r, z - z_lo, z_hi - z])  # side, bottom, top
            face = np.argmin(d, axis=0)
            for i, name in enumerate(("side", "bottom", "top")):
                gone[name] += float(m[face == i].sum())
        prev = cur
        if k % a.every == 0 or k == len(snaps) - 1:
            t, _, pos, _ = cur
            cells = [f"{gone[n]:.3g} kg ({100 * gone[n] / m_total:.2f}%)"
                     for n in ("side", "bottom", "top")]
            print(f"| {t:.3f} | " + " | ".join(cells) + f" | {pos[:, 0].max():.2f} m "
                  f"({r_hi - pos[:, 0].max():.2f}) | {pos[:, 2].min():.2f} m "
                  f"({pos[:, 2].min() - z_lo:.2f}) |")


if __name__ == "__main__":
    main()
