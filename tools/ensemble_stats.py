#!/usr/bin/python3
"""Mean ± sample standard deviation (range) of every numeric column of a markdown table, one run
per row: the ensemble row for tables that tools/ensemble.py does not summarise itself (the
asteroid runs, whose failure times are in seconds; docs/validation-asteroid.md).

Usage:
  docs/figures/asteroid/summarise_runs.py RUN1 RUN2 ... --target-mass M --times 5.638 10 15 \\
      | tools/ensemble_stats.py [--columns "largest m/M" "failure 15 s" ...]

Reads the markdown table on stdin (header row, an optional separator row, one row per run). A cell is
numeric if it starts with a number (a trailing unit or % is kept for the output format); '-',
'nan' or text cells are left out of that column's statistics and counted. Prints one line per
column: name, n, mean ± std (min-max). Standard deviations are sample ones (ddof = 1)."""

import argparse
import re
import sys

import numpy as np

NUM = re.compile(r"^\s*([-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?)\s*(%?)")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--columns", nargs="+", help="only these columns (header text)")
    args = ap.parse_args()
    rows = [line.strip() for line in sys.stdin if line.strip().startswith("|")]
    if len(rows) < 2:
        sys.exit("ensemble_stats: no markdown table with at least one row on stdin")
    split = lambda line: [c.strip() for c in line.strip("|").split("|")]  # noqa: E731
    header = split(rows[0])
    # The separator row (|---|---|) is optional: summarise_runs.py prints none.
    body = [split(r) for r in rows[1:] if not re.fullmatch(r"[|:\-\s]+", r)]
    for j, name in enumerate(header):
        if args.columns and name not in args.columns:
            continue
        vals, pct, skipped = [], False, 0
        for r in body:
            m = NUM.match(r[j]) if j < len(r) else None
            if m and m.group(1).lower() != "nan":
                vals.append(float(m.group(1)))
                pct = pct or m.group(2) == "%"
            else:
                skipped += 1
        if not vals:
            continue
        v = np.array(vals)
        sd = v.std(ddof=1) if len(v) > 1 else 0.0
        u = "%" if pct else ""
        extra = f" ({skipped} without a value)" if skipped else ""
        print(f"{name}: n = {len(v)}{extra}: {v.mean():.4g}{u} ± {sd:.2g}{u} "
              f"({v.min():.4g}{u}-{v.max():.4g}{u})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
