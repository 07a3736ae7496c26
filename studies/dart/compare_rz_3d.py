#!/usr/bin/python3
"""r-z against 3-D for a head-on DART-like run pair at matched resolution (issue 32).

Reads each RUN (an output directory of scenes/dart/raducan2019-10kpa-small-rz.toml or -3d.toml, or
any head-on run with a [beta] table) and prints one row per run:
  - beta_launch at the times --times (ms), linearly interpolated in RUN/timeseries.csv;
  - the fast-ejecta beta 1 + p(>qU) for q = 5e-2, 2e-2, 1e-2 and the ejected mass M(>v_esc)/m_imp
    (both from RUN/ejecta_launch.csv, as studies/dart/compare_raducan2019.py measures them; a
    ratio to the impactor's own mass, so a half model needs no factor 2);
  - the crater's depth and diameter at the last snapshot (tools/crater.py);
  - the energy error at the end, the points left in the domain at the last snapshot, and CPU seconds if given as RUN:CPU_S.
The last rows give each run's difference from the first run in %.
With --plot FILE.png (matplotlib) beta_launch(t) of every run.

Usage: compare_rz_3d.py RUN[:CPU_S][=LABEL] [RUN...] [--times 1 2 5 10] [--plot F.png] [--csv F]
"""

import argparse
import csv
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
import compare_raducan2019 as cr  # noqa: E402  (measures(), crater_at_end())
import plot_common as pc  # noqa: E402


def at(ts, t):
    """beta_launch at time t (s), linear between the time-series rows around it."""
    for (t0, b0, _), (t1, b1, _) in zip(ts, ts[1:]):
        if t0 <= t <= t1:
            return b0 + (b1 - b0) * (t - t0) / (t1 - t0) if t1 > t0 else b1
    return float("nan")


def last_row(run):
    with open(os.path.join(run, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    return rows[-1]


def crater_last(run):
    """The crater row of the last snapshot (tools/crater.py): depth, diameter, points in it."""
    import importlib.util
    spec = importlib.util.spec_from_file_location(
        "shatter_tool_crater", os.path.join(HERE, "..", "..", "tools", "crater.py"))
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    _, rows = tool.measure(run, last=True)
    return rows[-1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="+", help="RUN[:CPU_S][=LABEL]")
    ap.add_argument("--times", nargs="+", type=float, default=[1, 2, 5, 10], help="ms")
    ap.add_argument("--plot")
    ap.add_argument("--csv")
    args = ap.parse_args()

    table, curves = [], []
    for spec in args.runs:
        spec, _, label = spec.partition("=")
        run, _, cpu = spec.partition(":")
        out, ts, (m_imp, u, launches) = cr.measures(run)
        crater = crater_last(run)
        last = last_row(run)
        row = {"run": label or os.path.basename(run.rstrip("/"))}
        for t in args.times:
            row[f"beta_launch_{t:g}ms"] = at(ts, t * 1e-3)
        for q in cr.Q:
            row[f"beta_gt_{q:g}U"] = out[f"beta_gt_{q:g}U"]
        row["M_ej_over_mimp"] = sum(m for m, v, vn, *_ in launches) / m_imp
        row["crater_depth_m"] = crater["depth_m"]
        row["crater_diameter_m"] = crater["diameter_m"]
        row["crater_time_s"] = crater["time_s"]
        row["energy_error"] = float(last["energy_error"])
        row["points_left"] = crater["points"]  # in the domain at the last snapshot (outflow removes)
        row["cpu_s"] = float(cpu) if cpu else float("nan")
        table.append(row)
        curves.append((row["run"], ts))

    keys = list(table[0].keys())
    w = csv.writer(sys.stdout)
    w.writerow(keys)
    for row in table:
        w.writerow([row[k] if isinstance(row[k], str) else f"{float(row[k]):.5g}" for k in keys])
    ref = table[0]
    for row in table[1:]:
        diff = [f"{row['run']} vs {ref['run']} (%)"]
        for k in keys[1:]:
            a, b = float(ref[k]), float(row[k])
            if k.startswith("beta"):  # beta - 1 is what the ejecta add: compare that too
                diff.append(f"{100 * (b / a - 1):+.1f} (b-1: {100 * ((b - 1) / (a - 1) - 1):+.1f})")
            else:
                diff.append(f"{100 * (b / a - 1):+.1f}" if a else "")
        w.writerow(diff)
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            cw = csv.DictWriter(f, fieldnames=keys)
            cw.writeheader()
            cw.writerows(table)
    if args.plot:
        fig, ax = pc.subplots(figsize=(6.5, 4.2))
        for i, (name, ts) in enumerate(curves):
            ax.plot([r[0] * 1e3 for r in ts], [r[1] for r in ts], f"C{i}", label=name,
                    lw=2.0 if "3d" in name.lower() else 1.0)
        pc.label(ax, "t_ms", "beta_launch")
        ax.set_title("raducan2019-10kpa, 3 x 3 m target: r-z vs 3-D half model (thick)",
                     fontsize=9)
        pc.legend(ax)
        pc.save(fig, args.plot)


if __name__ == "__main__":
    main()
