#!/usr/bin/python3
"""Momentum enhancement and ejecta of a run with a [beta] table (issue 32; docs/validation-dart.md).

Prints, from RUN/timeseries.csv and RUN/ejecta_launch.csv (pure Python: no numpy needed):
  - beta(t) at up to --rows times: beta (ejecta in the domain now), beta_target (momentum left
    below the surface) and beta_launch (every ejected point counted once, at its launch), and the
    last value's drift over the last fifth of the run (its convergence in time);
  - the cumulative ejecta mass M(>v) / m_imp against v / U (launch speeds), next to the
    point-source scaling of Housen & Holsapple 2011 (Icarus 211), in its power-law range:
        M(>v) / m = (3 k / 4 pi) (rho / delta)^(1 - 3 nu) (v / (C1 U))^(-3 mu)
    (their Eqs. for v(x) and M(<x) combined, with the end terms (n1 a, n2 R) left out). The
    constants are options; the defaults are the sand class as recalled in this session
    (mu 0.41, nu 0.4, k 0.3, C1 0.55): check them against HH2011's Table 3 before quoting.
With --csv FILE the M(>v) comparison is written as CSV; with --plot FILE.png (matplotlib) both
figures. With --fit LO HI the exponent is fitted to the run: a least-squares line through
log M(>=v) against log(v/U) at every launched point with LO <= v/U <= HI gives the slope -3 mu
(HH2011's power law, Eq. as above) and mu_fit = -slope / 3, printed beside --mu.

Usage: beta.py RUN_DIR [--target-density 2400] [--impactor-density 2703] [--mu 0.41] ...
"""

import argparse
import csv
import math
import os
import sys


def read_timeseries(run):
    with open(os.path.join(run, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    if not rows or "beta" not in rows[0]:
        sys.exit(f"{run}/timeseries.csv has no beta columns: the scene needs a [beta] table")
    return rows


def read_launches(run):
    """(impactor mass kg, impact speed m/s, rows as dicts) of RUN/ejecta_launch.csv."""
    path = os.path.join(run, "ejecta_launch.csv")
    with open(path) as f:
        first = f.readline().lstrip("# ").split()
        meta = dict(kv.split("=") for kv in first)
        rows = list(csv.DictReader(f))
    return float(meta["impactor_mass_kg"]), float(meta["impact_speed_m_per_s"]), rows


def hh2011(v_over_u, a):
    """M(>v) / m of the point-source power law (module docstring)."""
    ratio = a.target_density / a.impactor_density
    return (3 * a.k / (4 * math.pi)) * ratio ** (1 - 3 * a.nu) * (v_over_u / a.C1) ** (-3 * a.mu)


def beta_table(rows, n):
    step = max(1, len(rows) // n)
    picked = rows[::step] + ([rows[-1]] if (len(rows) - 1) % step else [])
    print("time_s        ejecta_kg     beta     beta_target  beta_launch")
    for r in picked:
        print(f"{float(r['time_s']):<13.4g} {float(r['ejecta_mass_kg']):<13.4g} "
              f"{float(r['beta']):<8.4f} {float(r['beta_target']):<12.4f} "
              f"{float(r['beta_launch']):.4f}")
    tail = rows[len(rows) * 4 // 5:]
    for key in ("beta", "beta_target", "beta_launch"):
        first, last = float(tail[0][key]), float(tail[-1][key])
        print(f"{key}: {last:.4f} at the end; changed by {last - first:+.4f} over the last fifth "
              f"of the run (t = {float(tail[0]['time_s']):.4g} to {float(tail[-1]['time_s']):.4g} s)")


def mass_speed(launches, m_imp, speed, a, escape):
    """Rows (v/U, M(>v)/m simulated, HH2011) at logarithmically spaced speeds."""
    pts = sorted(((float(r["speed_m_per_s"]), float(r["mass_kg"])) for r in launches),
                 reverse=True)
    pts = [p for p in pts if p[0] >= escape]
    if not pts:
        return []
    out, cum, i = [], 0.0, 0
    lo, hi = max(pts[-1][0], 1e-12), pts[0][0]
    n = 20
    for j in range(n + 1):
        v = hi * (lo / hi) ** (j / n)
        while i < len(pts) and pts[i][0] >= v:
            cum += pts[i][1]
            i += 1
        out.append((v / speed, cum / m_imp, hh2011(v / speed, a)))
    return out


def fit_mu(launches, m_imp, speed, lo, hi, escape):
    """(mu, prefactor, points used) of M(>=v)/m = A (v/U)^(-3 mu) fitted over lo <= v/U <= hi:
    least squares in log-log through the cumulative mass at every launched point's speed."""
    pts = sorted(((float(r["speed_m_per_s"]), float(r["mass_kg"])) for r in launches),
                 reverse=True)
    xs, ys, cum = [], [], 0.0
    for v, m in pts:
        if v < escape:
            break
        cum += m
        x = v / speed
        if lo <= x <= hi and cum > 0.0:
            xs.append(math.log(x))
            ys.append(math.log(cum / m_imp))
    n = len(xs)
    if n < 2:
        return float("nan"), float("nan"), n
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    if sxx == 0.0:
        return float("nan"), float("nan"), n
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    return -slope / 3.0, math.exp(my - slope * mx), n


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("--rows", type=int, default=12, help="beta(t) rows printed")
    ap.add_argument("--target-density", type=float, default=2400.0, help="rho, kg/m^3 (bulk)")
    ap.add_argument("--impactor-density", type=float, default=2703.0, help="delta, kg/m^3")
    ap.add_argument("--mu", type=float, default=0.41)
    ap.add_argument("--nu", type=float, default=0.4)
    ap.add_argument("--k", type=float, default=0.3)
    ap.add_argument("--C1", type=float, default=0.55)
    ap.add_argument("--escape-speed", type=float, default=0.0,
                    help="leave out launches slower than this (m/s)")
    ap.add_argument("--fit", nargs=2, type=float, metavar=("LO", "HI"),
                    help="fit mu to M(>v) over LO <= v/U <= HI")
    ap.add_argument("--csv", help="write the M(>v) comparison here")
    ap.add_argument("--plot", help="write beta(t) and M(>v) figures here (needs matplotlib)")
    a = ap.parse_args()
    rows = read_timeseries(a.run)
    beta_table(rows, a.rows)
    m_imp, speed, launches = read_launches(a.run)
    table = mass_speed(launches, m_imp, speed, a, a.escape_speed)
    print(f"\nM(>v)/m_imp against v/U ({len(launches)} launched points; m_imp = {m_imp:.4g} kg, "
          f"U = {speed:.4g} m/s); HH2011: mu {a.mu}, nu {a.nu}, k {a.k}, C1 {a.C1}")
    print("v/U          M(>v)/m      HH2011       ratio")
    for x, m, h in table:
        print(f"{x:<12.4g} {m:<12.4g} {h:<12.4g} {m / h if h > 0 else float('nan'):.3g}")
    if a.fit:
        mu, pre, n = fit_mu(launches, m_imp, speed, a.fit[0], a.fit[1], a.escape_speed)
        print(f"\nfit over {a.fit[0]:g} <= v/U <= {a.fit[1]:g} ({n} points): mu_fit {mu:.4f} "
              f"(M(>v)/m = {pre:.4g} (v/U)^{-3 * mu:.4f}); --mu {a.mu}")
    if a.csv:
        with open(a.csv, "w") as f:
            f.write("v_over_U,M_over_m,hh2011_M_over_m\n")
            for x, m, h in table:
                f.write(f"{x:.6g},{m:.6g},{h:.6g}\n")
    if a.plot:
        import plot_common as pc  # tools/plot_common.py: Agg, dpi, common labels
        fig, (ax, ax2) = pc.subplots(1, 2, figsize=(10, 4))
        t = [float(r["time_s"]) * 1e3 for r in rows]
        for key in ("beta", "beta_target", "beta_launch"):
            ax.plot(t, [float(r[key]) for r in rows], label=key)
        ax.axhspan(3.61 - 0.25, 3.61 + 0.19, color="gray", alpha=0.3, label="DART 3.61 (Cheng 2023)")
        pc.label(ax, "t_ms", "beta")
        pc.legend(ax)
        ax2.loglog([x for x, _, _ in table], [m for _, m, _ in table], "o-", label="simulated")
        ax2.loglog([x for x, _, _ in table], [h for _, _, h in table], "--", label="HH2011")
        pc.label(ax2, "v_over_U", "M_over_m")
        pc.legend(ax2)
        pc.save(fig, a.plot)

if __name__ == "__main__":
    main()
