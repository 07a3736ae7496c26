"""shatterpy's snapshot and time-series readers on files the C++ writer made."""

import shutil

import h5py
import numpy as np
import pytest

import shatterpy as sp


def test_bundled_datasets_are_split_into_columns(run_dir):
    path = sp.snapshots(run_dir)[-1]
    t, c, axis = sp.read_snapshot(path, bundles=True)
    assert t == pytest.approx(1.0e-6, rel=1e-12)  # tiny.toml's end_time
    assert axis == 2  # symmetry_plane = "z"
    n = c["mass"].size
    assert c["position"].shape == (n, 3) and c["velocity"].shape == (n, 3)
    assert c["stress"].shape == (n, 6)
    # Tensor6 order xx, xy, xz, yy, yz, zz (exact: the same stored values).
    np.testing.assert_array_equal(c["stress"][:, 1], c["sxy"])
    np.testing.assert_array_equal(c["stress"][:, 3], c["syy"])
    np.testing.assert_array_equal(c["position"][:, 2], c["z"])
    assert (c["z"] >= 0).all()  # the half model keeps z >= 0


def test_snapshot_names_bodies_and_materials(run_dir):
    bodies, materials = sp.snapshot_names(sp.snapshots(run_dir)[0])
    # Bodies in the scene's table order (TOML tables are sorted by name); group g = body g.
    assert bodies == ["projectile", "target"]
    assert materials == ["nylon", "basalt"]


def test_snapshots_are_shuffled_and_deflated(run_dir):
    with h5py.File(sp.snapshots(run_dir)[0], "r") as f:
        d = f["particles/position"]
        assert d.compression == "gzip" and d.shuffle
        assert d.dtype == np.float64
        assert f.attrs["precision"] in (b"binary64", "binary64")


def test_single_precision_snapshots_verify_and_read_as_float64(single_run_dir, run_dir):
    path = sp.snapshots(single_run_dir)[-1]
    with h5py.File(path, "r") as f:
        assert f["particles/velocity"].dtype == np.float32
        assert f["particles/id"].dtype == np.int64  # integers stay exact
    _, c32, _ = sp.read_snapshot(path)
    _, c64, _ = sp.read_snapshot(sp.snapshots(run_dir)[-1])
    assert c32["x"].dtype == np.float64
    # Same run, same thread count: identical state, rounded to binary32 (relative 2^-24).
    np.testing.assert_allclose(c32["x"], c64["x"], rtol=2.0 ** -24, atol=0)
    np.testing.assert_array_equal(c32["id"], c64["id"])
    with open(single_run_dir / "particles.xmf") as f:
        assert 'Precision="4"' in f.read()


def test_a_changed_value_is_refused_by_its_checksum(run_dir, tmp_path):
    bad = tmp_path / "bad.h5"
    shutil.copy(sp.snapshots(run_dir)[-1], bad)
    with h5py.File(bad, "r+") as f:
        d = f["particles/velocity"]
        v = d[()]
        v[0, 0] += 1.0
        d[...] = v  # the stored crc32 attribute now disagrees
    with pytest.raises(sp.CorruptSnapshot, match="velocity"):
        sp.read_snapshot(bad)


def test_timeseries_has_energies_with_units(run_dir):
    ts = sp.timeseries(run_dir)
    for k in ("time_s", "kinetic_J", "internal_J", "outflow_J", "energy_error"):
        assert k in ts
    assert np.all(np.diff(ts["time_s"]) > 0)
    assert ts["kinetic_J"][0] > 0  # the projectile moves at 3.2 km/s
