"""Crater depth and diameter against time and resolution (docs/validation-axisymmetric.md,
"Crater in a half-space"), from r-z runs measured by crater.py.

usage: crater_figure.py OUT.png OUT.csv LABEL=RUN_DIR ...
LABEL is MATERIAL:CPPR (e.g. basalt:40); RUN_DIR.log, when present, holds /usr/bin/time's line
"CPU user U s ...", copied into the table. The CSV has every snapshot; the figure one panel per
material, depth and diameter (in projectile radii) against time (in a/U)."""
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import crater  # noqa: E402


def cpu_seconds(run_dir):
    try:
        text = open(run_dir.rstrip("/") + ".log").read()
    except OSError:
        return float("nan")
    m = re.search(r"CPU user ([0-9.]+) s", text)
    return float(m.group(1)) if m else float("nan")


out_png, out_csv = sys.argv[1], sys.argv[2]
runs = [arg.split("=", 1) for arg in sys.argv[3:]]
materials = list(dict.fromkeys(label.split(":")[0] for label, _ in runs))
fig, axes = plt.subplots(1, len(materials), figsize=(5.5 * len(materials), 4), squeeze=False)
lines = ["material,cppr,t_aU,depth_a,diameter_a,points,cpu_s"]
for label, run in runs:
    material, cppr = label.split(":")
    rows, a = crater.measure(run)
    cpu = cpu_seconds(run)
    ax = axes[0][materials.index(material)]
    t = [r[1] for r in rows if r[1] >= 2.0]
    depth = [r[2] / a for r in rows if r[1] >= 2.0]
    dia = [r[3] / a for r in rows if r[1] >= 2.0]
    text = f"depth, {cppr} CPPR ({rows[0][4]} rings, {cpu:.0f} CPU s)"
    (line,) = ax.plot(t, depth, "o-", ms=3, label=text)
    ax.plot(t, dia, "s--", ms=3, color=line.get_color(), label=f"diameter, {cppr} CPPR")
    for r in rows:
        lines.append(f"{material},{cppr},{r[1]:.3f},{r[2] / a:.4f},{r[3] / a:.4f},{r[4]},{cpu:.1f}")
for m, ax in zip(materials, axes[0]):
    ax.set_title(f"{m} half-space, basalt sphere at 5 km/s, r-z")
    ax.set_xlabel("t (a/U)")
    ax.set_ylabel("crater depth and diameter (projectile radii)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=6.5)
fig.tight_layout()
fig.savefig(out_png, dpi=120)
open(out_csv, "w").write("\n".join(lines) + "\n")
