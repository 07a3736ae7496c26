"""Read shatter's outputs into numpy arrays.

A run directory (written by `shatter run`) holds timeseries.csv, snapshots/snapshot_*.h5 with
particles.xmf beside them, fragments.csv/.h5/.ss and scene.toml. Every HDF5 dataset shatter writes
carries a CRC-32 (zlib) of its values in the attribute "crc32"; the readers here verify it and
raise CorruptSnapshot naming the file and dataset when it differs (docs/outputs.md).
"""

import csv
import glob
import os
import struct
import zlib

import h5py
import numpy as np

__all__ = [
    "CorruptSnapshot", "verified", "read_snapshot", "read_snapshot_time", "snapshot_names",
    "snapshots", "snapshot_at", "timeseries", "fragments", "fragment_table", "read_ss",
    "PKDGRAV_UNITS", "stress_tensors", "STRESS_COLUMNS", "BUNDLES", "label_of", "scene",
    "impact_geometry", "model_label", "symmetry_axis", "snapshot_names",
]

# 2-d snapshot datasets and the columns they bundle (src/io/particles_h5.cpp): positions and
# velocities N x 3, the stress N x 6 in XDMF's Tensor6 order.
BUNDLES = {
    "position": ("x", "y", "z"),
    "velocity": ("vx", "vy", "vz"),
    "stress": ("sxx", "sxy", "sxz", "syy", "syz", "szz"),
}


class CorruptSnapshot(ValueError):
    """A dataset whose values do not match the CRC-32 stored with them."""


def verified(dataset, path):
    """The dataset's values, checked against its "crc32" attribute (zlib CRC-32 of the values as
    stored: native byte order, binary64 or binary32, row-major). Files that declare checksums
    (root attribute "checksums") must carry one on every dataset; older ones have none."""
    values = dataset[()]
    stored = dataset.attrs.get("crc32")
    if stored is None:
        if "checksums" in dataset.file.attrs:
            raise CorruptSnapshot(f"{path}: dataset '{dataset.name}' has no checksum")
        return values
    actual = zlib.crc32(np.ascontiguousarray(values).tobytes())
    if actual != int(stored):
        raise CorruptSnapshot(f"{path}: dataset '{dataset.name}' is corrupt: checksum "
                              f"{actual:08x}, stored {int(stored):08x}")
    return values


def _strings(values):
    return [v.decode() if isinstance(v, bytes) else str(v) for v in np.atleast_1d(values)]


def read_snapshot(path, bundles=False):
    """(time in s, dict column -> array, symmetry axis or -1) of a snapshot. Bundled datasets
    (position, velocity, stress) are split into their columns (x, y, z, vx, ..., sxx, ...) as
    float64; with bundles=True the 2-d arrays are kept as well under their own names. Raises
    CorruptSnapshot when a dataset does not match its checksum."""
    with h5py.File(path, "r") as f:
        cols = {}
        for k in f["particles"]:
            values = verified(f["particles"][k], path)
            if k in BUNDLES and values.ndim == 2:
                for c, name in enumerate(BUNDLES[k]):
                    cols[name] = values[:, c].astype(np.float64)
                if bundles:
                    cols[k] = values
            else:
                cols[k] = values.astype(np.float64) if values.dtype.kind == "f" else values
        axis = int(f.attrs.get("symmetry_axis", 0)) - 1
        return float(f.attrs["time"]), cols, axis


def snapshot_names(path):
    """(body names, material names) a snapshot stores (empty lists for older snapshots)."""
    with h5py.File(path, "r") as f:
        if "names" not in f:
            return [], []
        g = f["names"]
        return (_strings(verified(g["body"], path)), _strings(verified(g["material"], path)))


def symmetry_axis(run_dir):
    """The symmetry axis of a run's snapshots (0, 1, 2; -1 = full model or no snapshot)."""
    files = snapshots(run_dir)
    if not files:
        return -1
    with h5py.File(files[0], "r") as f:
        return int(f.attrs.get("symmetry_axis", 0)) - 1


def model_label(axis):
    """How a figure should name what it shows: a half model's snapshots hold one half."""
    return "half model (symmetry plane {}=0)".format("xyz"[axis]) if axis >= 0 else "full model"


def snapshots(run_dir):
    return sorted(glob.glob(os.path.join(run_dir, "snapshots", "snapshot_*.h5")))


def read_snapshot_time(path):
    with h5py.File(path, "r") as f:
        return float(f.attrs["time"])


def snapshot_at(run_dir, t):
    """The snapshot closest in time to t (s)."""
    files = snapshots(run_dir)
    times = [read_snapshot_time(p) for p in files]
    return files[int(np.argmin([abs(x - t) for x in times]))]


def timeseries(run_dir):
    """Columns of RUN_DIR/timeseries.csv as numpy arrays keyed by header name (units in the
    names)."""
    with open(os.path.join(run_dir, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]} if rows else {}


def fragment_table(path):
    """A fragments.csv as (dict column -> array, header dict with total_mass_kg, dust_mass_kg,
    fragments). Columns carry their units in their names (mass_kg, vx_m/s, ...; composition
    mass_body_NAME_kg and mass_material_NAME_kg when known)."""
    with open(path) as f:
        first = f.readline()
        meta = dict(kv.split("=") for kv in first.lstrip("# ").split())
        rows = list(csv.DictReader(f))
    names = rows[0].keys() if rows else []
    cols = {k: np.array([float(r[k]) for r in rows]) for k in names}
    return cols, {k: float(v) for k, v in meta.items()}


def fragments(path):
    """(masses in kg, speeds in m/s, total mass in kg) of a fragments.csv."""
    cols, meta = fragment_table(path)
    if not cols:
        return np.zeros(0), np.zeros(0), meta["total_mass_kg"]
    speed = np.sqrt(cols["vx_m/s"] ** 2 + cols["vy_m/s"] ** 2 + cols["vz_m/s"] ** 2)
    return cols["mass_kg"], speed, meta["total_mass_kg"]


# pkdgrav's units (G = 1): length 1 AU, mass GM_sun / G, time sqrt(AU^3 / GM_sun) = 1 yr / 2 pi
# (src/fracture/fragment_output.cpp).
_AU = 1.495978707e11
_GM_SUN = 1.32712440018e20
_G = 6.67430e-11
PKDGRAV_UNITS = {"length_m": _AU, "mass_kg": _GM_SUN / _G, "time_s": (_AU ** 3 / _GM_SUN) ** 0.5}


def read_ss(path, si=True):
    """A pkdgrav .ss file (XDR big-endian: header time, n_data, pad; 96-byte records) as (time,
    dict of arrays mass, radius, pos (n x 3), vel, spin, color, org_idx). SI units unless
    si=False (pkdgrav units)."""
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < 16:
        raise ValueError(f"{path}: {len(data)} bytes, shorter than an ss header")
    time, n, _ = struct.unpack(">dii", data[:16])
    if n < 0 or len(data) != 16 + 96 * n:
        raise ValueError(f"{path}: header says {n} records, file has {len(data)} bytes")
    rec = np.dtype([("mass", ">f8"), ("radius", ">f8"), ("pos", ">f8", 3), ("vel", ">f8", 3),
                    ("spin", ">f8", 3), ("color", ">i4"), ("org_idx", ">i4")])
    r = np.frombuffer(data, dtype=rec, offset=16, count=n)
    out = {k: r[k].astype(np.float64 if r[k].dtype.kind == "f" else np.int64) for k in rec.names}
    if si:
        u = PKDGRAV_UNITS
        time *= u["time_s"]
        out["mass"] *= u["mass_kg"]
        out["radius"] *= u["length_m"]
        out["pos"] *= u["length_m"]
        out["vel"] *= u["length_m"] / u["time_s"]
        out["spin"] /= u["time_s"]
    return time, out


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
