#!/usr/bin/python3
"""beta_launch of the raducan2019 runs against run time and resolution (issue 32, session 20).

For each RUN=COHESION_PA:POROSITY_PCT:FRICTION:CPPR[:CPU_S] it reads RUN/timeseries.csv and
RUN/ejecta_launch.csv (a run continued with `shatter resume` keeps both in one directory) and
prints, beside the iSALE-2D row of docs/figures/dart/raducan2019_beta.csv (Raducan et al. 2019,
derived by studies/dart/raducan2019_beta.py):

  - beta_launch at 5, 10, 20, 50 ms and every 50 ms to the end, its change over each 0.1 s
    (the drift per 0.1 s), over the last fifth of the run, and the energy error at the end;
  - the split by launch speed, as studies/dart/compare_raducan2019.py: 1 + p(>qU) / (m_imp U)
    for q = 5e-2, 2e-2, 1e-2, 1e-3, 1e-4 (the momentum of the ejecta faster than q U only) with
    its drift over the last fifth, and iSALE's value; the launch speeds of the ejecta launched in
    the run's last fifth (their momentum-weighted median, in m/s and in U);
  - with --tracers PATH (a local copy of sr516/iSALE_ejecta_data, read, never copied): iSALE's
    beta counted from its ejecta faster than the median launch speed of our last fifth, i.e. how
    much of iSALE's final beta lies in ejecta slower than what the run launches at its end;
  - --fit: an EXTRAPOLATION, not a result. beta_launch - 1 = A t^k is fitted by least squares in
    log-log over [f t_end, t_end] for each window fraction f of --windows (default 0.5 0.6 0.7
    0.8: the last half to the last fifth). Its basis: in point-source scaling the ejecta launched
    at time t leave from x ~ t^(mu / (1 + mu)) with speed v ~ x^(-1/mu), and their momentum above
    v grows as v^(1 - 3 mu) (M(>v) ~ v^(-3 mu), HH2011 Icarus 211, as recalled), so beta - 1 ~
    t^((3 mu - 1) / (1 + mu)) while the crater grows; the law has no end (the crater stops where
    the strength or gravity stops it), so the extrapolated values at 0.6, 1 and 5 s are what the
    growth would give if it went on at the fitted rate: upper-side estimates when the local
    exponent falls. Printed: A, k, the rms residual in beta, and the values at T of --at.

With --until T the run is cut at T (its time series and launches after T left out): fitting a
run cut at 0.3 s and comparing the extrapolation with the run's own later values tests the
extrapolation.

With --plot FILE.png: beta_launch(t) of every run (log time) with iSALE's final beta dotted and
the fit over the last of --windows dashed beyond each run's end; below, the local exponent d ln(beta_launch - 1) / d ln t
(over a factor 1.25 in t). With --csv FILE the per-run table.

Usage: convergence.py REFERENCE.csv RUN=C:P:F:CPPR[:CPU] [...] [--tracers PATH] [--fit]
       [--windows 0.5 0.6 0.7 0.8] [--at 0.6 1 5] [--until T] [--plot F.png] [--csv F.csv]
"""

import argparse
import csv
import glob
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import plot_common as pc  # noqa: E402  (tools/plot_common.py: Agg, dpi, common labels)
from compare_raducan2019 import read_reference, run_and_point  # noqa: E402  (this folder)

Q = (5e-2, 2e-2, 1e-2, 1e-3, 1e-4)
M_ISALE = 4.0 / 3.0 * math.pi * 0.42**3 * 1000.0  # raducan2019_beta.py: a 0.42 m, delta 1000
U_ISALE = 7000.0


def read_run(run, until=None):
    with open(os.path.join(run, "timeseries.csv")) as f:
        ts = [(float(r["time_s"]), float(r["beta_launch"]), float(r["energy_error"]))
              for r in csv.DictReader(f) if r.get("beta_launch") and r.get("wall_s")]
    if until is not None:
        ts = [r for r in ts if r[0] <= until + 1e-12]
    ts.sort()
    with open(os.path.join(run, "ejecta_launch.csv")) as f:
        meta = dict(kv.split("=") for kv in f.readline().lstrip("# ").split())
        launches = [(float(r["mass_kg"]), float(r["speed_m_per_s"]),
                     float(r["normal_speed_m_per_s"]), float(r["launch_time_s"]))
                    for r in csv.DictReader(f)]
    if until is not None:
        launches = [r for r in launches if r[3] <= until + 1e-12]
    return ts, float(meta["impactor_mass_kg"]), float(meta["impact_speed_m_per_s"]), launches


def at(ts, t):
    """beta_launch at time t, interpolated linearly in the time series."""
    if t <= ts[0][0]:
        return ts[0][1]
    for (t0, b0, _), (t1, b1, _) in zip(ts, ts[1:]):
        if t0 <= t <= t1:
            return b0 + (b1 - b0) * (t - t0) / (t1 - t0) if t1 > t0 else b1
    return ts[-1][1]


def times(t_end):
    out = [0.005, 0.01, 0.02, 0.05]
    t = 0.1
    while t < t_end - 1e-9:
        out.append(round(t, 3))
        t += 0.05
    return [x for x in out if x < t_end - 1e-9] + [t_end]


def weighted_median(values, weights):
    pairs = sorted(zip(values, weights))
    total, acc = sum(weights), 0.0
    for v, w in pairs:
        acc += w
        if acc >= 0.5 * total:
            return v
    return float("nan")


def fit_power(ts, t_lo, t_hi):
    """(A, k, rms residual in beta) of beta - 1 = A t^k by least squares in log-log over
    [t_lo, t_hi], on the time series thinned to 200 evenly spaced samples."""
    pts = [(t, b) for t, b, _ in ts if t_lo <= t <= t_hi and b > 1.0]
    if len(pts) < 3:
        return float("nan"), float("nan"), float("nan")
    step = max(1, len(pts) // 200)
    pts = pts[::step]
    xs = [math.log(t) for t, _ in pts]
    ys = [math.log(b - 1.0) for _, b in pts]
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    k = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    a = math.exp(my - k * mx)
    rms = math.sqrt(sum((1.0 + a * t**k - b) ** 2 for t, b in pts) / n)
    return a, k, rms


def isale_beta_faster(tracers, v):
    """iSALE's 1 + p(>v) / (m_imp U) from a tracer file (columns x, m, v_x, v_y)."""
    import numpy as np
    d = np.genfromtxt(tracers, delimiter=",", names=True)
    speed = np.hypot(d["v_x"], d["v_y"])
    sel = speed > v
    return 1.0 + float(np.sum(d["m"][sel] * d["v_y"][sel])) / (M_ISALE * U_ISALE)


def tracer_file(root, key):
    cohesion, porosity, friction = key
    n = round(math.log10(cohesion))
    if friction == 0.6:
        series, name = "Porosity", f"Yd1e{n}-{porosity:g}.csv"
    else:
        series, name = "Friction", f"Yd1e{n}-{round(10 * friction):02d}.csv"
    hits = sorted(glob.glob(os.path.join(root, series, "*", name)))
    return hits[0] if hits else None


def analyse(run, key, ref_row, a):
    ts, m_imp, u, launches = read_run(run, a.until)
    t_end, b_end, e_end = ts[-1]
    row = {"t_end_s": t_end, "beta_launch": b_end, "isale_beta": float(ref_row["beta"]),
           "difference_pct": 100.0 * (b_end / float(ref_row["beta"]) - 1.0),
           "energy_error_pct": 100.0 * e_end,
           "drift_last_fifth": b_end - at(ts, 0.8 * t_end)}
    table = [(t, at(ts, t)) for t in times(t_end)]
    drifts = []
    t = 0.1
    while t <= t_end + 1e-9:
        drifts.append((round(t - 0.1, 3), round(t, 3), at(ts, t) - at(ts, t - 0.1)))
        t += 0.1
    if t_end - drifts[-1][1] > 1e-3 if drifts else False:
        drifts.append((round(t_end - 0.1, 4), t_end, b_end - at(ts, t_end - 0.1)))
    for q in Q:
        fast = [(m, vn, tl) for m, v, vn, tl in launches if v > q * u and vn > 0.0]
        p = sum(m * vn for m, vn, _ in fast) / (m_imp * u)
        early = sum(m * vn for m, vn, tl in fast if tl <= 0.8 * t_end) / (m_imp * u)
        row[f"beta_gt_{q:g}U"] = 1.0 + p
        row[f"drift_gt_{q:g}U"] = p - early
        row[f"isale_beta_gt_{q:g}U"] = float(ref_row[f"beta_gt_{q:g}U"])
    late = [(v, m * max(vn, 0.0)) for m, v, vn, tl in launches if tl > 0.8 * t_end]
    row["v_late_median_m_per_s"] = weighted_median(*zip(*late)) if late else float("nan")
    row["v_late_median_over_U"] = row["v_late_median_m_per_s"] / u
    if a.tracers:
        tf = tracer_file(a.tracers, key)
        if tf:
            row["isale_beta_gt_v_late"] = isale_beta_faster(tf, row["v_late_median_over_U"]
                                                            * U_ISALE)
    fits = []
    if a.fit:
        for f in a.windows:
            A, k, rms = fit_power(ts, f * t_end, t_end)
            fits.append((f, A, k, rms, [1.0 + A * T**k for T in a.at]))
    return row, table, drifts, fits, ts


def local_exponent(ts, factor=1.25, n=60):
    """d ln(beta - 1) / d ln t over a factor `factor` in t, on a log grid from 10 ms."""
    t_end = ts[-1][0]
    out = []
    lo = 0.01
    for i in range(n + 1):
        t1 = lo * (t_end / lo) ** (i / n)
        t0 = t1 / factor
        if t0 < ts[0][0]:
            continue
        b0, b1 = at(ts, t0), at(ts, t1)
        if b0 > 1.0 and b1 > b0:
            out.append((math.sqrt(t0 * t1), math.log((b1 - 1.0) / (b0 - 1.0)) / math.log(factor)))
        elif b0 > 1.0:
            out.append((math.sqrt(t0 * t1), 0.0))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("reference")
    ap.add_argument("runs", nargs="+", help="RUN=COHESION_PA:POROSITY_PCT:FRICTION:CPPR[:CPU_S]")
    ap.add_argument("--tracers", help="local copy of sr516/iSALE_ejecta_data")
    ap.add_argument("--fit", action="store_true", help="fit beta - 1 = A t^k (an extrapolation)")
    ap.add_argument("--windows", nargs="+", type=float, default=[0.5, 0.6, 0.7, 0.8])
    ap.add_argument("--at", nargs="+", type=float, default=[0.6, 1.0, 5.0])
    ap.add_argument("--until", type=float, help="cut every run at this time (s)")
    ap.add_argument("--plot")
    ap.add_argument("--csv")
    a = ap.parse_args()
    ref = read_reference(a.reference)
    rows, curves = [], []
    for spec in a.runs:
        run, key, fields = run_and_point(spec)
        row, table, drifts, fits, ts = analyse(run, key, ref[key], a)
        name = os.path.basename(run.rstrip("/"))
        row = {"run": name, "cohesion_Pa": key[0], "porosity_pct": key[1], "friction": key[2],
               "cppr": fields[3], "cpu_s": fields[4] if len(fields) > 4 else float("nan"), **row}
        rows.append(row)
        curves.append((row, ts, fits))
        print(f"\n## {name}: {key[0] / 1e3:g} kPa, {key[1]:g}%, f {key[2]:g}, CPPR {fields[3]:g}")
        print("| t (s) | " + " | ".join(f"{t:g}" for t, _ in table) + " |")
        print("|---" * (len(table) + 1) + "|")
        print("| beta_launch | " + " | ".join(f"{b:.3f}" for _, b in table) + " |")
        print("drift per 0.1 s: " + ", ".join(f"{t0:g}-{t1:g} s {d:+.3f}" for t0, t1, d in drifts))
        print(f"end {row['t_end_s']:.4f} s: beta_launch {row['beta_launch']:.3f} against iSALE "
              f"{row['isale_beta']:.3f} ({row['difference_pct']:+.1f}%), drift over the last fifth "
              f"{row['drift_last_fifth']:+.3f}, energy error {row['energy_error_pct']:+.2f}%")
        for q in Q:
            print(f"  1 + p(>{q:g}U): {row[f'beta_gt_{q:g}U']:.3f} (drift last fifth "
                  f"{row[f'drift_gt_{q:g}U']:+.4f}); iSALE {row[f'isale_beta_gt_{q:g}U']:.3f}")
        print(f"  launches of the last fifth: momentum-weighted median speed "
              f"{row['v_late_median_m_per_s']:.3g} m/s = {row['v_late_median_over_U']:.2e} U")
        if "isale_beta_gt_v_late" in row:
            print(f"  iSALE's 1 + p(> that speed): {row['isale_beta_gt_v_late']:.3f} of its final "
                  f"{row['isale_beta']:.3f} (slower ejecta: {row['isale_beta'] - row['isale_beta_gt_v_late']:.3f})")
        for f, A, k, rms, vals in fits:
            print(f"  EXTRAPOLATION fit beta - 1 = A t^k over [{f:g}, 1] t_end: A {A:.4f}, k {k:.4f},"
                  f" rms {rms:.4f}; at " + ", ".join(f"{T:g} s {v:.3f}" for T, v in zip(a.at, vals)))
    if a.csv:
        pc.write_csv(a.csv, "r-z runs of scenes/dart/raducan2019-*.toml: beta_launch at the end, "
                     "drift, split by launch speed, against iSALE-2D (Raducan et al. 2019, derived "
                     "from sr516/iSALE_ejecta_data); studies/dart/convergence.py", rows)
    if a.plot:
        plot(curves, a.plot)


def plot(curves, path):
    fig, (ax, ax_k) = pc.subplots(2, 1, figsize=(7.5, 7), sharex=True,
                                  gridspec_kw={"height_ratios": [3, 1.4]})
    for i, (row, ts, fits) in enumerate(curves):
        colour = f"C{i}"
        label = (f"{row['cohesion_Pa'] / 1e3:g} kPa, {row['porosity_pct']:g}%, "
                 f"CPPR {row['cppr']:g}")
        ts_ = [r for r in ts if r[0] >= 1e-3]
        ax.plot([r[0] for r in ts_], [r[1] for r in ts_], colour, label=label)
        ax.axhline(row["isale_beta"], color=colour, ls=":", lw=1)
        for j, (f, A, k, rms, _) in enumerate(fits[-1:]):
            t_end = row["t_end_s"]
            tt = [t_end * (5.0 / t_end) ** (s / 40) for s in range(41)]
            ax.plot(tt, [1.0 + A * t**k for t in tt], color=colour, ls="--", lw=0.8)
        le = local_exponent(ts)
        ax_k.plot([t for t, _ in le], [k for _, k in le], colour, lw=0.9)
    ax.set_xscale("log")
    pc.label(ax, None, "beta_launch")
    ax.set_title("beta_launch(t), r-z MPM; dotted: iSALE final (5 s); dashed: fit A t^k of the "
                 "last --windows window, extrapolated", fontsize=8)
    pc.legend(ax, loc="upper left")
    ax_k.set_xlabel("time (s)")
    ax_k.set_ylabel("d ln(beta_launch - 1) / d ln t", fontsize=8)
    ax_k.axhline(0.0, color="gray", lw=0.5)
    pc.save(fig, path)


if __name__ == "__main__":
    main()
