#!/usr/bin/python3
"""Planar spall in basalt (scenes/diagnostics/spall-basalt.toml), SPH beside MPM.

Usage: spall_profile.py RUN [RUN ...] --label L [L ...] [--times 16e-6 18e-6 20e-6 24e-6 30e-6]
                        [--plot FILE.png]

Per run, from the slab's points (body "slab") averaged over each layer of equal starting x:
damage, axial stress s_xx and velocity v_x against the starting position x0, at the given
times and at the end. Printed: where the slab failed (layers with mean D >= 0.9, in mm of x0),
how many points failed outside the analytic spall plane's +-3 mm (x0 = 60 mm, the flyer's
thickness inside the rear face), the mean speed of the spalled layer (x0 > 60 mm; elastic
theory 2 up = 30 m/s) and of the rest (x0 < 57 mm; 0 after the whole pulse is trapped), the
largest layer-mean tension left in the rest of the slab after the spall, and the opening of the
spall plane (x gap between the layers either side of the failed band, minus the starting gap).
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "tools"))
import shatter_plot as sp  # noqa: E402

SPALL = 0.060


def layers(run):
    files = sp.snapshots(run)
    _, first, _ = sp.read_snapshot(files[0])
    names, _ = sp.snapshot_names(files[0])
    slab = names.index("slab")
    ids = np.sort(first["id"][first["body"].astype(int) == slab].astype(np.int64))
    o = np.argsort(first["id"].astype(np.int64))
    k = o[np.searchsorted(first["id"].astype(np.int64)[o], ids)]
    x0 = np.round(first["x"][k], 6)
    xs = np.unique(x0)
    lay = np.searchsorted(xs, x0)
    out = {"x0": xs, "t": [], "d": [], "sxx": [], "vx": [], "x": [], "dfail": []}
    for f in files:
        t, c, _ = sp.read_snapshot(f)
        cid = c["id"].astype(np.int64)
        o = np.argsort(cid)
        k = o[np.searchsorted(cid[o], ids)]
        cnt = np.bincount(lay, minlength=len(xs))

        def mean(v):
            return np.bincount(lay, weights=v, minlength=len(xs)) / cnt
        out["t"].append(t)
        out["d"].append(mean(c["damage"][k]))
        out["dfail"].append(mean((c["damage"][k] >= 0.9).astype(float)))
        out["sxx"].append(mean(c["sxx"][k]))
        out["vx"].append(mean(c["vx"][k]))
        out["x"].append(mean(c["x"][k]))
    return {k: np.array(v) for k, v in out.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--label", nargs="+", required=True)
    ap.add_argument("--times", type=float, nargs="+", default=[16e-6, 18e-6, 20e-6, 24e-6, 30e-6])
    ap.add_argument("--plot")
    a = ap.parse_args()
    if len(a.label) != len(a.runs):
        raise SystemExit("--label needs one label per run")
    res = {lab: layers(r) for lab, r in zip(a.label, a.runs)}
    print("| run | failed layers (x0, mm) | points failed beyond 60 +- 3 mm | spall layer v_x "
          "(m/s) | rest v_x | largest tension left in x0 < 57 mm after 20 us (MPa) | "
          "opening of the spall plane at the end (mm) |")
    print("|---|---|---|---|---|---|---|")
    for lab, L in res.items():
        x0 = L["x0"]
        fl = L["dfail"][-1] >= 0.5
        band = x0[fl]
        far = np.abs(x0 - SPALL) > 3e-3
        nfar = (L["dfail"][-1][far]).sum()
        desc = (f"{1e3 * band.min():.1f}-{1e3 * band.max():.1f} ({fl.sum()} layers)"
                if fl.any() else "none")
        spl = x0 > SPALL
        rest = x0 < SPALL - 3e-3
        late = L["t"] > 20e-6
        tens = L["sxx"][late][:, rest].max() / 1e6 if late.any() else np.nan
        if fl.any():
            lo, hi = np.where(fl)[0].min() - 1, np.where(fl)[0].max() + 1
            hi = min(hi, len(x0) - 1)
            lo = max(lo, 0)
            opening = (L["x"][-1][hi] - L["x"][-1][lo]) - (x0[hi] - x0[lo])
        else:
            opening = np.nan
        print(f"| {lab} | {desc} | {nfar:.1f} layers' worth | {L['vx'][-1][spl].mean():.1f} | "
              f"{L['vx'][-1][rest].mean():.2f} | {tens:.1f} | {1e3 * opening:.3f} |")
    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(3, len(res), figsize=(5.5 * len(res), 8), sharex=True,
                               squeeze=False)
        for j, (lab, L) in enumerate(res.items()):
            x0 = 1e3 * L["x0"]
            for tt in list(a.times) + [L["t"][-1]]:
                i = int(np.argmin(np.abs(L["t"] - tt)))
                lw = 1.6 if tt == L["t"][-1] else 0.9
                lbl = f"{1e6 * L['t'][i]:.0f} us"
                ax[0, j].plot(x0, L["sxx"][i] / 1e6, lw=lw, label=lbl)
                ax[1, j].plot(x0, L["vx"][i], lw=lw, label=lbl)
                ax[2, j].plot(x0, L["d"][i], lw=lw, label=lbl)
            ax[0, j].set_title(lab)
            ax[0, j].set_ylabel("layer mean s_xx (MPa)")
            ax[1, j].set_ylabel("v_x (m/s)")
            ax[2, j].set_ylabel("damage")
            ax[2, j].set_xlabel("starting x (mm)")
            for i in range(3):
                ax[i, j].axvline(60, color="k", lw=0.5, ls="--")
            ax[0, j].legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(a.plot, dpi=80)


if __name__ == "__main__":
    main()
