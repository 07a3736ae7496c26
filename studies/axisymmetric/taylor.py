"""Taylor bar: final length and mushroom radius of the rod, r-z against 3-D and the benchmark.
usage: taylor.py OUT.csv LABEL=DIR[:CPU_S] ...  (DIR: a run of scenes/verification/taylor-*.toml)

As tests/verification/axisymmetric/taylor_bar_test.cpp: L = max z - min z + s on the points'
cells (s the point spacing; L0 for the initial rod); R = R0 + max r - max r_initial, the outward
displacement of the outermost point (r = x in r-z, hypot(x, y) in 3-D).
"""
import sys, glob
import h5py, numpy as np

L0, R0 = 32.4e-3, 3.2e-3  # m, taylor-rz.toml

rows = ["label,cell_mm,points,steps,L_mm,L_over_L0,R_mm,R_over_R0,cpu_s"]
for arg in sys.argv[2:]:
    label, d = arg.split("=", 1)
    d, _, cpu = d.partition(":")
    snaps = sorted(glob.glob(d + "/snapshots/*.h5"))
    first, last = h5py.File(snaps[0]), h5py.File(snaps[-1])
    a, b = first["particles/position"][()], last["particles/position"][()]
    s = np.min(np.diff(np.unique(np.round(a[:, 2], 9))))  # the lattice spacing along z
    L = b[:, 2].max() - b[:, 2].min() + s
    R = R0 + np.hypot(b[:, 0], b[:, 1]).max() - np.hypot(a[:, 0], a[:, 1]).max()
    rows.append(f"{label},{2 * s * 1e3:.2g},{len(a)},{last.attrs['step']},{L * 1e3:.2f},"
                f"{L / L0:.4f},{R * 1e3:.2f},{R / R0:.3f},{cpu}")
open(sys.argv[1], "w").write("\n".join(rows) + "\n")
print("\n".join(rows))
