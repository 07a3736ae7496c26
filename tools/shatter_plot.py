"""Shared readers for the plot scripts: a run directory holds timeseries.csv, snapshots/*.h5,
fragments.csv and scene.toml (written by `shatter run`)."""

import csv
import glob
import os
import zlib

import h5py
import numpy as np


def timeseries(run_dir):
    """Columns of timeseries.csv as numpy arrays keyed by header name (units in the names)."""
    with open(os.path.join(run_dir, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]} if rows else {}


def snapshots(run_dir):
    return sorted(glob.glob(os.path.join(run_dir, "snapshots", "snapshot_*.h5")))


class CorruptSnapshot(ValueError):
    """A dataset whose values do not match the CRC-32 stored with them."""


def verified(dataset, path):
    """The dataset's values, checked against its "crc32" attribute (zlib CRC-32 of the values as
    stored, native byte order; docs/reliability.md). Snapshots that declare checksums (root
    attribute "checksums") must carry one on every dataset; older ones have none."""
    values = dataset[()]
    stored = dataset.attrs.get("crc32")
    if stored is None:
        if "checksums" in dataset.file.attrs:
            raise CorruptSnapshot(f"{path}: dataset '{dataset.name}' has no checksum")
        return values
    actual = zlib.crc32(values.tobytes())
    if actual != int(stored):
        raise CorruptSnapshot(f"{path}: dataset '{dataset.name}' is corrupt: checksum "
                              f"{actual:08x}, stored {int(stored):08x}")
    return values


def read_snapshot(path):
    """(time in s, dict column -> array, symmetry axis or -1). Raises CorruptSnapshot when a
    column does not match its checksum."""
    with h5py.File(path, "r") as f:
        cols = {k: verified(f["particles"][k], path) for k in f["particles"]}
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


# Voigt order of the stress columns and their places in the symmetric 3 x 3 tensor.
STRESS_COLUMNS = (((0, 0), "sxx"), ((1, 1), "syy"), ((2, 2), "szz"), ((0, 1), "sxy"),
                  ((1, 2), "syz"), ((0, 2), "sxz"))


def stress_tensors(cols, sel=slice(None)):
    """(n, 3, 3) stress tensors of the points `sel` (a mask, index array or slice) of a
    snapshot's columns (read_snapshot), or of an (n, 6) array in STRESS_COLUMNS order."""
    if isinstance(cols, np.ndarray):
        comps = [cols[sel, k] for k in range(6)]
    else:
        comps = [cols[name][sel] for _, name in STRESS_COLUMNS]
    s = np.zeros((len(comps[0]), 3, 3))
    for ((i, j), _), v in zip(STRESS_COLUMNS, comps):
        s[:, i, j] = v
        s[:, j, i] = v
    return s


def scene(run_dir):
    """The resolved scene a run wrote (RUN_DIR/scene.toml) as a dict, or None."""
    import tomllib
    path = os.path.join(run_dir, "scene.toml")
    if not os.path.exists(path):
        return None
    with open(path, "rb") as f:
        return tomllib.load(f)


def impact_geometry(first, axis, scene_dict=None):
    """Target and impact point of a projectile-on-target run, from its first snapshot's columns
    and symmetry axis (read_snapshot) and, when given, its resolved scene (scene()). The target
    is the heaviest body. With an [impact] section on a spherical target the impact point is the
    scene's own, C + R n with n at the impact angle from the reversed velocity
    (src/scene/impact.cpp). Otherwise the surface point of the lattice nearest the projectile's
    centre of mass. Returns (target body index, target centre, target radius, unit vector from
    the impact point towards the target centre, impact point)."""
    body = first["body"].astype(int)
    target = int(np.argmax(np.bincount(body, weights=first["mass"])))
    imp = (scene_dict or {}).get("impact")
    tb = (scene_dict or {}).get("body", {}).get(imp["target"], {}) if imp else {}
    if tb.get("shape") == "sphere":
        centre = np.array(tb["centre"], dtype=float)
        radius = float(tb["radius"])
        d = np.array(imp["direction"], dtype=float)
        d /= np.linalg.norm(d)
        o = np.array(imp["offset"], dtype=float)
        o -= (o @ d) * d
        o /= np.linalg.norm(o)
        a = np.radians(imp["angle"])
        inward = np.cos(a) * d - np.sin(a) * o
        return target, centre, radius, inward, centre - radius * inward
    pos0 = np.stack([first["x"], first["y"], first["z"]], 1)
    centre = pos0[body == target].mean(axis=0)
    if axis >= 0:
        centre[axis] = 0.0  # a half model's centre lies on the symmetry plane
    radius = np.max(np.linalg.norm(pos0[body == target] - centre, axis=1))
    proj = pos0[body != target].mean(axis=0)
    if axis >= 0:
        proj[axis] = centre[axis]
    inward = (centre - proj) / np.linalg.norm(centre - proj)
    return target, centre, radius, inward, centre - radius * inward
