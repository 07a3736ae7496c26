#!/usr/bin/python3
"""The shocked state of scenes/diagnostics/planar-nylon-basalt.toml against the Hugoniot (issue 27).

Per run and time: the mean pressure, specific internal energy, axial velocity and density of the
basalt slab's point layers (grouped by starting x, one point spacing each) behind the shock, and
over those layers the mean and the spread (max - min). The impedance match of the Tillotson
Hugoniots of Table 1's nylon and basalt (`shatter material ... --hugoniot`) gives the plateau:
up = 1.22 km/s, p = 16.6 GPa, E = 0.745 MJ/kg, rho = 3 565 kg/m^3.

With --points the table is per point instead: mean and standard deviation over the points of
the first --layers layers (the scatter a layer mean hides; session 12, the null-space modes).

Usage: planar_shock_state.py RUN [RUN ...] [--times 1.5e-6 2e-6] [--layers 5] [--points]"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import shatter_plot as sp  # noqa: E402

HUGONIOT = {"p": 16.6e9, "energy": 0.745e6, "vx": 1220.0, "rho": 3565.0}


def layer_states(run, t_want, n_layers, per_point=False):
    files = sp.snapshots(run)
    _, first, _ = sp.read_snapshot(files[0])
    t, snap, _ = sp.read_snapshot(sp.snapshot_at(run, t_want))
    body = first["body"].astype(int)
    slab = int(np.argmax(np.bincount(body, weights=first["mass"])))
    in0 = body == slab
    x0_of = dict(zip(first["id"][in0].astype(np.int64), first["x"][in0]))
    layers = np.unique(np.round(first["x"][in0], 9))[:n_layers]
    sel = snap["body"].astype(int) == slab
    x0 = np.array([x0_of[i] for i in snap["id"][sel].astype(np.int64)])
    if per_point:
        m = np.isin(np.round(x0, 9), np.round(layers, 9))
        return t, layers, [{k: (snap["pressure"] if k == "p" else snap[k])[sel][m] for k in HUGONIOT}]
    rows = []
    for lx in layers:
        m = np.isclose(x0, lx, atol=1e-9)
        rows.append({k: float(np.mean((snap["pressure"] if k == "p" else snap[k])[sel][m]))
                     for k in HUGONIOT})
    return t, layers, rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--times", type=float, nargs="+", default=[1.5e-6, 2.0e-6])
    ap.add_argument("--layers", type=int, default=5)
    ap.add_argument("--points", action="store_true",
                    help="mean +- standard deviation over points instead of layer means")
    args = ap.parse_args()
    unit = {"p": (1e-9, "GPa"), "energy": (1e-6, "MJ/kg"), "vx": (1.0, "m/s"),
            "rho": (1.0, "kg/m^3")}
    what = "mean ± std over points" if args.points else "layers / mean / spread"
    print("| run | t (us) | " + " | ".join(f"{k} ({u[1]}): {what}"
                                           for k, u in unit.items()) + " |")
    print("|---|---|" + "---|" * len(unit))
    print("| Hugoniot (impedance match) | | " + " | ".join(
        f"{HUGONIOT[k] * unit[k][0]:.3g}" for k in unit) + " |")
    for run in args.runs:
        for t_want in args.times:
            t, _, rows = layer_states(run, t_want, args.layers, args.points)
            if args.points:
                print(f"| {os.path.basename(os.path.normpath(run))} | {t * 1e6:.1f} | " + " | ".join(
                    f"{rows[0][k].mean() * s:.4g} ± {rows[0][k].std() * s:.3g}"
                    for k, (s, _) in unit.items()) + " |")
                continue
            cells = []
            for k, (scale, _) in unit.items():
                v = np.array([r[k] for r in rows]) * scale
                cells.append(" ".join(f"{x:.3g}" for x in v) +
                             f" / {v.mean():.3g} / {v.max() - v.min():.3g}")
            print(f"| {os.path.basename(os.path.normpath(run))} | {t * 1e6:.1f} | " +
                  " | ".join(cells) + " |")


if __name__ == "__main__":
    sys.exit(main())
