#!/usr/bin/python3
"""Spherically symmetric linear elastic wave: exact solution, checks of its derivation, and the
tension an outgoing wave of a given radial-stress history must carry.

Usage:
  spherical_wave.py check                       # derivation checks (t = 0, equation of motion)
  spherical_wave.py profiles [--out FILE.png]   # the test problem's profiles at t = 2.5 a / c_p
  spherical_wave.py lab RUN_DIR [--r1 0.015] [--r2 0.03] [--out FILE.png]
      RUN_DIR: an undamaged `shatter run` of scenes/lab-impact.toml with dense snapshots. Takes
      the radial-stress history at r1 along the axis from the impact point into the target,
      propagates it to r2 as an outgoing elastic spherical wave (below) and compares radial and
      hoop stress there with shatter's.

Theory (docs/verification.md, "Spherical elastic wave"). Irrotational motion u = grad(phi) with
phi_tt = c_p^2 lap(phi). For spherical symmetry w = r phi solves the 1D wave equation
w_tt = c_p^2 w_rr, so
    u_r  = w_r / r - w / r^2,                 v_r = w_rt / r - w_t / r^2,
    s_rr = M w_rr / r - 4 G (w_r / r^2 - w / r^3),
    s_tt = lam w_rr / r + 2 G (w_r / r^2 - w / r^3)       (= lam div u + 2 G u_r / r),
with M = lam + 2 G and lap(phi) = w_rr / r.
Test problem: phi(r, 0) = 0 (no displacement, no stress) and phi_t(r, 0) = psi0(r), i.e.
v0 = grad(psi0), with psi0 = A (1 - r^2/a^2)^3 for r < a (C^2 at r = a). d'Alembert with the odd
extension of r psi0 gives w = F(r - c t) - F(r + c t), F(s) = A a^2 / (16 c) (1 - s^2/a^2)^4
(|s| < a, else 0). For c t > a only the outgoing F(r - c t) is left: phi = F(r - c t) / r.
Outgoing wave of a given s_rr history at radius r0: with xi = r0 - c t, w = F(xi) solves
    M F'' - 4 G F' / r0 + 4 G F / r0^2 = r0 s_rr(xi),  F = F' = 0 ahead of the wave,
and then s_tt(t) = lam F'' / r0 + 2 G (F' / r0^2 - F / r0^3) at r0.
"""

import argparse
import os
import sys

import numpy as np


class Elastic:
    def __init__(self, rho, young, poisson):
        self.rho = rho
        self.G = young / (2 * (1 + poisson))
        self.K = young / (3 * (1 - 2 * poisson))
        self.lam = self.K - 2 * self.G / 3
        self.M = self.lam + 2 * self.G
        self.c = np.sqrt(self.M / rho)


BASALT = Elastic(2700.0, 53.1e9, 0.15)


class Bump:
    """F(s) = k b(s), b = (1 - s^2/a^2)^4 on |s| < a, k = A a^2 / (16 c); derivatives in s."""

    def __init__(self, a, amplitude, c):
        self.a, self.A, self.c = a, amplitude, c
        self.k = amplitude * a * a / (16 * c)

    def d(self, s, n):
        a = self.a
        q = (s / a) ** 2
        inside = np.abs(s) < a
        one = np.where(inside, 1 - q, 0.0)
        if n == 0:
            b = one ** 4
        elif n == 1:
            b = -8 * s / a**2 * one ** 3
        elif n == 2:
            b = -8 / a**2 * one ** 2 * (1 - 7 * q)
        else:  # n == 3
            b = 48 * s / a**4 * one * (3 - 7 * q)
        return self.k * np.where(inside, b, 0.0)

    def psi0(self, r):
        return np.where(r < self.a, self.A * np.clip(1 - (r / self.a) ** 2, 0, None) ** 3, 0.0)


def exact(m, bump, r, t):
    """u_r, v_r, s_rr, s_tt of the test problem at radius r > 0, time t."""
    c = m.c
    sm, sp = r - c * t, r + c * t
    w = bump.d(sm, 0) - bump.d(sp, 0)
    wr = bump.d(sm, 1) - bump.d(sp, 1)
    wrr = bump.d(sm, 2) - bump.d(sp, 2)
    wt = -c * (bump.d(sm, 1) + bump.d(sp, 1))
    wrt = -c * (bump.d(sm, 2) + bump.d(sp, 2))
    ur = wr / r - w / r**2
    vr = wrt / r - wt / r**2
    srr = m.M * wrr / r - 4 * m.G * (wr / r**2 - w / r**3)
    stt = m.lam * wrr / r + 2 * m.G * (wr / r**2 - w / r**3)
    return ur, vr, srr, stt


def rms(x):
    return np.sqrt(np.mean(x[2:-2] ** 2))


def check():
    m = Elastic(2700.0, 53.1e9, 0.15)
    a = 0.01
    bump = Bump(a, -1.0, m.c)
    r = np.linspace(1e-4, 3 * a, 3001)
    ur, vr, srr, stt = exact(m, bump, r, 0.0)
    # t = 0: no displacement, no stress, v = grad(psi0).
    v0 = np.gradient(bump.psi0(r), r)
    scale = np.max(np.abs(v0))
    print(f"t=0: max|u_r| {np.max(np.abs(ur)):.2e}, max|s| {np.max(np.abs(srr)) + np.max(np.abs(stt)):.2e}, "
          f"max|v - grad psi0| / max|v0| {np.max(np.abs(vr - v0)[5:-5]) / scale:.2e}")
    # Equation of motion rho v_t = d s_rr/dr + 2 (s_rr - s_tt) / r, and v = u_t, by differences.
    worst_eom = worst_kin = 0.0
    for t in (0.3 * a / m.c, 1.7 * a / m.c, 3.0 * a / m.c):
        dt = 1e-4 * a / m.c
        r = np.linspace(0.2 * a, 5 * a, 8001)
        _, v1, _, _ = exact(m, bump, r, t + dt)
        _, v0_, _, _ = exact(m, bump, r, t - dt)
        u1, _, _, _ = exact(m, bump, r, t + dt)
        u0, _, _, _ = exact(m, bump, r, t - dt)
        ur, vr, srr, stt = exact(m, bump, r, t)
        lhs = m.rho * (v1 - v0_) / (2 * dt)
        rhs = np.gradient(srr, r) + 2 * (srr - stt) / r
        # RMS, not max: F'''' jumps at |s| = a, where central differences are only first order.
        worst_eom = max(worst_eom, rms(lhs - rhs) / np.max(np.abs(lhs)))
        worst_kin = max(worst_kin, np.max(np.abs((u1 - u0) / (2 * dt) - vr)) / np.max(np.abs(vr)))
        # Strains from u_r agree with the stress formulas (Hooke's law).
        err = np.gradient(ur, r)
        s_hooke = m.lam * (err + 2 * ur / r) + 2 * m.G * err
        worst_eom = max(worst_eom, rms(s_hooke - srr) / np.max(np.abs(srr)))
    print(f"equation of motion and Hooke (relative, by differences): {worst_eom:.2e}; "
          f"v = u_t: {worst_kin:.2e}")
    ok = worst_eom < 1e-4 and worst_kin < 1e-5
    print("OK" if ok else "FAILED")
    return 0 if ok else 1


def profiles(out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    m = Elastic(2700.0, 53.1e9, 0.15)
    a = 0.25
    bump = Bump(a, -1.0, m.c)
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    for tc in (1.5, 2.5, 4.0):
        r = np.linspace(0.02, 5.5 * a, 2000)
        ur, vr, srr, stt = exact(m, bump, r, tc * a / m.c)
        ax[0].plot(r / a, srr, label=f"s_rr, c t = {tc} a")
        ax[0].plot(r / a, stt, "--", label=f"s_tt, c t = {tc} a")
        ax[1].plot(r / a, vr, label=f"v_r, c t = {tc} a")
    ax[0].set_xlabel("r / a")
    ax[0].set_ylabel("stress (Pa)")
    ax[0].legend(fontsize=7)
    ax[1].set_xlabel("r / a")
    ax[1].set_ylabel("v_r (m/s)")
    ax[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print("wrote", out)


def source_from_radial(m, t, srr, r0):
    """Outgoing elastic wave with radial-stress history srr(t) at r0: returns F, F', F'' on the
    retarded time t (xi = r0 - c t), by integrating
        M F'' - 4 G F' / r0 + 4 G F / r0^2 = r0 s_rr
    from rest ahead of the wave (xi decreases as t grows, so dF/dt = -c F')."""
    dxi = m.c * (t[1] - t[0])
    n = len(t)
    F, Fp, Fpp = np.zeros(n), np.zeros(n), np.zeros(n)
    for k in range(n):
        Fpp[k] = (r0 * srr[k] + 4 * m.G * Fp[k] / r0 - 4 * m.G * F[k] / r0**2) / m.M
        if k + 1 < n:  # symplectic Euler, one step of -dxi
            Fp[k + 1] = Fp[k] - dxi * Fpp[k]
            F[k + 1] = F[k] - dxi * Fp[k + 1]
    return F, Fp, Fpp


def wave_at(m, F, Fp, Fpp, r):
    """Eqs. (1), (2) of the module doc for the outgoing wave w = F(r - c t) at radius r."""
    near = Fp / r**2 - F / r**3
    return m.M * Fpp / r - 4 * m.G * near, m.lam * Fpp / r + 2 * m.G * near, Fp / r - F / r**2


def read_axis_history(run_dir, radii, width, cone):
    """Mean radial and hoop stress and largest principal stress of the target points within
    `width` of each distance in `radii` from the impact point and within `cone` degrees of the
    line from the impact point through the target centre, at every snapshot."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "tools"))
    import shatter_plot as sp
    files = sp.snapshots(run_dir)
    _, first, axis = sp.read_snapshot(files[0])
    body = first["body"].astype(int)
    target, centre, radius, n_in, impact = sp.impact_geometry(first, axis)
    pos0 = np.stack([first["x"], first["y"], first["z"]], 1)
    tsel = body == target
    x0 = pos0[tsel] - impact
    d = np.linalg.norm(x0, axis=1)
    cosang = x0 @ n_in / np.maximum(d, 1e-12)
    groups = []
    for r0 in radii:
        pick = (np.abs(d - r0) < width) & (cosang > np.cos(np.radians(cone)))
        groups.append(np.sort(first["id"][tsel][pick].astype(np.int64)))
    out = {r0: {"t": [], "srr": [], "stt": [], "smax": []} for r0 in radii}
    for path in files:
        t, c, _ = sp.read_snapshot(path)
        ids = c["id"].astype(np.int64)
        order = np.argsort(ids)
        for r0, g in zip(radii, groups):
            sel = order[np.searchsorted(ids[order], g)]
            s = sp.stress_tensors(c, sel)
            x = np.stack([c["x"][sel], c["y"][sel], c["z"][sel]], 1) - impact
            nn = x / np.linalg.norm(x, axis=1)[:, None]
            rr = np.einsum("ni,nij,nj->n", nn, s, nn)
            h = out[r0]
            h["t"].append(t)
            h["srr"].append(np.mean(rr))
            h["stt"].append(np.mean(0.5 * (np.trace(s, axis1=1, axis2=2) - rr)))
            h["smax"].append(np.mean(np.linalg.eigvalsh(s)[:, -1]))
    for r0, g in zip(radii, groups):
        out[r0] = {k: np.array(v) for k, v in out[r0].items()}
        out[r0]["points"] = len(g)
    return out, radius


def lab(run_dir, r1, r2, out, width, cone):
    """Takes shatter's radial-stress history at r1 (first passage only, up to the first
    zero-crossing after the tensile phase), propagates it as an outgoing elastic spherical wave
    to r2, and compares s_rr and s_tt there with shatter's; also the hoop stress implied at r1."""
    m = BASALT
    hist, radius = read_axis_history(run_dir, [r1, r2], width, cone)
    h1, h2 = hist[r1], hist[r2]
    t = np.linspace(0, h1["t"][-1], 6001)
    # First passage at r1: until the echo from the target's far side (2 R - r1 further) returns.
    t_echo = r1 / m.c + 2 * (2 * radius - r1) / m.c
    s1 = np.where(t < t_echo, np.interp(t, h1["t"], h1["srr"]), 0.0)
    F, Fp, Fpp = source_from_radial(m, t, s1, r1)
    srr1, stt1, ur1 = wave_at(m, F, Fp, Fpp, r1)
    srr2, stt2, ur2 = wave_at(m, F, Fp, Fpp, r2)
    t2 = t + (r2 - r1) / m.c
    for r0, h in ((r1, h1), (r2, h2)):
        print(f"shatter at {r0 * 1e3:.0f} mm ({h['points']} points, +-{cone} deg): min s_rr "
              f"{h['srr'].min() / 1e6:.0f}, max s_rr {h['srr'].max() / 1e6:.0f}, max s_tt "
              f"{h['stt'].max() / 1e6:.0f}, max of the mean largest principal "
              f"{h['smax'].max() / 1e6:.0f} MPa")
    print(f"elastic at {r1 * 1e3:.0f} mm from its own s_rr: max s_tt {stt1.max() / 1e6:.0f} MPa, "
          f"max u_r {ur1.max() * 1e6:.1f} um (u_r / r = {ur1.max() / r1:.1e})")
    # The least tension an elastic wave with the same compressive lobe can carry: s_rr equal to
    # shatter's compressive lobe and zero after it; the hoop tension then comes from u_r / r.
    for r0, h in ((r1, h1), (r2, h2)):
        s0 = np.interp(t, h["t"], h["srr"])
        k0 = np.argmin(s0)
        lobe = np.zeros_like(s0, dtype=bool)
        lo, hi = k0, k0
        while lo > 0 and s0[lo - 1] < 0:
            lo -= 1
        while hi + 1 < len(t) and s0[hi + 1] < 0:
            hi += 1
        lobe[lo:hi + 1] = True
        half = t[s0 <= 0.5 * s0[k0]]
        Fc = source_from_radial(m, t, np.where(lobe, s0, 0.0), r0)
        _, sttc, urc = wave_at(m, *Fc, r0)
        print(f"compressive lobe only at {r0 * 1e3:.0f} mm (peak {-s0[k0] / 1e6:.0f} MPa, "
              f"{(t[hi] - t[lo]) * 1e6:.1f} us long, FWHM {(half[-1] - half[0]) * 1e6:.1f} us): "
              f"max s_tt {sttc.max() / 1e6:.0f} MPa, max u_r {urc.max() * 1e6:.1f} um")
    print(f"elastic at {r2 * 1e3:.0f} mm from shatter's s_rr at {r1 * 1e3:.0f} mm: min s_rr "
          f"{srr2.min() / 1e6:.0f}, max s_rr {srr2.max() / 1e6:.0f}, max s_tt {stt2.max() / 1e6:.0f} MPa")
    if out:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(11, 4), sharey=True)
        for a_, r0, h, srr_e, stt_e, te in ((ax[0], r1, h1, srr1, stt1, t),
                                             (ax[1], r2, h2, srr2, stt2, t2)):
            a_.plot(h["t"] * 1e6, h["srr"] / 1e6, "o-", ms=3, label="shatter s_rr (radial)")
            a_.plot(h["t"] * 1e6, h["stt"] / 1e6, "s-", ms=3, label="shatter s_tt (hoop)")
            a_.plot(h["t"] * 1e6, h["smax"] / 1e6, "^-", ms=3, label="shatter largest principal")
            tag = "elastic, from its own s_rr" if r0 == r1 else f"elastic, propagated from {r1 * 1e3:.0f} mm"
            if r0 != r1:
                a_.plot(te * 1e6, srr_e / 1e6, "b--", label=f"s_rr {tag}")
            a_.plot(te * 1e6, stt_e / 1e6, "k--", label=f"s_tt {tag}")
            a_.axhline(0, color="gray", lw=0.5)
            a_.axhline(40.2, color="r", lw=0.5, ls=":")
            a_.set_xlim(0, h["t"][-1] * 1e6)
            a_.set_xlabel("t (us)")
            a_.set_title(f"{r0 * 1e3:.0f} mm from the impact point (axis +-{cone} deg)", fontsize=9)
            a_.legend(fontsize=7)
        ax[0].set_ylabel("stress (MPa); dotted: 40.2 MPa")
        fig.tight_layout()
        fig.savefig(out, dpi=110)
        print("wrote", out)


def sharpe(a0, r, history, duration, scale_to):
    """Sharpe's problem: a spherical cavity of radius a0 in an infinite elastic body, loaded by a
    pressure p(t) (the boundary condition s_rr(a0, t) = -p(t)); the outgoing wave's s_rr, s_tt
    and u_r at radius r, scaled so that the peak radial compression there is `scale_to` (Pa).
    p(t): the contact-force history in `history` (CSV: t, F) or a half-sine of `duration`."""
    m = BASALT
    t = np.linspace(0, 40e-6, 16001)
    if history:
        d = np.loadtxt(history, delimiter=",", skiprows=1)
        # The first push only: the force up to its first change of sign.
        end = d[np.argmax(d[:, 1] <= 0), 0] if np.any(d[:, 1] <= 0) else d[-1, 0]
        p = np.where(t < end, np.clip(np.interp(t, d[:, 0], d[:, 1]), 0, None), 0.0)
    else:
        p = np.where(t < duration, np.sin(np.pi * t / duration), 0.0)
    F, Fp, Fpp = source_from_radial(m, t, -p, a0)
    srr, stt, ur = wave_at(m, F, Fp, Fpp, r)
    k = scale_to / -srr.min()
    srr, stt, ur = srr * k, stt * k, ur * k
    # Width of the compressive lobe around the peak compression.
    k0 = np.argmin(srr)
    lo, hi = k0, k0
    while lo > 0 and srr[lo - 1] < 0:
        lo -= 1
    while hi + 1 < len(t) and srr[hi + 1] < 0:
        hi += 1
    width = t[hi] - t[lo]
    print(f"cavity {a0 * 1e3:.1f} mm, at {r * 1e3:.0f} mm: peak compression {-srr.min() / 1e6:.0f} MPa "
          f"(compressive phase {width * 1e6:.1f} us), radial tension {srr.max() / 1e6:.0f} MPa, "
          f"hoop tension {stt.max() / 1e6:.0f} MPa, hoop compression {-stt.min() / 1e6:.0f} MPa, "
          f"max u_r {ur.max() * 1e6:.1f} um (u_r/r {ur.max() / r:.1e}, 2(lam+G) u_r/r "
          f"{2 * (m.lam + m.G) * ur.max() / r / 1e6:.0f} MPa)")
    return t + (r - a0) / m.c, srr, stt, ur


def sharpe_plot(run_dir, history, r, scale_to, out, cone=20.0, width=1.5e-3):
    """Shatter's stresses at r on the axis against Sharpe's elastic wave driven by the contact
    force history, for two cavity radii (the projectile radius and twice it)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    hist, _ = read_axis_history(run_dir, [r], width, cone)
    h = hist[r]
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    ax.plot(h["t"] * 1e6, h["srr"] / 1e6, "o-", ms=3, color="C0", label="shatter s_rr")
    ax.plot(h["t"] * 1e6, h["stt"] / 1e6, "s-", ms=3, color="C1", label="shatter s_tt (hoop)")
    for a0, ls in ((3.5e-3, "--"), (7e-3, ":")):
        t, srr, stt, _ = sharpe(a0, r, history, 0.0, scale_to)
        ax.plot(t * 1e6, srr / 1e6, ls, color="C0", label=f"elastic s_rr, cavity {a0 * 1e3:.1f} mm")
        ax.plot(t * 1e6, stt / 1e6, ls, color="C1", label=f"elastic s_tt, cavity {a0 * 1e3:.1f} mm")
    ax.axhline(0, color="gray", lw=0.5)
    ax.axhline(40.2, color="r", lw=0.6, ls="-.", label="40.2 MPa")
    ax.set_xlim(0, h["t"][-1] * 1e6)
    ax.set_xlabel("t (us)")
    ax.set_ylabel("stress (MPa)")
    ax.set_title(f"{r * 1e3:.0f} mm from the impact point (axis +-{cone:.0f} deg): shatter, undamaged, "
                 f"and Sharpe's elastic wave\ndriven by shatter's contact force, scaled to the same "
                 f"peak compression", fontsize=8)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print("wrote", out)


def lab_table(run_dir, cone, window, out):
    """Per distance from the impact point (2.5 mm bins, points within `cone` degrees of the axis
    into the target): medians of the peak radial compression, and of the peak radial tension,
    hoop tension and largest principal stress during the first passage (from the arrival d / c to
    d / c + window) and over the whole run."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "tools"))
    import shatter_plot as sp
    m = BASALT
    files = sp.snapshots(run_dir)
    _, first, axis = sp.read_snapshot(files[0])
    body = first["body"].astype(int)
    target, centre, radius, n_in, impact = sp.impact_geometry(first, axis)
    pos0 = np.stack([first["x"], first["y"], first["z"]], 1)
    tsel = body == target
    x0 = pos0[tsel] - impact
    d = np.linalg.norm(x0, axis=1)
    pick = (x0 @ n_in) / np.maximum(d, 1e-12) > np.cos(np.radians(cone))
    ids = np.sort(first["id"][tsel][pick].astype(np.int64))
    d = d[pick][np.argsort(first["id"][tsel][pick].astype(np.int64))]
    n = len(ids)
    comp = np.zeros(n)
    keys = ("rr", "tt", "max")
    first_pass = {k: np.full(n, -np.inf) for k in keys}
    whole = {k: np.full(n, -np.inf) for k in keys}
    for path in files[1:]:
        t, c, _ = sp.read_snapshot(path)
        allid = c["id"].astype(np.int64)
        order = np.argsort(allid)
        sel = order[np.searchsorted(allid[order], ids)]
        s = sp.stress_tensors(c, sel)
        x = np.stack([c["x"][sel], c["y"][sel], c["z"][sel]], 1) - impact
        nn = x / np.linalg.norm(x, axis=1)[:, None]
        rr = np.einsum("ni,nij,nj->n", nn, s, nn)
        vals = {"rr": rr, "tt": 0.5 * (np.trace(s, axis1=1, axis2=2) - rr),
                "max": np.linalg.eigvalsh(s)[:, -1]}
        comp = np.minimum(comp, rr)
        early = t <= d / m.c + window
        for k in keys:
            whole[k] = np.maximum(whole[k], vals[k])
            first_pass[k] = np.where(early, np.maximum(first_pass[k], vals[k]), first_pass[k])
    edges = np.arange(5e-3, 2 * radius + 1e-9, 5e-3)
    print(f"points within {cone} deg of the axis; first passage: t <= d / c_p + {window * 1e6:.1f} us")
    print("  d (mm) | points | peak s_rr compr. | first passage: s_rr tens.  s_tt tens.  max princ."
          " | whole run: max princ.  (MPa, medians)")
    rows = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        b = (d >= lo) & (d < hi)
        if b.sum() < 5:
            continue
        med = lambda v: np.median(v[b]) / 1e6  # noqa: E731
        row = (0.5 * (lo + hi) * 1e3, b.sum(), -med(comp), med(first_pass["rr"]),
               med(first_pass["tt"]), med(first_pass["max"]), med(whole["max"]))
        rows.append(row)
        print("  {:6.1f} | {:6d} | {:16.0f} | {:26.0f} {:11.0f} {:11.0f} | {:21.0f}".format(*row))
    if out:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        r_ = np.array(rows)
        fig, ax = plt.subplots(figsize=(6.5, 4))
        ax.plot(r_[:, 0], r_[:, 2], "s-", label="peak radial compression")
        ax.plot(r_[:, 0], r_[:, 3], "o-", label="radial tension, first passage")
        ax.plot(r_[:, 0], r_[:, 4], "^-", label="hoop tension, first passage")
        ax.plot(r_[:, 0], r_[:, 6], "k:", label="largest principal, whole run")
        ax.axhline(40.2, color="r", lw=0.6, ls="--", label="40.2 MPa")
        ax.set_yscale("log")
        ax.set_xlabel("initial distance from the impact point (mm)")
        ax.set_ylabel("MPa (medians)")
        ax.set_title(f"undamaged lab impact, within {cone:.0f} deg of the axis", fontsize=9)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3, which="both")
        fig.tight_layout()
        fig.savefig(out, dpi=110)
        print("wrote", out)


def study_plot(prefix, cells, out):
    """Shell-mean profiles written by the test's convergence study (SPHERICAL_WAVE_CSV=prefix,
    tests/verification/mpm/spherical_wave_test.cpp) against the exact solution."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(14, 4))
    cols = (("srr", "s_rr (Pa)"), ("stt", "s_tt, hoop (Pa)"), ("vr", "v_r (m/s)"))
    for n in cells:
        d = np.genfromtxt(f"{prefix}{n}.csv", delimiter=",", names=True)
        r = d["r_m"] / 0.1
        for a_, (k, _) in zip(ax, cols):
            name = [c for c in d.dtype.names if c.startswith(k + "_mpm")][0]
            a_.plot(r, d[name], label=f"shatter, a/h = {n}")
    for a_, (k, label) in zip(ax, cols):
        name = [c for c in d.dtype.names if c.startswith(k + "_exact")][0]
        a_.plot(r, d[name], "k--", lw=2, label="exact")
        a_.axhline(0, color="gray", lw=0.5)
        a_.set_xlabel("r / a")
        a_.set_ylabel(label)
        a_.legend(fontsize=7)
    ax[0].set_title("radial stress (shell means, width h)", fontsize=9)
    ax[1].set_title("hoop stress", fontsize=9)
    ax[2].set_title("radial velocity", fontsize=9)
    fig.suptitle("spherical elastic wave at c t = 2.5 a (start from rest, v0 = grad psi0)",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    print("wrote", out)


def contact_force(run_dir, out):
    """Contact force of the projectile on the target along the axis into the target, from the
    projectile's momentum in consecutive snapshots (F = -dp/dt); writes CSV t_s,F_N for
    `sharpe --history`."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "tools"))
    import shatter_plot as sp
    files = sp.snapshots(run_dir)
    _, first, axis = sp.read_snapshot(files[0])
    target, _, _, n_in, _ = sp.impact_geometry(first, axis)
    ts, ps = [], []
    for path in files:
        t, c, _ = sp.read_snapshot(path)
        b = c["body"].astype(int) != target
        v = np.stack([c["vx"][b], c["vy"][b], c["vz"][b]], 1)
        ts.append(t)
        ps.append((c["mass"][b] @ v) @ n_in)
    ts, ps = np.array(ts), np.array(ps)
    force = -np.gradient(ps, ts)
    np.savetxt(out, np.c_[ts, force], delimiter=",", header="t_s,F_N", comments="")
    k = np.argmax(force)
    print(f"peak contact force {force[k] / 1e3:.0f} kN at {ts[k] * 1e6:.2f} us; impulse "
          f"{ps[0] - ps.min():.3f} kg m/s; wrote {out}")


def lab_noise(run_dir, cell):
    """Grid-scale noise in the lab impact: per distance from the impact point, the median over
    target points of the peak (over snapshots) largest principal stress of the point itself and
    of the mean stress tensor of the points sharing its grid cell (edge `cell`, current
    positions): the cell mean removes what varies from point to point within a cell."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "tools"))
    import shatter_plot as sp
    files = sp.snapshots(run_dir)
    _, first, axis = sp.read_snapshot(files[0])
    body = first["body"].astype(int)
    target, _, radius, _, impact = sp.impact_geometry(first, axis)
    pos0 = np.stack([first["x"], first["y"], first["z"]], 1)
    tsel = body == target
    ids = first["id"][tsel].astype(np.int64)
    order0 = np.argsort(ids)
    ids = ids[order0]
    dist = np.linalg.norm(pos0[tsel][order0] - impact, axis=1)
    peak_p = np.full(len(ids), -np.inf)
    peak_c = np.full(len(ids), -np.inf)
    names = [k for _, k in sp.STRESS_COLUMNS]
    for path in files[1:]:
        t, c, _ = sp.read_snapshot(path)
        allid = c["id"].astype(np.int64)
        o = np.argsort(allid)
        sel = o[np.searchsorted(allid[o], ids)]
        comp = np.stack([c[k][sel] for k in names], 1)
        x = np.stack([c["x"][sel], c["y"][sel], c["z"][sel]], 1)
        key = np.floor(x / cell).astype(np.int64)
        _, inv, cnt = np.unique(key, axis=0, return_inverse=True, return_counts=True)
        inv = inv.ravel()
        mean = np.zeros((len(cnt), 6))
        np.add.at(mean, inv, comp)
        mean /= cnt[:, None]

        def smax(v):
            return np.linalg.eigvalsh(sp.stress_tensors(v))[:, -1]
        peak_p = np.maximum(peak_p, smax(comp))
        peak_c = np.maximum(peak_c, smax(mean)[inv])
    print("  d (mm) | median peak largest principal (MPa): point | cell mean | ratio")
    for lo in np.arange(0, 2 * radius, 5e-3):
        b = (dist >= lo) & (dist < lo + 5e-3)
        if b.sum() < 5:
            continue
        mp, mc = np.median(peak_p[b]), np.median(peak_c[b])
        print(f"  {(lo + 2.5e-3) * 1e3:6.1f} | {mp / 1e6:42.0f} | {mc / 1e6:9.0f} | {mp / mc:5.2f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    sub.add_parser("check")
    p = sub.add_parser("profiles")
    p.add_argument("--out", default="spherical_wave_profiles.png")
    p = sub.add_parser("sharpe")
    p.add_argument("--a0", type=float, default=3.5e-3)
    p.add_argument("--r", type=float, default=0.03)
    p.add_argument("--history", help="CSV t_s,F_N: pressure shape (e.g. the contact force)")
    p.add_argument("--duration", type=float, default=4e-6)
    p.add_argument("--scale-to", type=float, default=250e6)
    p.add_argument("--run", help="shatter run to overlay (with --out)")
    p.add_argument("--out")
    p = sub.add_parser("study-plot")
    p.add_argument("prefix")
    p.add_argument("--cells", type=int, nargs="+", default=[6, 8, 12, 16])
    p.add_argument("--out", default="profiles.png")
    p = sub.add_parser("contact-force")
    p.add_argument("run_dir")
    p.add_argument("--out", default="contact_force.csv")
    p = sub.add_parser("lab-noise")
    p.add_argument("run_dir")
    p.add_argument("--cell", type=float, default=2.4e-3)
    p = sub.add_parser("lab-table")
    p.add_argument("run_dir")
    p.add_argument("--cone", type=float, default=30.0)
    p.add_argument("--window", type=float, default=5e-6)
    p.add_argument("--out")
    p = sub.add_parser("lab")
    p.add_argument("run_dir")
    p.add_argument("--r1", type=float, default=0.015)
    p.add_argument("--r2", type=float, default=0.03)
    p.add_argument("--width", type=float, default=1.5e-3)
    p.add_argument("--cone", type=float, default=20.0)
    p.add_argument("--out")
    a = ap.parse_args()
    if a.cmd == "check":
        return check()
    if a.cmd == "profiles":
        profiles(a.out)
        return 0
    if a.cmd == "study-plot":
        study_plot(a.prefix, a.cells, a.out)
        return 0
    if a.cmd == "contact-force":
        contact_force(a.run_dir, a.out)
        return 0
    if a.cmd == "lab-noise":
        lab_noise(a.run_dir, a.cell)
        return 0
    if a.cmd == "lab-table":
        lab_table(a.run_dir, a.cone, a.window, a.out)
        return 0
    if a.cmd == "sharpe":
        if a.run and a.out:
            sharpe_plot(a.run, a.history, a.r, a.scale_to, a.out)
        else:
            sharpe(a.a0, a.r, a.history, a.duration, a.scale_to)
        return 0
    lab(a.run_dir, a.r1, a.r2, a.out, a.width, a.cone)
    return 0


if __name__ == "__main__":
    sys.exit(main())
