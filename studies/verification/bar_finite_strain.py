#!/usr/bin/python3
"""The vibrating bar's finite-strain reference: how far the exact *nonlinear* bar is from the
linear solution the verification problem compares against (issue 16 item 5).

The engine integrates the Cauchy stress from the rate of deformation (LinearElastic, Poisson 0),
which for a bar in uniaxial strain is sigma = E ln F, and with the cross-section fixed by the slip
planes the force per reference area is the same, P = E ln(1 + du/dX). The reference solution of
problem 1 (shared/reference/verification-problems.md) is the linear one, P = E du/dX. This script
solves both with an independent 1D finite-difference scheme (nodes at X = k dX, node 0 fixed, the
end X = L free, lumped masses, leapfrog, CFL 0.5, 1000 cells by default) from u = 0,
v = v0 sin(beta X), and reports, with the verification problem's own measures
(src/verification/problems.cpp, run_vibrating_bar):

  com_rms   RMS over every step of |v_com - v_com,exact| / (v0 (1 - cos beta L) / (beta L)),
            v_com,exact the linear solution's, the leapfrog velocity taken at t^n + dt/2
  u_end     mass-weighted L2 of u - u_exact at the end (5.125 periods) over v0 / omega
  u_half    the same at t = T/2 of the first period, and at t = T (u_period)

for the linear law (the scheme's own error: it must be far below the engine's) and for the log
law (the finite-strain effect). Usage: bar_finite_strain.py [--v0 0.1 0.01 0.001] [--cells N]."""

import argparse

import numpy as np

E, RHO, L = 100.0, 1.0, 25.0  # VibratingBar defaults (include/shatter/verification/problems.hpp)
C = np.sqrt(E / RHO)
BETA = np.pi / (2 * L)  # mode 1
OMEGA = C * BETA
PERIOD = 2 * np.pi / OMEGA


def run(v0, law, cells, cfl=0.5, periods=5.125):
    dx = L / cells
    X = np.arange(cells + 1) * dx
    m = np.full(cells + 1, RHO * dx)
    m[0] = m[-1] = 0.5 * RHO * dx
    u = np.zeros(cells + 1)
    v = v0 * np.sin(BETA * X)  # v^{1/2} = v^0 + a(u = 0) dt / 2 = v^0
    t_end = periods * PERIOD
    n = int(np.ceil(t_end / (cfl * dx / C)))
    dt = t_end / n
    amp = v0 * (1 - np.cos(BETA * L)) / (BETA * L)
    u_ref = v0 / OMEGA
    sq = 0.0
    snap = {}
    marks = {int(round(0.5 * PERIOD / dt)): "u_half", int(round(PERIOD / dt)): "u_period"}
    for i in range(n):
        u += v * dt
        u[0] = 0.0
        strain = np.diff(u) / dx
        P = E * np.log1p(strain) if law == "log" else E * strain
        f = np.zeros(cells + 1)
        f[1:] -= P
        f[:-1] += P
        v += f / m * dt
        v[0] = 0.0
        t_v = (i + 1.5) * dt
        com = np.sum(m * v) / np.sum(m)
        sq += ((com - amp * np.cos(OMEGA * t_v)) / amp) ** 2
        if i + 1 in marks:
            t_x = (i + 1) * dt
            err = u - u_ref * np.sin(BETA * X) * np.sin(OMEGA * t_x)
            snap[marks[i + 1]] = np.sqrt(np.sum(m * err * err) / np.sum(m)) / u_ref
    err = u - u_ref * np.sin(BETA * X) * np.sin(OMEGA * n * dt)
    return {"com_rms": np.sqrt(sq / n),
            "u_end": np.sqrt(np.sum(m * err * err) / np.sum(m)) / u_ref, **snap}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--v0", type=float, nargs="+", default=[0.1, 0.01, 0.001])
    ap.add_argument("--cells", type=int, default=1000)
    args = ap.parse_args()
    print("| v0 (m/s) | strain amplitude v0/c | law | com_rms | u_end (5.125 T) | u at T/2 | u at T |")
    print("|---|---|---|---|---|---|---|")
    for v0 in args.v0:
        for law in ("linear", "log"):
            r = run(v0, law, args.cells)
            print(f"| {v0:g} | {v0 / C:.0e} | {law} | {r['com_rms']:.2e} | {r['u_end']:.2e} | "
                  f"{r['u_half']:.2e} | {r['u_period']:.2e} |", flush=True)


if __name__ == "__main__":
    main()
