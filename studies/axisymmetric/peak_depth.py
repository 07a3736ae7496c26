"""Peak pressure against depth below the impact point along the axis, r-z against 3-D.
usage: peak_depth.py OUT.png OUT.csv LABEL=DIR ...  (axis: z through x = y = 0; impact at z = 0)"""
import sys, glob
import h5py, numpy as np
import matplotlib; matplotlib.use("Agg")
import matplotlib.pyplot as plt

def load(d):
    snaps = sorted(glob.glob(d + "/snapshots/*.h5"))
    first, last = h5py.File(snaps[0]), h5py.File(snaps[-1])
    ids0 = first["particles/id"][()]
    x0 = first["particles/position"][()]
    pos = dict(zip(ids0.tolist(), range(len(ids0))))
    ids = last["particles/id"][()]
    idx = np.array([pos[i] for i in ids])
    p0 = x0[idx]
    body = last["particles/body"][()]
    pk = last["particles/peak_pressure"][()]
    r = np.hypot(p0[:, 0], p0[:, 1]); depth = -p0[:, 2]
    names = [n.decode() for n in last["names/body"][()]]
    return r, depth, pk, body == names.index("target")

out_png, out_csv = sys.argv[1], sys.argv[2]
plt.figure(figsize=(6, 4))
rows = []
for arg in sys.argv[3:]:
    label, d = arg.split("=", 1)
    r, depth, pk, body = load(d)
    sel = body & (r < 1.7e-3) & (depth > 0)
    bins = np.arange(0, 0.03, 1.6e-3)
    k = np.digitize(depth[sel], bins)
    ds, ps = [], []
    for b in range(1, len(bins)):
        m = k == b
        if m.any():
            ds.append(0.5 * (bins[b - 1] + bins[b]) * 1e3); ps.append(pk[sel][m].max() / 1e9)
            rows.append(f"{label},{ds[-1]:.2f},{ps[-1]:.4g}")
    plt.semilogy(ds, ps, "o-", label=f"{label} ({sel.sum()} points near the axis)")
plt.xlabel("depth below the impact point (mm)"); plt.ylabel("peak pressure (GPa), max per bin")
plt.legend(fontsize=7); plt.grid(True, which="both", alpha=0.3); plt.tight_layout()
plt.savefig(out_png, dpi=120)
open(out_csv, "w").write("run,depth_mm,peak_GPa\n" + "\n".join(rows) + "\n")
