#!/usr/bin/python3
"""Our r-z runs of scenes/dart/raducan2019-*.toml against the iSALE-2D grid of Raducan et al. 2019.

For each RUN=COHESION_PA:POROSITY_PCT:FRICTION it reads RUN/timeseries.csv (beta_launch(t)) and
RUN/ejecta_launch.csv (each ejected point once, at its crossing of the count plane) and prints,
beside the row of docs/figures/dart/raducan2019_beta.csv (studies/dart/raducan2019_beta.py):
  - beta_launch at the end and its drift over the last fifth of the run (as tools/beta.py);
  - the beta of the ejecta faster than q U only, 1 + sum_{v > qU} m v_n / (m_imp U), for
    q = 5e-2, 2e-2, 1e-2 (what a run too short for the slow, late ejecta can be compared with);
  - its drift over the last fifth (the launches after 0.8 t_end), and M(>qU)/m_imp.
With --plot FILE.png (matplotlib) beta_launch(t) of each run with the reference's final beta and
fast-ejecta beta as lines; with --csv FILE the table.

Each run's crater at its last snapshot (tools/crater.py: diameter and depth against the
pre-impact surface, cavity volume) goes into the table.

With RUN=C:P:F:CPPR:CPU_S the run's resolution and CPU seconds go into the table too; the plot's
second panel shows each run's time step dt(t) (the EOS-following shear modulus keeps it from
collapsing in expanded ejecta; docs/validation-dart.md).

With --tracers PATH (a local copy of sr516/iSALE_ejecta_data; CC BY-NC-SA, read, never copied)
also the beta of the ejecta launched within radius X of the axis, ours (launch_radius_m) and
theirs (the tracers' launch distance x), at X = 1, 2, ... m up to our farthest launch: a run that
stops while the crater still grows has counted the inner ejecta completely and the outer ones not
at all, and this compares the part it has (iSALE's ejection reaches x ~ 7 m at 10 kPa, 20%).

Usage: compare_raducan2019.py REFERENCE.csv RUN=1e4:20:0.6[:CPPR:CPU_S] [RUN=...] [--plot F.png]
       [--csv F.csv]
"""

import argparse
import csv
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import plot_common as pc  # noqa: E402  (tools/plot_common.py: Agg, dpi, common labels)

Q = (5e-2, 2e-2, 1e-2)


def read_reference(path):
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return {(float(r["cohesion_Pa"]), float(r["porosity_pct"]), float(r["friction"])): r
            for r in rows if r["series"] == "Porosity" or float(r["friction"]) != 0.6}


def run_and_point(spec):
    """RUN=COHESION_PA:POROSITY_PCT:FRICTION[:...] -> RUN, the grid point's key, all the fields."""
    run, point = spec.rsplit("=", 1)
    fields = [float(v) for v in point.split(":")]
    return run, tuple(fields[:3]), fields


def read_run(run):
    with open(os.path.join(run, "timeseries.csv")) as f:
        ts = [(float(r["time_s"]), float(r["beta_launch"]), float(r["dt_s"]))
              for r in csv.DictReader(f) if r.get("beta_launch") and r.get("wall_s")]
    path = os.path.join(run, "ejecta_launch.csv")
    with open(path) as f:
        meta = dict(kv.split("=") for kv in f.readline().lstrip("# ").split())
        launches = [(float(r["mass_kg"]), float(r["speed_m_per_s"]),
                     float(r["normal_speed_m_per_s"]), float(r["launch_time_s"]),
                     float(r["launch_radius_m"]))
                    for r in csv.DictReader(f)]
    return ts, float(meta["impactor_mass_kg"]), float(meta["impact_speed_m_per_s"]), launches


def measures(run):
    ts, m_imp, u, launches = read_run(run)
    t_end, b_end = ts[-1][:2]
    b_fifth = min(ts, key=lambda r: abs(r[0] - 0.8 * t_end))[1]
    out = {"t_end_s": t_end, "beta_launch": b_end, "drift_last_fifth": b_end - b_fifth}
    for q in Q:
        fast = [(m, vn, t) for m, v, vn, t, _ in launches if v > q * u and vn > 0.0]
        out[f"beta_gt_{q:g}U"] = 1.0 + sum(m * vn for m, vn, _ in fast) / (m_imp * u)
        # its drift over the last fifth: the same sum over the launches before 0.8 t_end
        early = sum(m * vn for m, vn, t in fast if t <= 0.8 * t_end) / (m_imp * u)
        out[f"drift_gt_{q:g}U"] = out[f"beta_gt_{q:g}U"] - 1.0 - early
        out[f"M_gt_{q:g}U_over_mimp"] = sum(m for m, _, _ in fast) / m_imp
    out["launch_radius_max_m"] = max((x for *_, x in launches), default=0.0)
    return out, ts, (m_imp, u, launches)


def crater_at_end(run):
    """The crater at the run's last snapshot, measured by tools/crater.py (its definition)."""
    import importlib.util
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools",
                        "crater.py")
    spec = importlib.util.spec_from_file_location("shatter_tool_crater", path)
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    _, rows = tool.measure(run, last=True)
    return {"crater_time_s": rows[-1]["time_s"], "crater_diameter_m": rows[-1]["diameter_m"],
            "crater_depth_m": rows[-1]["depth_m"], "crater_volume_m3": rows[-1]["volume_m3"]}


def within_radius(ours, tracer_csv):
    """beta of the ejecta launched within X of the axis, ours and theirs, X = 1 m, 2 m, ..."""
    m_imp, u, launches = ours
    import numpy as np
    d = np.genfromtxt(tracer_csv, delimiter=",", names=True)
    m_isale = 4.0 / 3.0 * np.pi * 0.42**3 * 1000.0  # raducan2019_beta.py: a, delta
    out = []
    x_max = max((x for *_, x in launches), default=0.0)
    for X in range(1, int(x_max) + 1):
        b_ours = 1.0 + sum(m * vn for m, v, vn, _, x in launches if x <= X) / (m_imp * u)
        sel = d["x"] <= X
        b_isale = 1.0 + float(np.sum(d["m"][sel] * d["v_y"][sel])) / (m_isale * 7000.0)
        out.append((X, b_ours, b_isale))
    return out


def tracer_file(root, cohesion, porosity, friction=0.6):
    """iSALE's tracer file of a grid point: Porosity/*/Yd1eN-PP.csv at f 0.6, else
    Friction/*/Yd1eN-FF.csv (FF = 10 f, two digits)."""
    import glob
    n = round(__import__('math').log10(cohesion))
    if friction == 0.6:
        series, name = "Porosity", f"Yd1e{n}-{porosity:g}.csv"
    else:
        series, name = "Friction", f"Yd1e{n}-{round(10 * friction):02d}.csv"
    hits = sorted(glob.glob(os.path.join(root, series, "*", name)))
    return hits[0] if hits else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("reference")
    ap.add_argument("runs", nargs="+", help="RUN=COHESION_PA:POROSITY_PCT:FRICTION")
    ap.add_argument("--plot")
    ap.add_argument("--csv")
    ap.add_argument("--tracers", help="local copy of sr516/iSALE_ejecta_data")
    args = ap.parse_args()
    ref = read_reference(args.reference)
    table, curves = [], []
    for spec in args.runs:
        run, key, fields = run_and_point(spec)
        r = ref[key]
        ours, ts, launches = measures(run)
        row = {"run": os.path.basename(run.rstrip("/")), "cohesion_Pa": key[0],
               "porosity_pct": key[1], "friction": key[2]}
        if len(fields) == 5:
            row.update({"cppr": fields[3], "cpu_s": fields[4]})
        row.update({**ours, **crater_at_end(run), "isale_beta": float(r["beta"])})
        for q in Q:
            row[f"isale_beta_gt_{q:g}U"] = float(r[f"beta_gt_{q:g}U"])
            row[f"isale_M_gt_{q:g}U_over_mimp"] = float(r[f"M_gt_{q:g}U_over_mimp"])
        table.append(row)
        tracers = args.tracers and tracer_file(args.tracers, *key)
        if tracers:
            for X, b_o, b_i in within_radius(launches, tracers):
                print(f"{row['run']}: launched within {X} m: beta ours {b_o:.3f}, iSALE {b_i:.3f}")
        curves.append((row, ts))
    keys = list(table[0].keys())
    for r in table:
        print(", ".join(f"{k} {r[k]:.4g}" if isinstance(r[k], float) else f"{k} {r[k]}"
                        for k in keys))
    if args.csv:
        pc.write_csv(args.csv, "shatter r-z runs of scenes/dart/raducan2019-*.toml against the "
                     "iSALE-2D beta of Raducan et al. 2019 (Icarus 329; derived from "
                     "sr516/iSALE_ejecta_data by studies/dart/raducan2019_beta.py); "
                     "studies/dart/compare_raducan2019.py", table, keys)
    if args.plot:
        plot(curves, args.plot)


def plot(curves, path):
    fig, (ax, ax_dt) = pc.subplots(2, 1, figsize=(7, 6.5), sharex=True,
                                   gridspec_kw={"height_ratios": [3, 1]})
    for i, (row, ts) in enumerate(curves):
        colour = f"C{i}"
        label = f"{row['cohesion_Pa'] / 1e3:g} kPa, {row['porosity_pct']:g}%, f {row['friction']:g}"
        ax.plot([r[0] * 1e3 for r in ts], [r[1] for r in ts], colour,
                label=f"{row['run']}: {label}")
        ax.axhline(row["isale_beta_gt_0.01U"], color=colour, ls="--", lw=1)
        ax.axhline(row["isale_beta"], color=colour, ls=":", lw=1)
        ax_dt.plot([r[0] * 1e3 for r in ts], [r[2] for r in ts], colour, lw=0.8)
    ax_dt.set_yscale("log")
    pc.label(ax_dt, "t_ms", "dt")
    pc.label(ax, None, "beta_launch")
    ax.set_title("r-z MPM vs iSALE (Raducan et al. 2019): -- ejecta > 0.01 U, : all (final)",
                 fontsize=9)
    pc.legend(ax)
    pc.save(fig, path)

if __name__ == "__main__":
    main()
