#!/usr/bin/python3
"""Wave-speed verification problem (scenes/verification/wave-speed.toml, problem 4) with both
methods at three resolutions, and the convergence order of the measured c_p (issue 10,
Validation "Elastic waves"; docs/validation-sph.md).

The scene's bar (2 m, E = 10 MPa, nu = 0.25, rho = 1000 kg/m^3, c_p = 109.545 m/s) hits the
wall x = 0 at 1 m/s between slip planes (uniaxial strain). Changes for the study, the same for
both methods:
  - x_lo = "slip" instead of "fixed": SPH refuses no-slip faces; for a bar hitting the wall head
    on, both stop the normal motion, and the answers agree until the release reaches the wall
    again at 2 L / c_p = 36.5 ms (after that a slip wall lets the bar go, a fixed one pulls it
    back); the gauges below end at 18.3 ms.
  - the bar and the domain are one cell thick at every resolution (y, z in [0, cell]): between
    slip planes the thickness does not matter (uniaxial strain), and it keeps the cost linear.
  - end_time 20 ms.
Gauges (as the scene's header): t_half, the first time KE falls below KE0 / 2 (linear
interpolation between time-series rows, written every step), gives c_p = L / (2 t_half);
KE at L / c_p = 18.26 ms (exact 0; the ringing behind the front); the largest energy error.
SPH keeps its own artificial viscosity (alpha = 1, beta = 2, the solver's defaults; it is the
SPH shock capturing of every SPH run), MPM runs the scene's "no bulk viscosity".

Usage:
  sph_wave_speed.py --out-dir DIR [--cells 0.02 0.01 0.005] [--methods mpm sph]
                    [--shatter build/release/shatter] [--table-only]
                    [--set KEY=VALUE ...] [--tag SUFFIX]   (e.g. SPH without viscosity:
                    --methods sph --set solver.sph.alpha=0 --set solver.sph.beta=0 --tag=-inviscid)
"""

import argparse
import csv
import math
import os
import subprocess

CP = math.sqrt(12.0e6 / 1000.0)  # (K + 4G/3)/rho with K = 6.667 MPa, G = 4 MPa
L = 2.0


def run(shatter, method, cell, out, extra):
    cmd = ["nice", "-n", "5", shatter, "run", "scenes/verification/wave-speed.toml",
           "--threads", "1", "--quiet", "--overwrite", "--out", out,
           "--set", f'solver.method="{method}"',
           "--set", f"solver.cell_size={cell}",
           "--set", 'domain.x_lo="slip"',
           "--set", f"domain.hi=[4.0, {cell}, {cell}]",
           "--set", f"body.bar.hi=[2.0, {cell}, {cell}]",
           "--set", "solver.end_time=0.02",
           "--set", "output.snapshot_every=0.0"]
    for e in extra:
        cmd += ["--set", e]
    r0 = os.times()
    subprocess.run(cmd, check=True)
    r1 = os.times()
    return (r1.children_user + r1.children_system) - (r0.children_user + r0.children_system)


def measure(out):
    t, ke, err, steps = [], [], [], 0
    with open(os.path.join(out, "timeseries.csv")) as fh:
        for row in csv.DictReader(fh):
            t.append(float(row["time_s"]))
            ke.append(float(row["kinetic_J"]))
            err.append(abs(float(row["energy_error"])))
            steps = int(row["step"])
    half = 0.5 * ke[0]
    t_half = float("nan")
    for i in range(1, len(t)):
        if ke[i] < half <= ke[i - 1]:
            t_half = t[i - 1] + (half - ke[i - 1]) / (ke[i] - ke[i - 1]) * (t[i] - t[i - 1])
            break
    t_end = L / CP
    k_end = float("nan")
    for i in range(1, len(t)):
        if t[i] >= t_end:
            k_end = ke[i - 1] + (t_end - t[i - 1]) / (t[i] - t[i - 1]) * (ke[i] - ke[i - 1])
            break
    return dict(cp=L / (2.0 * t_half), ke_end=k_end / ke[0], err=max(err), steps=steps)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out-dir", required=True)
    ap.add_argument("--cells", type=float, nargs="+", default=[0.02, 0.01, 0.005])
    ap.add_argument("--methods", nargs="+", default=["mpm", "sph"])
    ap.add_argument("--shatter", default="build/release/shatter")
    ap.add_argument("--table-only", action="store_true")
    ap.add_argument("--set", dest="extra", action="append", default=[],
                    help="extra scene override for every run (e.g. solver.sph.alpha=0)")
    ap.add_argument("--tag", default="", help="suffix of the run directories")
    args = ap.parse_args()
    rows = {}
    for method in args.methods:
        for cell in args.cells:
            out = os.path.join(args.out_dir, f"{method}-{cell:g}{args.tag}")
            cpu = float("nan")
            if not args.table_only:
                cpu = run(args.shatter, method, cell, out, args.extra)
            m = measure(out)
            m["cpu"] = cpu
            rows[(method, cell)] = m
    print("| method | cell (m) | points | steps | c_p (m/s) | error | order | KE(L/c_p)/KE0 | "
          "max energy error | CPU (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for method in args.methods:
        prev = None
        for cell in args.cells:
            m = rows[(method, cell)]
            e = m["cp"] / CP - 1.0
            order = "-"
            if prev is not None and e != 0.0 and prev[1] != 0.0:
                order = f"{math.log(abs(prev[1]) / abs(e)) / math.log(prev[0] / cell):.2f}"
            points = int(round(2.0 / (cell / 2))) * 4
            print(f"| {method.upper()} | {cell:g} | {points} | {m['steps']} | {m['cp']:.2f} | "
                  f"{100 * e:+.2f} % | {order} | {m['ke_end']:.3f} | {m['err']:.1e} | "
                  f"{m['cpu']:.1f} |")
            prev = (cell, e)
    print(f"\nexact c_p = {CP:.3f} m/s; order = log(|e_coarse| / |e_fine|) / log 2")


if __name__ == "__main__":
    main()
