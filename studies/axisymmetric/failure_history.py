"""Failed mass fraction of the target against time, and the largest fragment, r-z against 3-D
(docs/validation-axisymmetric.md, "Head-on laboratory impact with damage").

usage: failure_history.py OUT.png OUT.csv LABEL=RUN_DIR ...
The failed fraction is mass-weighted from the snapshots (D >= 0.9, the scene's threshold): in r-z
the points are rings of mass 2 pi r rho A, so the time series' failure_ratio (a count of points)
is not the failed mass there. The largest fragment is the first row of RUN_DIR/fragments.csv
(3-D: the mirrored whole body; r-z: the body of revolution), as a fraction of the target's mass."""
import glob
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def history(run):
    out = []
    for snap in sorted(glob.glob(run + "/snapshots/*.h5")):
        with h5py.File(snap) as f:
            names = [n.decode() for n in f["names/body"][()]]
            target = f["particles/body"][()] == names.index("target")
            m = f["particles/mass"][()][target]
            d = f["particles/damage"][()][target]
            # A 3-D half model (symmetry_axis > 0, points off y = 0) holds half the target; an
            # r-z snapshot (axis face x, every point on y = 0) holds all of it in its rings.
            rz = bool((f["particles/position"][()][:, 1] == 0.0).all())
            half = int(f.attrs["symmetry_axis"]) > 0 and not rz
            whole = m.sum() * (2.0 if half else 1.0)
            out.append((float(f.attrs["time"]), m[d >= 0.9].sum() / m.sum(), whole))
    return out


def largest(run, target_mass):
    """Largest fragment's mass (of the mirrored body for a 3-D half model) over the whole
    target's."""
    rows = [l for l in open(run + "/fragments.csv") if not l.startswith("#")]
    head = rows[0].strip().split(",")
    first = rows[1].strip().split(",")
    name = "mass_body_target_kg" if "mass_body_target_kg" in head else "mass_kg"
    col = head.index(name)
    return float(first[col]) / target_mass, int(first[head.index("particles")])


out_png, out_csv = sys.argv[1], sys.argv[2]
lines = ["run,t_us,failed_mass_fraction,largest_fragment_over_target"]
plt.figure(figsize=(6, 4))
for arg in sys.argv[3:]:
    label, run = arg.split("=", 1)
    h = history(run)
    target_mass = h[0][2]
    big, npts = largest(run, target_mass)
    t = [x[0] * 1e6 for x in h]
    f = [x[1] for x in h]
    plt.plot(t, f, "o-", label=f"{label} (largest fragment {big:.3g} of the target)")
    for ti, fi in zip(t, f):
        lines.append(f"{label},{ti:.1f},{fi:.4f},{big:.4g}")
plt.xlabel("t (us)")
plt.ylabel("failed mass fraction of the target (D >= 0.9)")
plt.grid(True, alpha=0.3)
plt.legend(fontsize=7)
plt.tight_layout()
plt.savefig(out_png, dpi=120)
open(out_csv, "w").write("\n".join(lines) + "\n")
