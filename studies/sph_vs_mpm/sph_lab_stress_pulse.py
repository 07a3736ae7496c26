#!/usr/bin/python3
"""Laboratory impact, stress pulse on the impact axis, SPH beside MPM (issue 10, "Laboratory
impact": axial stress and largest principal stress along the impact axis at 10, 20 and 30 mm,
damage off and on).

From runs of scenes/lab-impact.toml with dense snapshots (e.g. --set output.snapshot_every=0.5e-6),
the target points within --width of each distance from the impact point and within --cone
degrees of the line from the impact point through the target centre (studies/verification/spherical_wave.py
read_axis_history: the same gauge as the MPM studies of docs/verification.md), per snapshot:
the mean axial (radial from the impact point) stress s_rr and the mean largest principal stress.
Table: the peak compression (min s_rr) and the peak tension (max largest principal stress) at
each distance, and the arrival time of the compression (first time s_rr < half its minimum);
plot: the histories.

Runs that share a label are one ensemble (flaw seeds): the table gives each peak as mean +-
sample std (range) over the runs' own peaks, the plot the mean history and its min-max band.

Usage:
  sph_lab_stress_pulse.py RUN [RUN ...] --label L [L ...] [--radii 0.01 0.02 0.03]
                          [--plot FILE.png]
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "verification"))
import spherical_wave as sw  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--label", nargs="+", required=True)
    ap.add_argument("--radii", type=float, nargs="+", default=[0.01, 0.02, 0.03])
    ap.add_argument("--width", type=float, default=1.5e-3)
    ap.add_argument("--cone", type=float, default=20.0)
    ap.add_argument("--plot")
    args = ap.parse_args()
    if len(args.label) != len(args.runs):
        raise SystemExit("--label needs one label per run")
    groups = {}
    for run, lab in zip(args.runs, args.label):
        h, _ = sw.read_axis_history(run, args.radii, args.width, args.cone)
        groups.setdefault(lab, []).append(h)

    def fmt(vals, f):
        vals = [v for v in vals if v == v]
        if len(vals) == 1:
            return f.format(vals[0])
        return (f + " ± " + f + " (" + f + " to " + f + ")").format(
            np.mean(vals), np.std(vals, ddof=1), min(vals), max(vals))

    head = ["run", "runs"]
    for r in args.radii:
        head += [f"{1e3 * r:g} mm: points", "min s_rr (MPa)", "arrival (us)", "max s_1 (MPa)"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for lab, hs in groups.items():
        row = [lab, str(len(hs))]
        for r in args.radii:
            mins, arrs, maxs = [], [], []
            for h in hs:
                g = h[r]
                i = int(np.argmin(g["srr"]))
                half = np.nonzero(g["srr"] < 0.5 * g["srr"][i])[0]
                arrs.append(g["t"][half[0]] * 1e6 if len(half) else float("nan"))
                mins.append(g["srr"][i] / 1e6)
                maxs.append(g["smax"].max() / 1e6)
            row += [str(hs[0][r]["points"]), fmt(mins, "{:.0f}"), fmt(arrs, "{:.1f}"),
                    fmt(maxs, "{:.0f}")]
        print("| " + " | ".join(row) + " |")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(2, len(args.radii), figsize=(4.2 * len(args.radii), 6.5),
                               sharex=True)
        styles = ["-", "--", "-.", ":"]
        colours = ["tab:blue", "tab:red", "tab:green", "tab:purple", "tab:orange", "tab:brown"]
        for k, (lab, hs) in enumerate(groups.items()):
            for j, r in enumerate(args.radii):
                n = min(len(h[r]["t"]) for h in hs)
                t = hs[0][r]["t"][:n] * 1e6
                col = colours[k % len(colours)]
                kw = dict(color=col, ls=styles[(k // 2) % len(styles)], lw=1.3,
                          label=lab + (f" (mean of {len(hs)})" if len(hs) > 1 else ""))
                for row, key in ((0, "srr"), (1, "smax")):
                    v = np.array([h[r][key][:n] for h in hs]) / 1e6
                    ax[row, j].plot(t, v.mean(0), **kw)
                    if len(hs) > 1:
                        ax[row, j].fill_between(t, v.min(0), v.max(0), color=col, alpha=0.2,
                                                lw=0)
                ax[0, j].set_title(f"{1e3 * r:g} mm from the impact point (axis, +-"
                                   f"{args.cone:g} deg)", fontsize=9)
        for j in range(len(args.radii)):
            ax[0, j].set_ylabel("axial stress s_rr (MPa)")
            ax[1, j].set_ylabel("largest principal stress (MPa)")
            ax[1, j].set_xlabel("t (us)")
            for a in ax[:, j]:
                a.axhline(0.0, color="grey", lw=0.6)
        ax[0, 0].legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=90)
        print("wrote", args.plot)


if __name__ == "__main__":
    main()
