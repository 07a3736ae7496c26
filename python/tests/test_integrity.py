"""shatterpy refuses corrupt snapshots with its own error naming file and dataset or attribute
(issue 33, items 2 and 8): a changed header attribute (time, symmetry_axis) against the root's
attributes_crc32, and a compressed chunk zlib cannot inflate."""

import shutil
import struct

import h5py
import numpy as np
import pytest

import shatterpy as sp


def copy_last(run_dir, tmp_path):
    bad = tmp_path / "bad.h5"
    shutil.copy(sp.snapshots(run_dir)[-1], bad)
    return bad


def test_sealed_header_reads(run_dir):
    path = sp.snapshots(run_dir)[-1]
    with h5py.File(path, "r") as f:
        attrs = sp.verified_attrs(f, path)
    assert int(attrs["format_version"]) == 2
    assert sp.read_snapshot_time(path) == pytest.approx(1.0e-6, rel=1e-12)


def test_flipped_byte_of_the_time_attribute_is_refused(run_dir, tmp_path):
    bad = copy_last(run_dir, tmp_path)
    with h5py.File(bad, "r") as f:
        t = float(f.attrs["time"])
    data = bytearray(bad.read_bytes())
    at = data.find(struct.pack("<d", t))
    assert at >= 0 and data.find(struct.pack("<d", t), at + 1) < 0
    data[at + 2] ^= 0x01  # one bit of the stored time, in the file itself
    bad.write_bytes(bytes(data))
    with pytest.raises(sp.CorruptSnapshot, match=r"attributes of '/' are corrupt"):
        sp.read_snapshot(bad)
    with pytest.raises(sp.CorruptSnapshot, match="bad.h5"):
        sp.read_snapshot_time(bad)


def test_changed_symmetry_axis_is_refused(run_dir, tmp_path):
    bad = copy_last(run_dir, tmp_path)
    with h5py.File(bad, "r+") as f:
        f.attrs.modify("symmetry_axis", np.uint64(0))  # "no symmetry plane": doubles the mass
    with pytest.raises(sp.CorruptSnapshot, match="corrupt"):
        sp.read_snapshot(bad)


def test_undecodable_chunk_raises_corrupt_snapshot_naming_file_and_dataset(run_dir, tmp_path):
    bad = copy_last(run_dir, tmp_path)
    with h5py.File(bad, "r") as f:
        info = f["particles/velocity"].id.get_chunk_info(0)
    data = bytearray(bad.read_bytes())
    for i in range(16):  # inside the deflate stream: inflate() fails
        data[info.byte_offset + info.size // 2 + i] ^= 0xFF
    bad.write_bytes(bytes(data))
    with pytest.raises(sp.CorruptSnapshot, match=r"bad\.h5: dataset '/particles/velocity'"):
        sp.read_snapshot(bad)


def test_older_snapshot_without_seal_reads(run_dir, tmp_path):
    bad = copy_last(run_dir, tmp_path)
    with h5py.File(bad, "r+") as f:
        for name in ("attributes_crc32", "attributes_covered", "format_version"):
            del f.attrs[name]
    t, cols, axis = sp.read_snapshot(bad)
    assert axis == 2 and cols["mass"].size > 0
