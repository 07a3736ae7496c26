#!/usr/bin/python3
"""Directions of surface cracks against the grid axes (grid imprinting, issue 11 item 5).

For each run directory: the target's surface points (initial distance from the target centre
above R - one point spacing, in the t = 0 snapshot) carry the damage D of a later snapshot
(default the last). Cracks are read in the reference configuration (initial positions, matched by
point id), so ejecta and fragment motion do not bend them. At every surface point the tangential
damage gradient g is fitted by least squares over the surface points within 2.5 spacings (offsets
projected onto the tangent plane); the crack runs along t = n x g / |g| (n the outward normal), and
points with |g| above 0.1 per spacing (a crack edge) count with weight |g|.

The direction is compared with a frame of three axes projected onto the tangent plane (axes within
30 degrees of the normal are skipped there): psi = the smallest angle between t and a projected
axis (0 to 90 degrees; at most 45 where two orthogonal axes lie in the plane). Two frames: the grid axes, and the grid axes turned by the
rotation that turned the impact geometry (--rotate-about AXIS --degrees A, the rotation the scene's
impact.direction and impact.offset received). If cracks follow the grid, psi_grid piles up at small
angles in every run whatever the geometry's rotation; if they follow the impact, the rotated run's
psi_rot matches the unrotated run's psi_grid.

Usage:
  crack_orientation.py RUN [RUN ...] [--time 1e-4] [--target target] [--centre 0 0 0]
        [--radius 0.03] [--rotate-about NX NY NZ --degrees A] [--render OUT.png]
A second measure, less sensitive to how a gradient is fitted on a lattice: the correlation of the
failed indicator (D >= 0.9) between surface points 3-6 spacings apart whose separation lies within
10 degrees of a projected axis, minus that for separations more than 30 degrees from every axis
("pair anisotropy"; > 0 when failed points line up along the axes), for both frames and, as the
baseline of no preferred direction, averaged over six frames of random orientation.

Prints, per run and pooled: the weighted fraction of crack length with psi < 7.5 degrees (1/6 for
directions spread evenly over [0, 45], two orthogonal axes in the plane), the weighted mean psi,
and a 9-bin histogram (10-degree bins) for both frames. The comparison that counts is between
frames and between rotated and unrotated runs, not against the isotropic figure.
"""

import argparse
import os
import sys

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import shatterpy as sp  # noqa: E402


def rotation(axis, degrees):
    """Rodrigues rotation matrix about a unit axis."""
    k = np.asarray(axis, float)
    k = k / np.linalg.norm(k)
    a = np.radians(degrees)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(a) * kx + (1 - np.cos(a)) * kx @ kx


def body_index(snapshot, name):
    bodies, _ = sp.snapshot_names(snapshot)
    return bodies.index(name) if name in bodies else None


def crack_directions(run, t, target, centre, radius):
    """(points, unit normals, crack directions, weights) of the crack edges on the surface."""
    files = sp.snapshots(run)
    _, c0, axis0 = sp.read_snapshot(files[0])
    _, c1, _ = sp.read_snapshot(sp.snapshot_at(run, t))
    b = body_index(files[0], target)
    sel0 = np.ones(len(c0["x"]), bool) if b is None else c0["body"] == b
    x0 = np.stack([c0["x"], c0["y"], c0["z"]], 1)[sel0] - centre
    ids0 = c0["id"][sel0]
    spacing = np.cbrt(np.median(c0["volume0"][sel0]))
    r = np.linalg.norm(x0, axis=1)
    surf = r > radius - spacing
    x0, ids0 = x0[surf], ids0[surf]
    # damage of the later snapshot, by id (points that left through outflow count as failed)
    order = np.argsort(c1["id"])
    pos = np.searchsorted(c1["id"], ids0, sorter=order)
    pos = np.clip(pos, 0, len(order) - 1)
    found = c1["id"][order[pos]] == ids0
    d = np.where(found, c1["damage"][order[pos]], 1.0)
    n = x0 / np.linalg.norm(x0, axis=1)[:, None]
    surface = (x0, n, d, spacing)
    tree = cKDTree(x0)
    nbrs = tree.query_ball_point(x0, 2.5 * spacing)
    pts, nrm, dirs, w = [], [], [], []
    for i, js in enumerate(nbrs):
        js = [j for j in js if j != i]
        if len(js) < 5:
            continue
        off = x0[js] - x0[i]
        off -= np.outer(off @ n[i], n[i])  # tangent-plane offsets
        dd = d[js] - d[i]
        g, *_ = np.linalg.lstsq(off, dd, rcond=None)
        g -= (g @ n[i]) * n[i]
        gn = np.linalg.norm(g)
        if gn * spacing < 0.1:
            continue
        tdir = np.cross(n[i], g / gn)
        pts.append(x0[i])
        nrm.append(n[i])
        dirs.append(tdir)
        w.append(gn * spacing)
    if axis0 >= 0:
        # Half model: mirror the crack field into the other half so that both frames see the
        # full sphere (the mirror maps grid axes onto themselves).
        m = np.ones(3)
        m[axis0] = -1.0
        pts += [p * m for p in pts]
        nrm += [v * m for v in nrm]
        dirs += [v * m for v in dirs]
        w += w
    return np.array(pts), np.array(nrm), np.array(dirs), np.array(w), surface


def pair_anisotropy(surface, frame, lo=3.0, hi=6.0):
    """Correlation of the failed indicator (D >= 0.9) between surface points lo-hi spacings
    apart, for pairs whose separation (in the tangent plane at their midpoint) lies within 10
    degrees of a projected frame axis, minus the same for pairs more than 30 degrees from every
    projected axis. Straight cracks along the frame's axes make it positive."""
    x0, n, d, s = surface
    f = (d >= 0.9).astype(float)
    f = f - f.mean()
    var = (f * f).mean()
    pairs = cKDTree(x0).query_pairs(hi * s, output_type="ndarray")
    sep = x0[pairs[:, 1]] - x0[pairs[:, 0]]
    dist = np.linalg.norm(sep, axis=1)
    pairs, sep, dist = pairs[dist > lo * s], sep[dist > lo * s], dist[dist > lo * s]
    mid = n[pairs[:, 0]] + n[pairs[:, 1]]
    mid /= np.linalg.norm(mid, axis=1)[:, None]
    u = sep - (np.sum(sep * mid, axis=1))[:, None] * mid
    u /= np.linalg.norm(u, axis=1)[:, None]
    best = np.full(len(u), np.inf)
    for e in frame:
        p = e[None, :] - (mid @ e)[:, None] * mid
        pn = np.linalg.norm(p, axis=1)
        ok = pn > 0.5
        c = np.abs(np.sum(u * p, axis=1)) / np.maximum(pn, 1e-30)
        a = np.degrees(np.arccos(np.clip(c, 0.0, 1.0)))
        best = np.where(ok, np.minimum(best, a), best)
    prod = f[pairs[:, 0]] * f[pairs[:, 1]] / var
    along, across = best < 10.0, (best > 30.0) & np.isfinite(best)
    return float(prod[along].mean() - prod[across].mean()), int(along.sum()), int(across.sum())


def psi(nrm, dirs, frame):
    """Smallest in-plane angle (degrees, in [0, 90]) between each crack direction and the frame's
    axes projected onto the tangent plane (at most 45 where two orthogonal axes lie in the plane);
    NaN where no axis lies within 60 degrees of the plane."""
    out = np.full(len(dirs), np.nan)
    for i, (n, t) in enumerate(zip(nrm, dirs)):
        best = np.inf
        for e in frame:
            p = e - (e @ n) * n
            pn = np.linalg.norm(p)
            if pn < np.sin(np.radians(30.0)):
                continue
            c = abs(t @ (p / pn))
            best = min(best, np.degrees(np.arccos(min(1.0, c))))
        if np.isfinite(best):
            out[i] = best
    return out


def summary(angles, w):
    ok = np.isfinite(angles)
    a, ww = angles[ok], w[ok]
    if ww.sum() == 0:
        return float("nan"), float("nan"), np.zeros(9)
    hist, _ = np.histogram(a, bins=9, range=(0, 90), weights=ww)
    return float(ww[a < 7.5].sum() / ww.sum()), float((a * ww).sum() / ww.sum()), hist / ww.sum()


def render(run, t, target, centre, radius, out):
    """The reference-configuration surface points coloured by D, seen along +-x, +-y, +-z."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    *_, surface = crack_directions(run, t, target, centre, radius)
    x0, _, d, _ = surface
    fig, axes = plt.subplots(2, 3, figsize=(13, 8.5))
    views = [(0, 1, 2, 1), (0, 1, 2, -1), (1, 2, 0, 1), (1, 2, 0, -1), (0, 2, 1, 1), (0, 2, 1, -1)]
    for ax, (i, j, k, sgn) in zip(axes.flat, views):
        sel = sgn * x0[:, k] > 0
        sc = ax.scatter(x0[sel, i] * 1e3, x0[sel, j] * 1e3, c=d[sel], s=5, cmap="viridis",
                        vmin=0, vmax=1)
        ax.set_aspect("equal")
        ax.set_title(f"hemisphere {'+' if sgn > 0 else '-'}{'xyz'[k]}")
        ax.set_xlabel(f"{'xyz'[i]} (mm)")
        ax.set_ylabel(f"{'xyz'[j]} (mm)")
    fig.colorbar(sc, ax=axes, shrink=0.6, label="damage D")
    fig.suptitle(f"{run}: surface damage at t = {t * 1e6:.0f} us on the initial positions")
    fig.savefig(out, dpi=60)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--time", type=float, default=1e-4)
    ap.add_argument("--target", default="target")
    ap.add_argument("--centre", type=float, nargs=3, default=[0.0, 0.0, 0.0])
    ap.add_argument("--radius", type=float, default=0.03)
    ap.add_argument("--rotate-about", type=float, nargs=3, default=[-np.sqrt(3) / 2, 0.5, 0.0])
    ap.add_argument("--degrees", type=float, default=30.0)
    ap.add_argument("--label", default="")
    ap.add_argument("--render", help="PNG of the first run's surface damage, six hemispheres")
    args = ap.parse_args()
    if args.render:
        render(args.runs[0], args.time, args.target, np.array(args.centre), args.radius,
               args.render)
    grid = np.eye(3)
    turned = (rotation(args.rotate_about, args.degrees) @ grid.T).T
    pooled = {"grid": ([], []), "rot": ([], [])}
    print(f"| run {args.label} | surface points failed | crack edges | psi<7.5 grid | mean psi "
          f"grid | psi<7.5 rotated | mean psi rotated | pair anisotropy grid | pair anisotropy "
          f"rotated | pair anisotropy, random frames |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    aniso = {"grid": [], "rot": [], "random": []}
    for run in args.runs:
        _, nrm, dirs, w, surface = crack_directions(run, args.time, args.target,
                                                    np.array(args.centre), args.radius)
        row = [os.path.basename(run.rstrip("/")), f"{np.mean(surface[2] >= 0.9):.3f}",
               str(len(w))]
        for key, frame in (("grid", grid), ("rot", turned)):
            a = psi(nrm, dirs, frame)
            pooled[key][0].append(a)
            pooled[key][1].append(w)
            f, m, _ = summary(a, w)
            row += [f"{f:.3f}", f"{m:.1f}"]
        for key, frame in (("grid", grid), ("rot", turned)):
            aniso[key].append(pair_anisotropy(surface, frame)[0])
            row.append(f"{aniso[key][-1]:+.3f}")
        # baseline: frames in random orientations (fixed draw), where no preference is expected
        rng = np.random.default_rng(12345)
        base = []
        for _ in range(6):
            q, _r = np.linalg.qr(rng.normal(size=(3, 3)))
            base.append(pair_anisotropy(surface, q.T)[0])
        aniso["random"].append(float(np.mean(base)))
        row.append(f"{aniso['random'][-1]:+.3f}")
        print("| " + " | ".join(row) + " |")
    for key in ("grid", "rot", "random"):
        v = np.array(aniso[key])
        print(f"pair anisotropy {key}: {v.mean():+.3f} +- {v.std(ddof=1) if len(v) > 1 else 0:.3f}")
    for key in ("grid", "rot"):
        a = np.concatenate(pooled[key][0])
        w = np.concatenate(pooled[key][1])
        f, m, h = summary(a, w)
        print(f"pooled {key}: psi<7.5 {f:.3f}, mean psi {m:.1f} deg, histogram (10-deg bins, 0-90) "
              + " ".join(f"{x:.3f}" for x in h))


if __name__ == "__main__":
    main()
