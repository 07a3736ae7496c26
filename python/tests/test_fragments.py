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


# --- pkdgrav hand-off at asteroid scale: a fully failed body, packing-safe radii, colours ---

import shutil
import struct
import subprocess
import zlib

import h5py

from conftest import run_tiny, shatter_binary

SS_PALETTE = {3, 4, 8, 9, 10, 12, 13, 14, 15}  # docs/outputs.md; ssdefs.h reserves 2, 5, 6, 7, 11


def read_ss_independently(path):
    """From the layout in pkdgrav's ssio.h alone (not shatterpy's reader): XDR big-endian, header
    {double time; int n_data; int pad}, records {double mass, radius, pos[3], vel[3], spin[3];
    int color, org_idx}, pkdgrav units (only ratios of lengths are used here)."""
    with open(path, "rb") as f:
        data = f.read()
    _, n, _ = struct.unpack(">dii", data[:16])
    assert len(data) == 16 + 96 * n
    records = [struct.unpack(">11dii", data[16 + 96 * k:16 + 96 * (k + 1)]) for k in range(n)]
    return n, records


def overlapping_pairs(records):
    pos = np.array([r[2:5] for r in records])
    rad = np.array([r[1] for r in records])
    n = 0
    for i in range(len(records) - 1):
        d = np.linalg.norm(pos[i + 1:] - pos[i], axis=1)
        n += int(np.count_nonzero(rad[i] + rad[i + 1:] > d))
    return n


def fully_failed_copy(snapshot, dest):
    """The snapshot with D = 1 at every point (what a km-scale impact leaves), its damage
    checksum updated so that the reader accepts it."""
    shutil.copy(snapshot, dest)
    with h5py.File(dest, "r+") as f:
        d = f["particles/damage"]
        ones = np.ones(d.shape, dtype=d.dtype)
        d[...] = ones
        d.attrs.modify("crc32", np.array(zlib.crc32(ones.tobytes()), dtype=d.attrs["crc32"].dtype))
    return dest


def test_fully_failed_body_hands_every_point_to_pkdgrav(run_dir, tmp_path):
    snap = fully_failed_copy(sp.snapshots(run_dir)[-1], tmp_path / "failed.h5")
    r = subprocess.run([shatter_binary(), "fragments", str(snap), "--prefix",
                        str(tmp_path / "frag")], capture_output=True, text=True, check=True)
    assert "no fragment survives" in r.stdout + r.stderr, r.stdout + r.stderr
    n, records = read_ss_independently(tmp_path / "frag.ss")
    # Every point of the mirrored body, as the per-point file of the same snapshot holds them.
    n_points, _ = read_ss_independently(run_dir / "again_particles.ss")
    assert n == n_points > 0
    assert {r[11] for r in records} == {1}  # all dust
    assert [r[12] for r in records] == list(range(n))


def test_packing_safe_radius_removes_the_overlaps_of_a_real_run(run_dir, tmp_path):
    # The same tiny run with output.ss_radius = "packing_safe".
    safe = run_tiny(tmp_path / "safe", 'output.ss_radius="packing_safe"')
    n_eq, eq = read_ss_independently(run_dir / "fragments.ss")
    n_safe, packed = read_ss_independently(safe / "fragments.ss")
    assert n_eq == n_safe
    assert overlapping_pairs(packed) == 0
    # Same masses and centres; radii only shrink.
    for a, b in zip(eq, packed):
        assert a[0] == b[0] and a[2:5] == b[2:5]
        assert b[1] <= a[1]
    # The per-point file at equal volume: lattice neighbours overlap (r = 0.62 spacing).
    _, points = read_ss_independently(run_dir / "again_particles.ss")
    assert overlapping_pairs(points) > 0


def test_ss_colours_stay_in_the_documented_palette(run_dir):
    for name in ("fragments.ss", "again.ss", "again_particles.ss"):
        _, records = read_ss_independently(run_dir / name)
        assert {r[11] for r in records} <= SS_PALETTE | {1}, name


def test_fragments_prefix_in_a_missing_folder_creates_it(run_dir, tmp_path):
    prefix = tmp_path / "post" / "deeper" / "frag"
    r = subprocess.run([shatter_binary(), "fragments", str(sp.snapshots(run_dir)[-1]),
                        "--prefix", str(prefix)], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    assert f"created the folder {prefix.parent}" in r.stdout + r.stderr
    for ext in (".csv", ".h5", ".ss"):
        assert (prefix.parent / ("frag" + ext)).stat().st_size > 0
    # A prefix under a plain file: refused, naming the folder that cannot be made.
    (tmp_path / "plain").write_text("x")
    r = subprocess.run([shatter_binary(), "fragments", str(sp.snapshots(run_dir)[-1]),
                        "--prefix", str(tmp_path / "plain" / "frag")], capture_output=True,
                       text=True)
    assert r.returncode == 2
    assert "cannot create the folder" in r.stdout + r.stderr
