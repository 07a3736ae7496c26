#!/usr/bin/python3
"""Roofline of the MPM and SPH steps' stages on the development machine (docs/performance.md,
"Roofline (session 21)"), drawn from docs/figures/performance/roofline.csv.

The CSV holds two kinds of rows:
  ceiling: the machine's ceilings from bench/machine.cpp, per second of process CPU (per core
           busy): `rate` in GFLOP/s (name fma) or GB/s (name triad_<level>).
  stage:   one stage of a step at `points` points: fp64 flops and bytes per point and step (counted
           from the kernels' source: see the docs section for the method), the measured CPU ns per
           point and step, the memory level its streamed working set lives in (`level`, one of the
           triad names) and what bounds it (`bound`, the docs' reading).

For each stage the script derives the arithmetic intensity (flops/byte), the attained GFLOP/s and
GB/s per core, the roofline's ceiling at that intensity, min(FMA peak, intensity x triad rate of
its level), and the fraction of that ceiling attained; it prints them as a Markdown table and draws
the log-log roofline with the stages as points.

    /usr/bin/python3 tools/roofline.py [--csv PATH] [--out PNG] [--table]
    /usr/bin/python3 tools/roofline.py --measured RUN.json ...   (refresh cpu_ns and rates)

--bound CSV prints the floor of a whole step instead (docs/performance.md, "Session 23: peers and
the profile of main"): each stage row of that CSV holds its measured CPU ns per point-step (from a
profile of a real run), its flops, bytes, lane-divisions and lane-square roots per point, and the
level its columns stream from; the stage's floor is the largest of flops / FMA peak, bytes / triad
rate of its level and divisions x the divider's time per lane-division + square roots x its time
per lane-root (bench/machine.cpp, `machine/divide`, `machine/sqrt`, as ceilings `divide` and
`sqrt` in G lane-operations per second). The step's floor is the sum; a `goal` row (cpu_ns = the
goal's ns per point-step per core) is set against it.

    /usr/bin/python3 tools/roofline.py --bound docs/figures/performance/bound-lab-impact.csv

--measured refreshes the CSV's measured columns from Google Benchmark JSON files
(--benchmark_out_format=json of bench_machine, bench_step, bench_sph_step; several runs are
averaged, their range kept in `range`) and rewrites the CSV. A stage row names its benchmark
(`bench`) and its counter: a stage's `<stage>_ns` (wall time per point, Simulation::stage_timings)
is turned into CPU time by the benchmark's own process-CPU / wall ratio (one thread: the share of
the core the process had; it assumes the share was the same in every stage), `per_item` takes
1 / items_per_second the same way. A ceiling row's counter (bytes_per_second, flops) is already
per second of process CPU (bench/machine.cpp).
"""
import argparse
import csv
import json
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FIG_DIR = os.path.join(ROOT, "docs", "figures", "performance")


def measured(rows, paths):
    """Fills cpu_ns (stages) and rate (ceilings) with the mean over the JSON runs."""
    runs = []
    for path in paths:
        with open(path) as f:
            runs.append({b["name"]: b for b in json.load(f)["benchmarks"]})
    for row in rows:
        values = []
        for run in runs:
            b = run.get(row["bench"])
            if b is None:
                continue
            if row["kind"] == "ceiling":
                values.append(b[row["counter"]] / 1e9)
                continue
            share = b["cpu_time"] / b["real_time"]
            if row["counter"] == "per_item":
                values.append(1e9 / b["items_per_second"] * share)
            else:
                values.append(b[row["counter"]] * share)
        if not values:
            print(f"warning: no run has {row['bench']}: {row['name']} left as it was")
            continue
        mean = sum(values) / len(values)
        row["cpu_ns" if row["kind"] == "stage" else "rate"] = f"{mean:.3g}"
        row["range"] = f"{min(values):.3g}-{max(values):.3g} ({len(values)} runs)"


def load(path):
    ceilings, stages = {}, []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if row["kind"] == "ceiling" and row["rate"]:
                ceilings[row["name"]] = float(row["rate"])
            elif row["kind"] == "stage":
                s = dict(row)
                for k in ("points", "flops", "bytes", "cpu_ns"):
                    s[k] = float(s[k])
                stages.append(s)
    return ceilings, stages


def derive(ceilings, s):
    """Intensity, attained rates, ceiling and fraction of one stage row."""
    ai = s["flops"] / s["bytes"]
    gflops = s["flops"] / s["cpu_ns"]  # flops per ns = GFLOP/s
    gbs = s["bytes"] / s["cpu_ns"]  # bytes per ns = GB/s
    bw = ceilings[s["level"]]
    roof = min(ceilings["fma"], ai * bw)
    return {
        "ai": ai,
        "gflops": gflops,
        "gbs": gbs,
        "roof": roof,
        "fraction": gflops / roof,
        "roof_ns": s["flops"] / roof,  # the stage's time at its ceiling
        "memory_side": ai * bw < ceilings["fma"],
    }


def table(ceilings, stages):
    head = (
        "| method | stage | points | flops/pt | B/pt | flops/B | CPU ns/pt | GFLOP/s | GB/s "
        "| level | ceiling GFLOP/s | of ceiling | ns at ceiling | bound |"
    )
    lines = [head, "|" + "---|" * 14]
    for s in stages:
        d = derive(ceilings, s)
        lines.append(
            f"| {s['method']} | {s['name']} | {s['points']:.0e} | {s['flops']:.0f} | "
            f"{s['bytes']:.0f} | {d['ai']:.2f} | {s['cpu_ns']:.1f} | {d['gflops']:.1f} | "
            f"{d['gbs']:.1f} | {s['level']} | {d['roof']:.1f} | {100 * d['fraction']:.0f} % | "
            f"{d['roof_ns']:.1f} | {s['bound']} |"
        )
    return "\n".join(lines)


LEVELS = {
    "triad_L1": "triad, L1 (3 x 8 KiB)",
    "triad_L2": "triad, L2 (3 x 256 KiB)",
    "triad_L3": "triad, L3 (3 x 2 MiB)",
    "triad_L3_24MiB": "triad, L3 full (3 x 8 MiB)",
    "triad_DRAM": "triad, DRAM (3 x 256 MiB)",
}

# Label positions (points from the marker) where the stages crowd.
OFFSETS = {
    ("MPM", "p2g"): (14, -2),
    ("MPM", "remap"): (-40, 14),
    ("MPM", "constitutive"): (6, 16),
    ("MPM", "g2p"): (-50, -12),
    ("SPH", "rates"): (16, 12),
    ("SPH", "forces"): (10, -16),
    ("MPM", "advance_positions"): (-70, 8),
    ("MPM", "remap_velocity"): (6, -10),
    ("SPH", "drift"): (8, -12),
    ("SPH", "kick"): (8, 4),
}


def draw(ceilings, stages, out):
    fig, ax = plt.subplots(figsize=(9.5, 6.5))
    peak = ceilings["fma"]
    xs = [10 ** (e / 20) for e in range(-40, 41)]  # 0.01 .. 100 flops/byte
    styles = {
        "triad_L1": ("tab:green", ":"),
        "triad_L2": ("tab:olive", "-."),
        "triad_L3": ("tab:orange", "--"),
        "triad_L3_24MiB": ("tab:brown", "--"),
        "triad_DRAM": ("tab:red", "-"),
    }
    for name, (colour, ls) in styles.items():
        if name not in ceilings:
            continue
        bw = ceilings[name]
        ax.plot(xs, [min(peak, x * bw) for x in xs], color=colour, ls=ls, lw=1.3,
                label=f"{LEVELS[name]}: {bw:.0f} GB/s")
    ax.axhline(peak, color="k", lw=1.5, label=f"fp64 FMA peak: {peak:.1f} GFLOP/s")
    for name, text in (("fma_chain3", "3 dependent FMA chains"),
                       ("fma_chain1", "1 dependent FMA chain")):
        if name in ceilings:
            ax.axhline(ceilings[name], color="0.4", lw=1.0, ls=(0, (5, 2, 1, 2)))
            ax.text(0.012, ceilings[name] * 1.06, f"{text}: {ceilings[name]:.1f} GFLOP/s",
                    fontsize=7, color="0.3")
    markers = {("MPM", 1e5): ("o", "tab:blue"), ("MPM", 1e6): ("s", "tab:purple"),
               ("SPH", 1e5): ("^", "tab:cyan"), ("SPH", 1e6): ("v", "tab:gray")}
    seen = set()
    for s in stages:
        d = derive(ceilings, s)
        key = (s["method"], s["points"])
        marker, colour = markers.get(key, ("x", "k"))
        label = f"{s['method']} stages, {s['points']:.0e} points"
        ax.scatter(d["ai"], d["gflops"], marker=marker, color=colour, s=42, zorder=3,
                   label=None if key in seen else label)
        seen.add(key)
        if s.get("label", "1") == "1":
            dx, dy = OFFSETS.get((s["method"], s["name"]), (4, 3))
            ax.annotate(f"{s['method']} {s['name']}", (d["ai"], d["gflops"]), fontsize=7,
                        xytext=(dx, dy), textcoords="offset points",
                        arrowprops={"arrowstyle": "-", "lw": 0.4, "color": "0.5"})
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(xs[0], xs[-1])
    ax.set_ylim(0.1, 2 * peak)
    ax.set_xlabel("arithmetic intensity (fp64 flops per byte moved to or from memory)")
    ax.set_ylabel("attained GFLOP/s per core (per second of process CPU)")
    ax.set_title("Roofline of the MPM and SPH stages, 1 thread (AMD EPYC Zen 4 VM, session 21)",
                 fontsize=10)
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")


def bound(path):
    """The floor of each stage and of the whole step (--bound), as Markdown, per method."""
    ceilings, rows = {}, []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if row["kind"] == "ceiling":
                ceilings[row["name"]] = float(row["rate"])
            else:
                rows.append(row)
    for need in ("fma", "divide", "sqrt"):
        if need not in ceilings:
            raise SystemExit(f"{path}: no ceiling row '{need}'")
    num = lambda r, k: float(r[k]) if r.get(k) else 0.0  # noqa: E731
    for method in dict.fromkeys(r["method"] for r in rows):
        print(f"\n{method}\n")
        print("| stage | measured CPU ns | flops | B | div. | sqrt | ns at FMA peak | ns at triad "
              "| ns on the divider | floor ns | floor / measured |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        measured_sum = floor_sum = 0.0
        goal = None
        for r in rows:
            if r["method"] != method:
                continue
            if r["kind"] == "goal":
                goal = (r["name"], num(r, "cpu_ns"))
                continue
            ns = num(r, "cpu_ns")
            t_fma = num(r, "flops") / ceilings["fma"]
            t_mem = num(r, "bytes") / ceilings[r["level"]] if r["level"] else 0.0
            t_div = num(r, "divisions") / ceilings["divide"] + num(r, "sqrts") / ceilings["sqrt"]
            floor = max(t_fma, t_mem, t_div)
            measured_sum += ns
            floor_sum += floor
            print(f"| {r['name']} | {ns:.1f} | {num(r, 'flops'):.0f} | {num(r, 'bytes'):.0f} | "
                  f"{num(r, 'divisions'):.0f} | {num(r, 'sqrts'):.0f} | {t_fma:.1f} | {t_mem:.1f} | "
                  f"{t_div:.1f} | **{floor:.1f}** | {100 * floor / ns:.0f} % |")
        print(f"| **step** | **{measured_sum:.1f}** | | | | | | | | **{floor_sum:.1f}** | "
              f"{100 * floor_sum / measured_sum:.0f} % |")
        line = (f"\n{method}: measured {1e3 / measured_sum:.2f} M point-steps per CPU-s, floor "
                f"{1e3 / floor_sum:.2f} M per core")
        if goal:
            line += (f"; goal '{goal[0]}' = {goal[1]:.0f} ns per point-step per core: measured / "
                     f"goal {measured_sum / goal[1]:.2f}, floor / goal {floor_sum / goal[1]:.2f} "
                     f"(the goal needs {100 * floor_sum / goal[1]:.0f} % of the floor on average, "
                     f"the step attains {100 * floor_sum / measured_sum:.0f} %)")
        print(line)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--csv", default=os.path.join(FIG_DIR, "roofline.csv"))
    p.add_argument("--out", default=os.path.join(FIG_DIR, "roofline.png"))
    p.add_argument("--table", action="store_true", help="print the Markdown table")
    p.add_argument("--measured", nargs="+", metavar="JSON", help="refresh the measured columns")
    p.add_argument("--bound", metavar="CSV", help="print the floor of a step's stages and stop")
    a = p.parse_args()
    if a.bound:
        bound(a.bound)
        return
    if a.measured:
        with open(a.csv, newline="") as f:
            rows = list(csv.DictReader(f))
        measured(rows, a.measured)
        fields = list(rows[0].keys())
        if "range" not in fields:
            fields.append("range")
        with open(a.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=fields, lineterminator="\n")
            w.writeheader()
            w.writerows(rows)
        print(f"updated {a.csv} from {len(a.measured)} files")
    ceilings, stages = load(a.csv)
    for need in ("fma",):
        if need not in ceilings:
            raise SystemExit(f"{a.csv}: no ceiling row '{need}'")
    if a.table:
        print(table(ceilings, stages))
    draw(ceilings, stages, a.out)
    if not all(math.isfinite(derive(ceilings, s)["fraction"]) for s in stages):
        raise SystemExit("a stage row has a non-finite fraction")


if __name__ == "__main__":
    main()
