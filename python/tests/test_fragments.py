"""Fragment tables with composition, and pkdgrav's ss files, as written by `shatter`."""

import numpy as np
import pytest

import shatterpy as sp


def test_composition_columns_add_up_to_each_fragment_mass(run_dir):
    cols, meta = sp.fragment_table(run_dir / "fragments.csv")
    by_body = cols["mass_body_target_kg"] + cols["mass_body_projectile_kg"]
    by_material = cols["mass_material_basalt_kg"] + cols["mass_material_nylon_kg"]
    # Sums of the same particle masses in another order: a few ulps (1e-12 relative).
    np.testing.assert_allclose(by_body, cols["mass_kg"], rtol=1e-12)
    np.testing.assert_allclose(by_material, cols["mass_kg"], rtol=1e-12)
    assert meta["fragments"] == cols["mass_kg"].size


def test_fragments_ss_holds_one_record_per_fragment_in_si(run_dir):
    cols, _ = sp.fragment_table(run_dir / "fragments.csv")
    t, ss = sp.read_ss(run_dir / "fragments.ss")
    assert t == pytest.approx(1.0e-6, rel=1e-14)
    assert ss["mass"].size == cols["mass_kg"].size
    # Unit conversion there and back: a few roundings, 1e-14 relative.
    np.testing.assert_allclose(ss["mass"], cols["mass_kg"], rtol=1e-14)
    np.testing.assert_allclose(ss["vel"][:, 0], cols["vx_m/s"], rtol=1e-14, atol=1e-12)
    np.testing.assert_array_equal(ss["org_idx"], np.arange(ss["mass"].size))
    # Colour 3 = mostly body 0 (the projectile: bodies are sorted by name), 4 = mostly body 1.
    bodies, _ = sp.snapshot_names(sp.snapshots(run_dir)[0])
    assert bodies == ["projectile", "target"]
    mostly_target = cols["mass_body_target_kg"] > cols["mass_body_projectile_kg"]
    np.testing.assert_array_equal(ss["color"], np.where(mostly_target, 4, 3))


def test_particle_ss_holds_every_point_of_the_mirrored_body(run_dir):
    _, c, _ = sp.read_snapshot(sp.snapshots(run_dir)[-1])
    _, ss = sp.read_ss(run_dir / "again_particles.ss")
    assert ss["mass"].size == 2 * c["mass"].size  # half model mirrored
    np.testing.assert_allclose(ss["mass"].sum(), 2 * c["mass"].sum(), rtol=1e-12)
    assert set(np.unique(ss["color"])) <= {1} | set(range(3, 1000))


def test_pkdgrav_units_make_g_one():
    u = sp.PKDGRAV_UNITS
    g = 6.67430e-11 * u["mass_kg"] * u["time_s"] ** 2 / u["length_m"] ** 3
    assert g == pytest.approx(1.0, rel=1e-14)
    # The time unit is a year / 2 pi (Julian year, 5.0226e6 s to 5 digits).
    assert u["time_s"] == pytest.approx(365.25 * 86400 / (2 * np.pi), rel=1e-4)


def test_snapshots_of_the_older_layout_still_work(run_dir, tmp_path):
    """A snapshot as written before the bundled layout (x, y, z, vx, ... and the stress as 1-d
    datasets, no names) is still read by `shatter fragments` and by shatterpy."""
    import subprocess
    import zlib

    import h5py

    from conftest import shatter_binary

    old = tmp_path / "old.h5"
    src = sp.snapshots(run_dir)[-1]
    with h5py.File(src, "r") as f, h5py.File(old, "w") as g:
        for k, v in f.attrs.items():
            g.attrs[k] = v
        f.copy("groups", g)
        p = g.create_group("particles")
        p.attrs["count"] = f["particles"].attrs["count"]
        for name, d in f["particles"].items():
            values = d[()]
            columns = sp.BUNDLES.get(name, (name,))
            for c, col in enumerate(columns):
                v = np.ascontiguousarray(values[:, c] if values.ndim == 2 else values)
                out = p.create_dataset(col, data=v)
                out.attrs["units"] = d.attrs["units"]
                out.attrs["crc32"] = np.uint64(zlib.crc32(v.tobytes()))
    _, new_cols, _ = sp.read_snapshot(src)
    _, old_cols, _ = sp.read_snapshot(old)
    assert set(old_cols) == set(new_cols)
    np.testing.assert_array_equal(old_cols["sxy"], new_cols["sxy"])
    subprocess.run([shatter_binary(), "fragments", str(old), "--prefix", str(tmp_path / "old"),
                    "--quiet"], check=True)
    cols, _ = sp.fragment_table(tmp_path / "old.csv")
    ref, _ = sp.fragment_table(run_dir / "fragments.csv")
    np.testing.assert_array_equal(cols["mass_kg"], ref["mass_kg"])  # same points, same search
    assert not any(k.startswith("mass_body_") for k in cols)  # no names, no composition
