#!/usr/bin/python3
"""A notebook-style example: build a scene from a shipped one, sweep the impact speed, and read
each run's failure ratio and largest fragment.

    SHATTER_BINARY=build/release/shatter python3 python/examples/sweep_speed.py [OUT_DIR]

(about a second per run: the tiny lab impact of tests/fuzz/tiny.toml)."""

import os
import sys

import shatterpy as sp
import shatterpy.scenes as ss

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir)
out_dir = sys.argv[1] if len(sys.argv) > 1 else "out/sweep_speed"

# 1. Start from a scene file (or write the whole dict yourself).
scene = ss.load(os.path.join(ROOT, "tests", "fuzz", "tiny.toml"))

# 2. Change it, check it (shatter's own messages on a mistake), run it.
for speed in (2000.0, 3200.0):
    scene["impact"]["speed"] = speed
    scene["name"] = f"tiny-{speed:.0f}"
    ss.check(scene)
    run = ss.run(scene, os.path.join(out_dir, f"speed{speed:.0f}"), overwrite=True)

    # 3. Read the outputs.
    ts = sp.timeseries(run)
    mass, speeds, _ = sp.fragments(os.path.join(run, "fragments.csv"))
    print(f"{speed:6.0f} m/s: failure ratio {ts['failure_ratio'][-1]:.3f} at "
          f"{ts['time_s'][-1] * 1e6:.2f} us, {mass.size} fragments, largest {mass.max():.3g} kg")
