#!/usr/bin/python3
"""beta of the iSALE-2D DART-like grid of Raducan et al. 2019 from their published ejecta tracers.

Source: Raducan, Davison, Luther & Collins 2019, Icarus 329, "The role of asteroid strength,
porosity and internal friction in impact momentum transfer"; data and inputs in the public
repository sr516/iSALE_ejecta_data (licence CC BY-NC-SA 4.0). That repository is NOT shipped
with shatter: pass the path of a local copy. This script reads it and writes derived numbers only
(docs/figures/dart/raducan2019_beta.csv; docs/validation-dart.md).

Each CSV of Porosity/Yd1eN/ and Friction/Yd1eN/ lists the ejected tracers (columns x, m, v_x,
v_y: launch distance from the axis in m, tracer mass in kg, velocity components in m/s where the
tracer crossed the ejection plane EJECT_V = 0.84 m above the surface). As their
pySALEPlot/integration.py (the lines `pt = mass_ej*vel_y`, `beta = ejp[-1]/(m*U)+1`):

    beta = 1 + sum(m_i v_y,i) / (m_imp U),   m_imp = 4/3 pi a^3 delta

Constants and where they come from (iSALE_inputs/Parameter_studies/ of the repository):
  a     = 0.42 m     OBJRESH 40 (Yd1e3_r_1.inp line 24) x GRIDSPC 1.05e-2 m (line 14)
  U     = 7000 m/s   OBJVEL -7.0D3 (Yd1e3_r_1.inp line 26)
  delta = 1000 kg/m3 impactor bulk density: Tillotson aluminium (material.inp EOSNAME aluminu;
                     grain density 2700 kg/m3, the classic Tillotson aluminium value, not stated in
                     the repository) over its distension ALPHA0 2.7 (material.inp, impactr column)
  so m_imp = 310.3 kg (the 300 kg DART design of the time).
  EJECT_V = 0.84 m (Yd1e3_r_1.inp line 33) is where the velocities were taken; v_thr 0.1 m/s is
  integration.py's speed cut (the tracers in the CSVs are all faster: the cut is already applied).
Parameter points, from the file names (README of Parameter_studies: YDAM0, FRICDAM and ALPHA0 are
what the studies change; Porosity/Yd1e3/ also holds the Yd1e5-* series):
  Yd1eN        -> Ydam0 = 10^N Pa (YDAM0)
  Porosity/*-PP -> porosity PP %, f = 0.6 (FRICDAM of material.inp)
  Friction/*-FF -> f = FF/10; porosity 20% assumed (the README's nominal target; the shipped
                  material.inp has ALPHA0 1.3, i.e. 23%: which one the friction series used is not
                  stated in the repository)

Also written per point: the ejected mass M/m_imp; M(>v)/m_imp at v/U = 5e-2, 2e-2, 1e-2, 1e-3, 1e-4 (launch
speed sqrt(v_x^2 + v_y^2)); and 1 + p_ej(>v)/(m_imp U), the beta counted from the ejecta faster than
v only (a short run counts only the fast, early ejecta: this is what it can be compared with).

Usage: raducan2019_beta.py PATH_TO_iSALE_ejecta_data [--csv OUT.csv]
"""

import argparse
import csv
import glob
import math
import os
import re
import sys

A_IMP = 40 * 1.05e-2  # m
U_IMP = 7000.0  # m/s
DELTA = 2700.0 / 2.7  # kg/m^3
M_IMP = 4.0 / 3.0 * math.pi * A_IMP**3 * DELTA
V_FRACTIONS = (5e-2, 2e-2, 1e-2, 1e-3, 1e-4)
# Points whose data look wrong, with why (found by this script's own numbers).
SUSPECT = {
    ("Porosity", "Yd1e5-50.csv"):
        "its ejecta faster than 1e-3 U are those of Yd1e3-50 (same mass and momentum there, same"
        " first tracer): possibly the 1 kPa run relabelled or restarted; beta breaks the trend",
}


def parameter_point(series, name):
    """(cohesion Pa, porosity %, friction) from a file name such as Yd1e4-20.csv."""
    m = re.fullmatch(r"Yd1e(\d)-(\d\d)\.csv", name)
    if not m:
        return None
    cohesion = 10.0 ** int(m.group(1))
    value = int(m.group(2))
    if series == "Porosity":
        return cohesion, value, 0.6
    return cohesion, 20, value / 10.0


def measures(path):
    with open(path) as f:
        rows = [(float(r["m"]), float(r["v_x"]), float(r["v_y"])) for r in csv.DictReader(f)]
    mass = sum(m for m, _, _ in rows)
    out = {"tracers": len(rows), "mass_over_mimp": mass / M_IMP,
           "beta": 1.0 + sum(m * vy for m, _, vy in rows) / (M_IMP * U_IMP)}
    for q in V_FRACTIONS:
        fast = [(m, vy) for m, vx, vy in rows if math.hypot(vx, vy) > q * U_IMP]
        out[f"M_gt_{q:g}U_over_mimp"] = sum(m for m, _ in fast) / M_IMP
        out[f"beta_gt_{q:g}U"] = 1.0 + sum(m * vy for m, vy in fast) / (M_IMP * U_IMP)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("repo", help="local copy of sr516/iSALE_ejecta_data")
    ap.add_argument("--csv", help="write the table here")
    args = ap.parse_args()
    table = []
    for series in ("Porosity", "Friction"):
        for path in sorted(glob.glob(os.path.join(args.repo, series, "Yd1e*", "*.csv"))):
            point = parameter_point(series, os.path.basename(path))
            if point is None:
                continue
            table.append({"series": series, "cohesion_Pa": point[0], "porosity_pct": point[1],
                          "friction": point[2], **measures(path),
                          "note": SUSPECT.get((series, os.path.basename(path)), "")})
    if not table:
        sys.exit(f"no Porosity/ or Friction/ tracer files under {args.repo}")
    table.sort(key=lambda r: (r["series"], r["cohesion_Pa"], r["porosity_pct"], r["friction"]))
    keys = list(table[0].keys())
    print(f"m_imp = {M_IMP:.1f} kg, U = {U_IMP:.0f} m/s, a = {A_IMP:.2f} m")
    print("  ".join(keys))
    for r in table:
        print("  ".join(f"{r[k]:.4g}" if isinstance(r[k], float) else str(r[k]) for k in keys
                        if k != "note"), "SUSPECT" if r["note"] else "")
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            f.write("# beta and ejecta of the iSALE-2D DART-like grid of Raducan, Davison, Luther &"
                    " Collins 2019 (Icarus 329), derived by studies/dart/raducan2019_beta.py from"
                    " their tracer data, repository sr516/iSALE_ejecta_data (CC BY-NC-SA 4.0):"
                    " derived numbers only.\n")
            f.write(f"# m_imp = {M_IMP:.2f} kg (a = {A_IMP:.2f} m, delta = {DELTA:.0f} kg/m^3),"
                    f" U = {U_IMP:.0f} m/s; velocities at EJECT_V = 0.84 m; friction-series"
                    " porosity 20% assumed\n")
            w = csv.DictWriter(f, fieldnames=keys)
            w.writeheader()
            for r in table:
                w.writerow({k: (f"{v:.5g}" if isinstance(v, float) else v) for k, v in r.items()})


if __name__ == "__main__":
    main()
