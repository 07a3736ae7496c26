#!/usr/bin/env python3
"""The r-z spherical wave against its exact solution (docs/validation-axisymmetric.md).

Reads the output of
  SPHERICAL_WAVE_RZ_CELLS="4 8 16 32" build/release/tests/verification_axisymmetric \
      --gtest_filter='SphericalWaveRz.Study' > study.txt
and writes the error against resolution (with the fitted order of the two finest) and the shell
profiles at c t = 2.5 a: docs/figures/axisymmetric/spherical_wave_rz.{png,csv}.
Run with /usr/bin/python3 (Debian's matplotlib): spherical_wave_rz.py study.txt OUT_DIR
"""
import math
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    errors, profiles = {}, {}
    label = None
    for line in open(path):
        m = re.match(r"rz (\w+) a/h=(\d+) ", line)
        if m:
            label = (m.group(1), int(m.group(2)))
            continue
        m = re.match(r"\s+s_rr L2 (\S+) max \S+ \| s_tt L2 (\S+) max \S+ \| v_r L2 (\S+)", line)
        if m and label:
            errors[label] = tuple(float(x) for x in m.groups())
        if line.startswith("profile "):
            f = line.split()
            profiles.setdefault((f[1], int(f[2])), []).append([float(x) for x in f[3:]])
    return errors, profiles


def main():
    study, out = sys.argv[1], sys.argv[2]
    errors, profiles = read(study)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2))
    rows = ["shape,cells_per_a,srr_l2,stt_l2,vr_l2"]
    for shape, mark in (("linear", "o"), ("bspline2", "s")):
        n = sorted(k[1] for k in errors if k[0] == shape)
        for i, name in enumerate(("s_rr", "s_tt")):
            e = [errors[(shape, k)][i] for k in n]
            order = math.log(e[-2] / e[-1]) / math.log(n[-1] / n[-2])
            ax.loglog(n, e, mark + "-", label=f"{shape} {name} (order {order:.2f}, last pair)")
        for k in n:
            rows.append(f"{shape},{k}," + ",".join(f"{v:.6g}" for v in errors[(shape, k)]))
    ax.set_xlabel("cells per bump radius a/h")
    ax.set_ylabel("L2 error / exact peak |s_rr|")
    ax.set_title("r-z spherical wave at c t = 2.5 a")
    ax.legend(fontsize=7)
    ax.grid(True, which="both", alpha=0.3)
    fine = max(k[1] for k in profiles)
    p = profiles[("bspline2", fine)]
    r = [q[0] / 0.1 for q in p]
    bx.plot(r, [q[1] / 1e6 for q in p], "b.", ms=3, label=f"s_rr r-z (a/h = {fine})")
    bx.plot(r, [q[2] / 1e6 for q in p], "b-", lw=1, label="s_rr exact")
    bx.plot(r, [q[3] / 1e6 for q in p], "r.", ms=3, label="s_tt r-z")
    bx.plot(r, [q[4] / 1e6 for q in p], "r-", lw=1, label="s_tt exact")
    bx.set_xlabel("r / a")
    bx.set_ylabel("stress (MPa), shell means")
    bx.legend(fontsize=7)
    bx.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(f"{out}/spherical_wave_rz.png", dpi=120)
    open(f"{out}/spherical_wave_rz.csv", "w").write("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
