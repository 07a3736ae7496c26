"""Crater depth and diameter of an axisymmetric (r-z) run, at every snapshot.

usage: crater.py RUN_DIR [RUN_DIR ...]   (prints CSV: run,time_s,t_aU,depth_m,diameter_m,...)
       as a module: crater.profile(...), crater.measure(run_dir)

A thin wrapper kept for the studies that import it (crater_figure.py, studies/porosity): the
measure and its definition live in tools/crater.py (the installed crater report; its docstring
states the definition). This wrapper keeps the studies' conventions: the pre-impact surface at
z = 0, the body named "projectile" and the box target of the half-space scenes (scene_of).
"""
import glob
import importlib.util
import os
import sys
import tomllib

import h5py

# tools/crater.py under another module name: this file is itself imported as "crater".
_TOOL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools", "crater.py")
_spec = importlib.util.spec_from_file_location("shatter_tool_crater", _TOOL)
_tool = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_tool)
profile = _tool.profile
depth_and_diameter = _tool.depth_and_diameter


def scene_of(run_dir):
    with open(os.path.join(run_dir, "scene.toml"), "rb") as f:
        s = tomllib.load(f)
    h = s["solver"]["cell_size"]
    proj = s["body"]["projectile"]
    a, speed = proj["radius"], abs(proj["velocity"][2])
    target = s["body"]["target"]
    return h, a, speed, target["lo"][2], target["hi"][0]


def measure(run_dir):
    """[(time, t in a/U, depth, diameter, points)] for every snapshot of run_dir."""
    h, a, speed, z_bottom, r_max = scene_of(run_dir)
    rows = []
    for snap in sorted(glob.glob(os.path.join(run_dir, "snapshots", "*.h5"))):
        with h5py.File(snap) as f:
            t = float(f.attrs["time"])
            pos = f["particles/position"][()]
        tops = profile(pos[:, 0], pos[:, 2], h, h / 2.0, z_bottom, r_max)
        d, dia = depth_and_diameter(tops, h)
        rows.append((t, t * speed / a, d, dia, len(pos)))
    return rows, a


if __name__ == "__main__":
    print("run,time_s,t_aU,depth_m,diameter_m,depth_a,diameter_a,points")
    for run in sys.argv[1:]:
        rows, a = measure(run)
        for t, ta, d, dia, n in rows:
            print(f"{run},{t:.4g},{ta:.3f},{d:.5g},{dia:.5g},{d / a:.4f},{dia / a:.4f},{n}")
