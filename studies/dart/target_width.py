#!/usr/bin/python3
"""The target's width against the simulated time: two r-z runs of one Raducan et al. 2019 point on
targets of different radius (issue 32, sessions 21-22).

For NARROW and WIDE (run folders of the same scene but for the target cylinder's radius, e.g.
scenes/dart/raducan2019-1kpa.toml, 9 m, and raducan2019-1kpa-wide.toml, 13 m) it reads
RUN/timeseries.csv and RUN/ejecta_launch.csv and prints:

  - beta_launch of both at equal times (every 0.05 s to the shorter run's end, then the wider
    run's alone), their difference, and each against iSALE's final beta (the row of
    docs/figures/dart/raducan2019_beta.csv of --point);
  - the growth per 0.1 s and where it is launched: the momentum-weighted median and the 90th
    percentile of the launch radius (launch_radius_m, where the ejecta cross the count plane) of
    the ejecta launched in each 0.1 s, the farthest launch in it and the farthest so far;
  - beta split by launch radius, 1 + p(x in bin) / (m_imp U) for the bins of --bins (m), for
    both runs at the times of --at and, with --tracers (a local copy of sr516/iSALE_ejecta_data,
    CC BY-NC-SA: read, never copied), iSALE's from its tracers' launch distance x.

The lattice's volume factor (session 22): the r-z fill scales every point's volume (and mass) so
that a body has its shape's exact volume (src/scene/lattice_rz.cpp), and the factor depends on
where the lattice meets the faces, so the same lattice point can carry a different mass on two
targets (0.42% more on a 13 m x 12 m cylinder than on the 9 m x 12 m one: session 21's +-0.01
offset). The script prints the mass ratio wide / narrow of the target points the two runs share
(same position in their first snapshots, r < 8.5 m), so that a comparison says whether it is
matched (scenes/dart/raducan2019-10kpa-wide.toml is: 11.96 m deep, ratio 1.0003) or not.

With --plot FILE.png: beta_launch(t) of both (linear time) with iSALE's final beta dotted, and
below the beta carried by ejecta launched within radius X of the axis against X, for both runs
at their ends (and the wide one at the narrow one's end time) and iSALE's. With --csv FILE the
table of beta_launch at equal times.

Usage: target_width.py REFERENCE.csv NARROW WIDE --point 1e3:20:0.6 [--tracers PATH]
       [--bins 0 5 7 9 11 13] [--at 0.3 0.6 1.0] [--plot F.png] [--csv F.csv]
"""

import argparse
import csv
import glob
import math
import os
import sys
import tomllib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import plot_common as pc  # noqa: E402  (tools/plot_common.py: Agg, dpi, common labels)

M_ISALE = 4.0 / 3.0 * math.pi * 0.42**3 * 1000.0  # raducan2019_beta.py: a 0.42 m, delta 1000
U_ISALE = 7000.0


def read_reference(path, key):
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    for r in rows:
        k = (float(r["cohesion_Pa"]), float(r["porosity_pct"]), float(r["friction"]))
        if k == key and (r["series"] == "Porosity" or key[2] != 0.6):
            return r
    raise SystemExit(f"no reference row for {key}")


def read_run(run):
    with open(os.path.join(run, "timeseries.csv")) as f:
        ts = sorted((float(r["time_s"]), float(r["beta_launch"])) for r in csv.DictReader(f)
                    if r.get("beta_launch") and r.get("wall_s"))
    with open(os.path.join(run, "ejecta_launch.csv")) as f:
        meta = dict(kv.split("=") for kv in f.readline().lstrip("# ").split())
        norm = float(meta["impactor_mass_kg"]) * float(meta["impact_speed_m_per_s"])
        # (launch time, radius, momentum along the normal / (m_imp U)); only outward-moving mass
        launches = [(float(r["launch_time_s"]), float(r["launch_radius_m"]),
                     float(r["mass_kg"]) * max(float(r["normal_speed_m_per_s"]), 0.0) / norm)
                    for r in csv.DictReader(f)]
    return ts, launches


def target_label(run, with_domain=False):
    """'9 m x 12 m target' from the run's resolved scene (RUN/scene.toml); with with_domain
    (two runs of one target in different domains, session 23) ', domain r < 14 m, z > -13 m'."""
    try:
        with open(os.path.join(run, "scene.toml"), "rb") as f:
            scene = tomllib.load(f)
        t = scene["body"]["target"]
        text = f"{t['radius']:g} m x {t['length']:.4g} m target"
        if with_domain:
            d = scene["domain"]
            text += f", domain r < {d['hi'][0]:g} m, z > {d['lo'][2]:g} m"
        return text
    except (OSError, KeyError, tomllib.TOMLDecodeError):
        return os.path.basename(run.rstrip("/"))


def lattice_mass_ratio(narrow, wide, r_max=8.5):
    """Median, min and max of mass(wide) / mass(narrow) over the target points the two runs share
    (same r-z position to 1e-3 of a spacing in their first snapshots, r < r_max); None without
    h5py or snapshots."""
    try:
        import h5py
        import numpy as np
    except ImportError:
        return None
    out = []
    for run in (narrow, wide):
        snaps = sorted(glob.glob(os.path.join(run, "snapshots", "snapshot_*.h5")))
        if not snaps:
            return None
        with h5py.File(snaps[0], "r") as f:
            p = f["particles"]
            pos, mass, body = p["position"][:], p["mass"][:], p["body"][:]
            names = [n.decode() if isinstance(n, bytes) else str(n) for n in f["names"]["body"][:]]
        sel = body == names.index("target") if "target" in names else body == body.max()
        out.append({(round(x * 1e5), round(z * 1e5)): m
                    for (x, _, z), m in zip(pos[sel], mass[sel]) if x < r_max})
    shared = [out[1][k] / out[0][k] for k in out[0].keys() & out[1].keys()]
    if not shared:
        return None
    shared.sort()
    return shared[len(shared) // 2], shared[0], shared[-1], len(shared)


def at(ts, t):
    """beta_launch at time t (linear interpolation; the last value past the end)."""
    if t <= ts[0][0]:
        return ts[0][1]
    for (t0, b0), (t1, b1) in zip(ts, ts[1:]):
        if t0 <= t <= t1:
            return b0 + (b1 - b0) * (t - t0) / (t1 - t0) if t1 > t0 else b1
    return ts[-1][1]


def weighted_quantile(pairs, q):
    pairs = sorted(pairs)
    total = sum(w for _, w in pairs)
    acc = 0.0
    for v, w in pairs:
        acc += w
        if acc >= q * total:
            return v
    return float("nan")


def by_radius(launches, t, bins):
    """beta carried by the ejecta launched by time t in each radius bin."""
    return [sum(p for tl, x, p in launches if tl <= t and lo <= x < hi)
            for lo, hi in zip(bins, bins[1:] + [math.inf])]


def within(launches, t, xs):
    return [1.0 + sum(p for tl, x, p in launches if tl <= t and x <= X) for X in xs]


def isale_tracers(root, key):
    cohesion, porosity, friction = key
    n = round(math.log10(cohesion))
    series, name = ("Porosity", f"Yd1e{n}-{porosity:g}.csv") if friction == 0.6 else \
        ("Friction", f"Yd1e{n}-{round(10 * friction):02d}.csv")
    hits = sorted(glob.glob(os.path.join(root, series, "*", name)))
    if not hits:
        return None
    import numpy as np
    d = np.genfromtxt(hits[0], delimiter=",", names=True)
    # momentum along the surface normal (v_y) / (m_imp U), the launch distance x
    return [(float(x), float(m * vy) / (M_ISALE * U_ISALE))
            for x, m, vy in zip(d["x"], d["m"], d["v_y"])]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("reference")
    ap.add_argument("narrow")
    ap.add_argument("wide")
    ap.add_argument("--point", required=True, help="COHESION_PA:POROSITY_PCT:FRICTION")
    ap.add_argument("--tracers")
    ap.add_argument("--bins", nargs="+", type=float, default=[0.0, 5.0, 7.0, 9.0, 11.0])
    ap.add_argument("--at", nargs="+", type=float, default=[0.3, 0.6])
    ap.add_argument("--plot")
    ap.add_argument("--csv")
    a = ap.parse_args()
    key = tuple(float(v) for v in a.point.split(":"))
    ref = read_reference(a.reference, key)
    b_isale = float(ref["beta"])
    runs = {"narrow": read_run(a.narrow), "wide": read_run(a.wide)}
    t_n, t_w = runs["narrow"][0][-1][0], runs["wide"][0][-1][0]
    t_common = min(t_n, t_w)
    grid = [0.005, 0.01, 0.02] + [round(0.05 * i, 3) for i in range(1, 200)
                                  if 0.05 * i <= max(t_n, t_w) + 1e-9]
    rows = []
    names = {"narrow": target_label(a.narrow), "wide": target_label(a.wide)}
    if names["narrow"] == names["wide"]:  # one target in two domains: say which is which
        names = {"narrow": target_label(a.narrow, True), "wide": target_label(a.wide, True)}
    print(f"# {os.path.basename(a.narrow.rstrip('/'))}, {names['narrow']} (to {t_n:.4f} s) against "
          f"{os.path.basename(a.wide.rstrip('/'))}, {names['wide']} (to {t_w:.4f} s); "
          f"iSALE final {b_isale:.3f}")
    ratio = lattice_mass_ratio(a.narrow, a.wide)
    if ratio:
        med, lo, hi, n = ratio
        print(f"# lattice volume factor: mass of a shared target point, wide / narrow = {med:.5f} "
              f"(min {lo:.5f}, max {hi:.5f}, {n} points at r < 8.5 m): "
              + ("matched to 1e-3" if abs(med - 1) < 1e-3 else
                 "NOT matched: part of the difference is the lattice's volume scaling"))
    print("| t (s) | narrow | wide | wide - narrow | narrow vs iSALE | wide vs iSALE |")
    print("|---|---|---|---|---|---|")
    for t in grid + ([t_w] if t_w not in grid else []):
        bn = at(runs["narrow"][0], t) if t <= t_n + 1e-9 else float("nan")
        bw = at(runs["wide"][0], t) if t <= t_w + 1e-9 else float("nan")
        rows.append({"time_s": t, "beta_launch_narrow": bn, "beta_launch_wide": bw,
                     "difference": bw - bn, "narrow_vs_isale_pct": 100 * (bn / b_isale - 1),
                     "wide_vs_isale_pct": 100 * (bw / b_isale - 1)})
        f = lambda v, s="{:.3f}": "" if math.isnan(v) else s.format(v)  # noqa: E731
        print(f"| {t:g} | {f(bn)} | {f(bw)} | {f(bw - bn, '{:+.3f}')} | "
              f"{f(100 * (bn / b_isale - 1), '{:+.1f}%')} | {f(100 * (bw / b_isale - 1), '{:+.1f}%')} |")
    print(f"\ncommon end {t_common:.4f} s")
    for name, (ts, launches) in runs.items():
        t_end = ts[-1][0]
        print(f"\n## {name}: growth per 0.1 s and where it is launched")
        print("| interval (s) | growth | median launch radius (m) | 90th pct (m) "
              "| farthest in it (m) | farthest so far (m) |")
        print("|---|---|---|---|---|---|")
        t0 = 0.0
        while t0 < t_end - 1e-9:
            t1 = min(t0 + 0.1, t_end)
            sel = [(x, p) for tl, x, p in launches if t0 < tl <= t1 and p > 0]
            far = max((x for tl, x, p in launches if tl <= t1), default=float("nan"))
            print(f"| {t0:.1f}-{t1:.3g} | {at(ts, t1) - at(ts, t0):+.3f} | "
                  f"{weighted_quantile(sel, 0.5):.2f} | {weighted_quantile(sel, 0.9):.2f} | "
                  f"{max((x for x, _ in sel), default=float('nan')):.2f} | {far:.2f} |")
            t0 = t1
    labels = [f"{lo:g}-{hi:g} m" for lo, hi in zip(a.bins, a.bins[1:])] + [f">{a.bins[-1]:g} m"]
    print("\n## beta - 1 by launch radius")
    print("| run, t | " + " | ".join(labels) + " | sum |")
    print("|---" * (len(labels) + 2) + "|")
    for name, (ts, launches) in runs.items():
        t_end = ts[-1][0]
        for t in sorted(set([x for x in a.at if x < t_end - 1e-9] + [t_end])):
            parts = by_radius(launches, t, a.bins)
            print(f"| {name} {t:.3g} s | " + " | ".join(f"{p:.3f}" for p in parts)
                  + f" | {sum(parts):.3f} |")
    tracers = isale_tracers(a.tracers, key) if a.tracers else None
    if tracers:
        parts = [sum(p for x, p in tracers if lo <= x < hi)
                 for lo, hi in zip(a.bins, a.bins[1:] + [math.inf])]
        print("| iSALE final | " + " | ".join(f"{p:.3f}" for p in parts) + f" | {sum(parts):.3f} |")
        print(f"iSALE farthest launch x {max(x for x, _ in tracers):.2f} m")
    if a.csv:
        pc.write_csv(a.csv, "beta_launch of one raducan2019 point on two target widths at equal "
                     "times, against iSALE-2D's final beta (Raducan et al. 2019); "
                     "studies/dart/target_width.py", rows)
    if a.plot:
        plot(runs, tracers, b_isale, a, t_common, names, key)


def plot(runs, tracers, b_isale, a, t_common, names, key):
    fig, (ax, ax_x) = pc.subplots(2, 1, figsize=(7.5, 7.5))
    for i, (name, (ts, _)) in enumerate(runs.items()):
        ax.plot([t for t, _ in ts], [b for _, b in ts], f"C{i}", label=names[name])
    ax.axhline(b_isale, color="k", ls=":", lw=1, label=f"iSALE-2D final (5 s) {b_isale:.3f}")
    ax.axhline(0.8 * b_isale, color="gray", ls=":", lw=0.7, label="iSALE - 20%")
    pc.label(ax, None, "beta_launch")
    ax.set_xlabel("time (s)")
    ax.set_title(f"{key[0] / 1e3:g} kPa, {key[1]:g}%, f {key[2]:g}, r-z MPM CPPR 3: beta_launch(t) "
                 + ("on two target widths" if names["narrow"].split(",")[0] !=
                    names["wide"].split(",")[0] else "of one target in two domains"), fontsize=9)
    pc.legend(ax, loc="lower right")
    xs = [0.25 * i for i in range(0, 57)]
    for i, (name, (ts, launches)) in enumerate(runs.items()):
        t_end = ts[-1][0]
        ax_x.plot(xs, within(launches, t_end, xs), f"C{i}",
                  label=f"{names[name]}, at {t_end:.3g} s")
        if name == "wide" and t_end > t_common + 1e-3:
            ax_x.plot(xs, within(launches, t_common, xs), f"C{i}", ls="--", lw=0.9,
                      label=f"{names[name]}, at {t_common:.3g} s")
    if tracers:
        ax_x.plot(xs, [1.0 + sum(p for x, p in tracers if x <= X) for X in xs], "k",
                  lw=1.2, label="iSALE-2D final")
    ax_x.set_xlabel("launch radius X (m)")
    ax_x.set_ylabel("1 + p(launched within X) / (m_imp U)", fontsize=8)
    pc.legend(ax_x, loc="lower right")
    pc.save(fig, a.plot)


if __name__ == "__main__":
    main()
