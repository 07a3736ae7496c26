#!/usr/bin/python3
"""Stress profile of the elastic-pulse ringing diagnostic against its exact solution.

Usage: plot_elastic_pulse.py RUN_DIR [RUN_DIR ...] [--time 8e-6] [--speed 160] [--flyer 12e-3]
                             [--out FILE.png]

Each RUN_DIR is a `shatter run` of scenes/diagnostics/elastic-pulse-ringing.toml (with any
--set). A flyer of thickness --flyer hits a block of the same material at --speed in uniaxial
strain, so both take up = speed / 2 and the exact pulse is sigma_xx = -rho0 c_p up between
x = c_p t - 2 L and x = c_p t, with the material behind it at rest and stress-free. --rho0 and
--cp default to the scene's basalt at rest (`shatter material basalt --rho 2700`: c_p = 4614.09
m/s from Eq. 13); the soundspeed column cannot be used, it includes the viscous signal speed.

Printed per run, as fractions of the exact amplitude rho0 c_p up: the plateau mean error (points
more than 3 cells from both ends of the exact pulse), the largest compression (overshoot) and the
largest tension anywhere. The exact solution has no tension at all before the pulse reaches the
far face, so the last figure is the spurious tension a fracture model sees."""

import argparse
import sys
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

# The readers (shatter_plot) are among the user's tools.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "tools"))
import shatter_plot as sp


def measure(run_dir, t, speed, flyer, rho0, cp):
    time, c, _ = sp.read_snapshot(sp.snapshot_at(run_dir, t))
    x, sxx = c["x"], c["sxx"]
    spacing = float(np.median(c["size0"])) if "size0" in c else 1.2e-3
    amp = rho0 * cp * 0.5 * speed
    front = cp * time
    margin = 3 * 2 * spacing  # three cells of two points
    plateau = (x > front - 2 * flyer + margin) & (x < front - margin)
    return {
        "time": time, "x": x, "sxx": sxx, "amp": amp, "front": front,
        "plateau_err": float(-sxx[plateau].mean() / amp - 1.0),
        "plateau_std": float(sxx[plateau].std() / amp),
        "overshoot": float(-sxx.min() / amp),
        "tension": float(max(sxx.max(), 0.0) / amp),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run_dirs", nargs="+")
    ap.add_argument("--time", type=float, default=8e-6, help="snapshot time (s)")
    ap.add_argument("--speed", type=float, default=160.0, help="flyer speed (m/s)")
    ap.add_argument("--flyer", type=float, default=12e-3, help="flyer thickness (m)")
    ap.add_argument("--rho0", type=float, default=2700.0, help="density at rest (kg/m3)")
    ap.add_argument("--cp", type=float, default=4614.09, help="longitudinal speed at rest (m/s)")
    ap.add_argument("--labels", nargs="*", help="legend labels (default: folder names)")
    ap.add_argument("--out", help="output image (default FIRST_RUN/plots/elastic_pulse.png)")
    a = ap.parse_args()

    labels = a.labels if a.labels else [sp.label_of(d) for d in a.run_dirs]
    fig, ax = plt.subplots(figsize=(8, 4.2))
    print("run, plateau error, plateau std, overshoot, largest tension (fractions of rho0 c_p up)")
    m = None
    for d, lab in zip(a.run_dirs, labels):
        m = measure(d, a.time, a.speed, a.flyer, a.rho0, a.cp)
        o = np.argsort(m["x"])
        ax.plot(m["x"][o] * 1e3, m["sxx"][o] / 1e6, ".-", ms=3, lw=0.8,
                label=f"{lab}: tension {m['tension']:.2f}, overshoot {m['overshoot']:.2f}")
        print(f"{lab}, {m['plateau_err']:+.3f}, {m['plateau_std']:.3f}, {m['overshoot']:.3f}, "
              f"{m['tension']:.3f}")
    # Exact pulse of the last run's constants (all runs share the material).
    xs = np.array([-a.flyer, m["front"] - 2 * a.flyer, m["front"] - 2 * a.flyer, m["front"],
                   m["front"], m["x"].max()])
    ys = np.array([0, 0, -m["amp"], -m["amp"], 0, 0]) / 1e6
    ax.plot(xs * 1e3, ys, "k--", lw=1.2, label="exact")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("sigma_xx (MPa)")
    ax.set_title(f"elastic pulse at t = {m['time'] * 1e6:.1f} us (exact: no tension)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    out = a.out or os.path.join(a.run_dirs[0], "plots", "elastic_pulse.png")
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    fig.tight_layout()
    fig.savefig(out, dpi=130)
    print(out)


if __name__ == "__main__":
    main()
