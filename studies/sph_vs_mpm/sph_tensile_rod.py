#!/usr/bin/python3
"""Tensile rod study with SPH or MPM (Benz & Asphaug 1995, Sec. 5.1; issue 10 "Tensile rod").

Runs the verification test SphTensileRod.DISABLED_Study (tests/verification/sph/
tensile_rod_test.cpp: a basalt cylinder 1 cm x 4 cm between two grips pulled at 10/s and 60/s,
explicit Weibull flaws, to 25.8 us) at the given spacing over the given number of flaw seeds,
and tabulates per rate: first-failure strain, failed fraction, pieces >= 5 % of the rod, the
first crack's speed over c_g = 0.4 c_p (c_p = 4616 m/s) by two estimators (the earliest
failure per ring around the nucleus, and the time half of each ring has failed), mean +- sample std over seeds.

The grips are the scene's driven bodies (body.NAME.driven = true), so the same scene runs with
either method: --method mpm sets solver.method = "mpm" (cell = 2 spacings, 2 points per cell).

Usage:
  sph_tensile_rod.py [--method sph|mpm] [--spacing 1.25e-3] [--seeds 3] [--binary build/release/tests/verification_sph]
                     [--out FILE.md] [--end-factor 1]
Run it under nice on a shared machine: one run at 1.25 mm is ~30 s of CPU.
"""

import argparse
import os
import re
import statistics
import subprocess
import sys


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--method", choices=["sph", "mpm"], default="sph")
    ap.add_argument("--spacing", type=float, default=1.25e-3)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--binary", default="build/release/tests/verification_sph")
    ap.add_argument("--out", help="also write the markdown table here")
    ap.add_argument("--end-factor", type=float, default=1.0,
                    help="end time in units of the study's 25.8 us (a longer pull)")
    args = ap.parse_args()
    env = dict(os.environ, SHATTER_ROD_SPACING=str(args.spacing), SHATTER_ROD_SEEDS=str(args.seeds),
               SHATTER_ROD_END_FACTOR=str(args.end_factor), SHATTER_ROD_METHOD=args.method)
    proc = subprocess.run(
        [args.binary, "--gtest_also_run_disabled_tests", "--gtest_filter=SphTensileRod.DISABLED_Study"],
        env=env, capture_output=True, text=True)
    rows = []
    for line in proc.stdout.splitlines():
        if not line.startswith("ROD "):
            continue
        rows.append({k: float(v) for k, v in re.findall(r"(\w+)=([-+0-9.eE]+|nan)", line)})
        print(line, flush=True)
    if proc.returncode != 0 or not rows:
        sys.stderr.write(proc.stdout[-2000:] + proc.stderr[-2000:])
        sys.exit(1)

    def stat(vals, fmt):
        vals = [v for v in vals if v == v]
        if not vals:
            return "-"
        if len(vals) == 1:
            return fmt.format(vals[0])
        return (fmt + " +- " + fmt).format(statistics.mean(vals), statistics.stdev(vals))

    lines = [f"Tensile rod, {args.method.upper()}, spacing {args.spacing * 1e3:g} mm, {args.seeds} seeds "
             f"({int(rows[0]['points'])} rod points, {int(rows[0]['steps'])} steps)", "",
             "| pull rate (1/s) | first failure strain | failed fraction | pieces >= 5 % | "
             "crack speed / c_g (earliest per ring) | (half-failed time per ring) | crack points |",
             "|---|---|---|---|---|---|---|"]
    for rate in sorted({r["rate"] for r in rows}):
        rr = [r for r in rows if r["rate"] == rate]
        lines.append("| {:g} | {} | {} | {} | {} | {} | {} |".format(
            rate, stat([r["eps_first"] for r in rr], "{:.3g}"),
            stat([r["failed"] for r in rr], "{:.2f}"),
            stat([r["fragments"] for r in rr], "{:.1f}"),
            stat([r["crack_speed"] / r["cg"] for r in rr], "{:.2f}"),
            stat([r.get("crack_speed_half", float("nan")) / r["cg"] for r in rr], "{:.2f}"),
            stat([r["crack_points"] for r in rr], "{:.0f}")))
    text = "\n".join(lines)
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")


if __name__ == "__main__":
    main()
