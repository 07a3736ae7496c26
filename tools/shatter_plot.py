"""Shared readers for the plot scripts: a run directory holds timeseries.csv, snapshots/*.h5,
fragments.csv and scene.toml (written by `shatter run`)."""

import csv
import glob
import os

import h5py
import numpy as np


def timeseries(run_dir):
    """Columns of timeseries.csv as numpy arrays keyed by header name (units in the names)."""
    with open(os.path.join(run_dir, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]} if rows else {}


def snapshots(run_dir):
    return sorted(glob.glob(os.path.join(run_dir, "snapshots", "snapshot_*.h5")))


def read_snapshot(path):
    """(time in s, dict column -> array, symmetry axis or -1)."""
    with h5py.File(path, "r") as f:
        cols = {k: f["particles"][k][()] for k in f["particles"]}
        axis = int(f.attrs.get("symmetry_axis", 0)) - 1
        return float(f.attrs["time"]), cols, axis


def snapshot_at(run_dir, t):
    """The snapshot closest in time to t (s)."""
    files = snapshots(run_dir)
    times = [read_snapshot_time(p) for p in files]
    return files[int(np.argmin([abs(x - t) for x in times]))]


def read_snapshot_time(path):
    with h5py.File(path, "r") as f:
        return float(f.attrs["time"])


def fragments(path):
    """Fragment table (fragments.csv): header comment with the total mass, then one row each."""
    with open(path) as f:
        first = f.readline()
        meta = dict(kv.split("=") for kv in first.lstrip("# ").split())
        rows = list(csv.DictReader(f))
    mass = np.array([float(r["mass_kg"]) for r in rows])
    speed = np.array([np.linalg.norm([float(r["vx_m/s"]), float(r["vy_m/s"]), float(r["vz_m/s"])])
                      for r in rows])
    return mass, speed, float(meta["total_mass_kg"])


def label_of(run_dir):
    return os.path.basename(os.path.normpath(run_dir))
