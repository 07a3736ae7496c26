#!/usr/bin/python3
"""Summarise `shatter run` directories of the stability scenes (scenes/stability/) as the rows of
docs/stability.md: steps, min/max dt, energy error, peak pressure and specific internal energy,
the Tillotson regions reached, wall time and outcome.

    /usr/bin/python3 tools/stability_report.py OUT_DIR [OUT_DIR ...]

dt comes from timeseries.csv (write it every step: --set output.timeseries_every=1); steps that
were shortened to land on a snapshot or the end time are left out of the minimum. Peak pressure
and energy are sampled at the snapshots only (use a fine --set output.snapshot_every). The
Tillotson regions follow kernels/eos/tillotson.hpp (TillotsonRegion) with the catalogue's
parameters and the scene's overrides.
"""

import argparse
import csv
import glob
import math
import os
import sys
import tomllib

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REGIONS = ["compressed", "cold_expanded", "mixed", "hot_expanded", "vapour_expansion"]


def tillotson_regions(rho, e, q):
    """Region index per point, as TillotsonRegion::region (E < 0 counts as 0)."""
    e = np.maximum(e, 0.0)
    rho_iv = q.get("rho_iv", 0.0)
    r = np.where(e <= q["Eiv"], 1, 2)
    r = np.where(rho < rho_iv, 4, r)
    r = np.where(e >= q["Ecv"], 3, r)
    return np.where(rho >= q["rho0"], 0, r)


def materials(scene):
    with open(os.path.join(ROOT, "data", "materials.toml"), "rb") as f:
        catalogue = tomllib.load(f)
    out = []
    for name in sorted(scene["body"]):  # bodies are in key order, as the scene reader keeps them
        m = scene["body"][name]["material"]
        if isinstance(m, str):
            spec = dict(catalogue[m])
        else:
            spec = dict(catalogue[m["name"]])
            spec.update({k: v for k, v in m.items() if k != "name"})
        out.append((name, spec))
    return out


def summarise(run):
    with open(os.path.join(run, "scene.toml"), "rb") as f:
        scene = tomllib.load(f)
    rows = list(csv.DictReader(open(os.path.join(run, "timeseries.csv"))))
    every = scene["output"]["snapshot_every"]
    end = scene["solver"]["end_time"]

    def landing(t):
        return abs(t - end) < 1e-12 * end or (
            every > 0 and abs(t / every - round(t / every)) < 1e-6
        )

    dts = [float(r["dt_s"]) for r in rows[1:] if not landing(float(r["time_s"]))]
    err = [abs(float(r["energy_error"])) for r in rows]
    last = rows[-1]

    bodies = materials(scene)
    p_max = e_max = 0.0
    block = 4 * scene["solver"]["cell_size"]  # SparseGrid::kBlock nodes per block edge
    occupied = box = 0
    reached = {name: set() for name, _ in bodies}
    for snap in sorted(glob.glob(os.path.join(run, "snapshots", "*.h5"))):
        with h5py.File(snap) as f:
            P = f["particles"]
            p, e, rho, body = P["pressure"][:], P["energy"][:], P["rho"][:], P["body"][:]
            xyz = np.stack([P["x"][:], P["y"][:], P["z"][:]], axis=1)
        keys = np.floor(xyz / block).astype(np.int64)
        occupied = max(occupied, len(np.unique(keys, axis=0)))
        box = max(box, int(np.prod(keys.max(axis=0) - keys.min(axis=0) + 1)))
        p_max = max(p_max, float(p.max()))
        e_max = max(e_max, float(e.max()))
        for b, (name, spec) in enumerate(bodies):
            if spec.get("eos") != "tillotson":
                continue
            sel = body == b
            for r in np.unique(tillotson_regions(rho[sel], e[sel], spec)):
                reached[name].add(REGIONS[r])

    failed = glob.glob(os.path.join(run, "failed_step*.h5"))
    log = os.path.join(os.path.dirname(run.rstrip("/")), os.path.basename(run.rstrip("/")) + ".log")
    wall = float(last["wall_s"])
    if os.path.exists(log):
        for line in open(log):
            if " wall " in line and "maxrss" in line:
                wall = float(line.split(" wall ")[1].split()[0])
    outcome = (
        f"stopped: {os.path.basename(failed[0])}" if failed
        else "end time reached" if math.isclose(float(last["time_s"]), end, rel_tol=1e-9)
        else f"stopped at t = {last['time_s']}"
    )
    return {
        "scene": scene["name"],
        "steps": int(last["step"]),
        "t_end_us": float(last["time_s"]) * 1e6,
        "dt_min": min(dts),
        "dt_max": max(dts),
        "dt_first": dts[0],
        "err_max": max(err),
        "err_final": float(last["energy_error"]),
        "outflow_J": float(last["outflow_J"]),
        "p_max_GPa": p_max / 1e9,
        "E_max_MJkg": e_max / 1e6,
        "regions": {k: sorted(v, key=REGIONS.index) for k, v in reached.items()},
        "blocks": (occupied, box),
        "wall_s": wall,
        "outcome": outcome,
    }


def main(runs):
    print("| scene | steps | dt first / min / max (ns) | max abs energy error (final) | "
          "p max (GPa) | E max (MJ/kg) | wall (s) | outcome |")
    print("|---|---:|---|---|---:|---:|---:|---|")
    details = []
    for run in runs:
        s = summarise(run)
        print(f"| {s['scene']} | {s['steps']} | {s['dt_first']*1e9:.1f} / {s['dt_min']*1e9:.1f} / "
              f"{s['dt_max']*1e9:.1f} | {s['err_max']:.2e} ({s['err_final']:+.2e}) | "
              f"{s['p_max_GPa']:.3g} | {s['E_max_MJkg']:.3g} | {s['wall_s']:.0f} | "
              f"{s['outcome']} |")
        details.append(s)
    print()
    for s in details:
        regions = "; ".join(f"{k}: {', '.join(v)}" for k, v in s["regions"].items() if v)
        print(f"- {s['scene']}: Tillotson regions reached: {regions}; outflow "
              f"{s['outflow_J']:.3g} J; blocks holding points (most at a snapshot) "
              f"{s['blocks'][0]}, bounding box {s['blocks'][1]} blocks")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", metavar="OUT_DIR", help="a `shatter run` directory")
    main(ap.parse_args().runs)
