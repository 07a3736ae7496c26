"""Read shatter's outputs into numpy arrays.

A run directory (written by `shatter run`) holds timeseries.csv, snapshots/snapshot_*.h5 with
particles.xmf beside them, fragments.csv/.h5/.ss and scene.toml. Every HDF5 dataset shatter writes
carries a CRC-32 (zlib) of its values in the attribute "crc32", and the root attributes a reader
uses (time, step, symmetry_axis, ...) are sealed by "attributes_crc32"; the readers here verify
both and raise CorruptSnapshot naming the file and the dataset or attribute when one differs or
cannot be read at all (docs/outputs.md).
"""

import csv
import glob
import os
import struct
import zlib

import h5py
import numpy as np

__all__ = [
    "CorruptSnapshot", "verified", "verified_attrs", "read_snapshot", "read_snapshot_time", "snapshot_names",
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
    """A dataset or header attribute whose values do not match the CRC-32 stored with them, or
    that cannot be read at all."""


# The root attributes a reader uses: a sealed snapshot must cover them.
_USED_ATTRS = ("format", "format_version", "time", "step", "program_version", "symmetry_axis")


def _attr_bytes(value):
    """An attribute's value as the seal covers it (src/io/h5.cpp, seal_attrs): numbers as their
    native bytes, strings without NUL padding."""
    if isinstance(value, (bytes, np.bytes_)):
        return bytes(value).rstrip(b"\0")
    if isinstance(value, str):
        return value.encode().rstrip(b"\0")
    return np.ascontiguousarray(value).tobytes()


def verified_attrs(obj, path):
    """The attributes of `obj` (a file or group) as a dict, checked against the seal
    "attributes_crc32": CRC-32 over, for "attributes_covered" and each name it lists, the name,
    a NUL, the value's byte length (uint64 little-endian) and the value. A snapshot that has a
    format_version must be sealed; older ones are returned unverified."""
    try:
        attrs = {k: obj.attrs[k] for k in obj.attrs}
    except (OSError, KeyError, ValueError) as e:
        raise CorruptSnapshot(f"{path}: cannot read the attributes of '{obj.name}': {e}") from e
    if "attributes_crc32" not in attrs or "attributes_covered" not in attrs:
        if "format_version" in attrs or "attributes_crc32" in attrs or "attributes_covered" in attrs:
            raise CorruptSnapshot(f"{path}: the attributes of '{obj.name}' have no checksum "
                                  "(attributes_crc32 missing): corrupt file")
        return attrs
    names = ["attributes_covered"] + _attr_bytes(attrs["attributes_covered"]).decode(
        errors="replace").split()
    for name in _USED_ATTRS if obj.name == "/" else ():
        if name not in names:
            raise CorruptSnapshot(f"{path}: attribute '{name}' of '{obj.name}' is not covered by "
                                  "the attribute checksum: corrupt file")
    data = b""
    for name in names:
        if name not in attrs:
            raise CorruptSnapshot(f"{path}: attribute '{name}' of '{obj.name}' is missing: "
                                  "corrupt file")
        value = _attr_bytes(attrs[name])
        data += name.encode() + b"\0" + struct.pack("<Q", len(value)) + value
    actual, stored = zlib.crc32(data), int(attrs["attributes_crc32"])
    if actual != stored:
        raise CorruptSnapshot(f"{path}: the attributes of '{obj.name}' are corrupt: checksum "
                              f"{actual:08x}, stored {stored:08x}")
    return attrs


def verified(dataset, path):
    """The dataset's values, checked against its "crc32" attribute (zlib CRC-32 of the values as
    stored: native byte order, binary64 or binary32, row-major). Files that declare checksums
    (root attribute "checksums") must carry one on every dataset; older ones have none. A
    dataset HDF5 cannot decode (a corrupted compressed chunk) raises CorruptSnapshot too."""
    try:
        values = dataset[()]
    except (OSError, ValueError) as e:
        raise CorruptSnapshot(f"{path}: dataset '{dataset.name}' cannot be read (corrupt "
                              f"file?): {e}") from e
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
    with _open(path) as f:
        attrs = verified_attrs(f, path)
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
        axis = int(attrs.get("symmetry_axis", 0)) - 1
        return float(attrs["time"]), cols, axis


def _open(path):
    """The snapshot open for reading; a file HDF5 cannot open raises CorruptSnapshot."""
    try:
        return h5py.File(path, "r")
    except OSError as e:
        if not os.path.exists(path):
            raise
        raise CorruptSnapshot(f"{path}: not a readable HDF5 file (truncated or corrupt?): "
                              f"{e}") from e


def snapshot_names(path):
    """(body names, material names) a snapshot stores (empty lists for older snapshots)."""
    with _open(path) as f:
        if "names" not in f:
            return [], []
        g = f["names"]
        return (_strings(verified(g["body"], path)), _strings(verified(g["material"], path)))


def symmetry_axis(run_dir):
    """The symmetry axis of a run's snapshots (0, 1, 2; -1 = full model or no snapshot)."""
    files = snapshots(run_dir)
    if not files:
        return -1
    with _open(files[0]) as f:
        return int(verified_attrs(f, files[0]).get("symmetry_axis", 0)) - 1


def model_label(axis):
    """How a figure should name what it shows: a half model's snapshots hold one half."""
    return "half model (symmetry plane {}=0)".format("xyz"[axis]) if axis >= 0 else "full model"


def snapshots(run_dir):
    return sorted(glob.glob(os.path.join(run_dir, "snapshots", "snapshot_*.h5")))


def read_snapshot_time(path):
    with _open(path) as f:
        return float(verified_attrs(f, path)["time"])


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
