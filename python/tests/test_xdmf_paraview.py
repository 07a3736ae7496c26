"""particles.xmf opened by ParaView's default reader for .xmf files (Xdmf3ReaderS, ParaView 5.11
from Debian's python3-paraview, tools/setup.sh), as a user opening it in the GUI would: every time
step, the points, and the arrays with their components, compared with the snapshots."""

import os

import numpy as np

import shatterpy as sp

# Deliberately no skip: without python3-paraview this test fails (tools/setup.sh installs it).
from paraview import servermanager, simple
from vtkmodules.numpy_interface import dataset_adapter as dsa


def fetch(reader, t):
    reader.UpdatePipeline(t)
    data = servermanager.Fetch(reader)
    if data.IsA("vtkMultiBlockDataSet"):
        data = data.GetBlock(0)
    return dsa.WrapDataObject(data)


def test_default_reader_shows_points_vectors_tensor_and_times(run_dir):
    # The GUI passes an absolute path (Xdmf3 joins a bare relative name wrongly).
    reader = simple.OpenDataFile(os.path.abspath(run_dir / "particles.xmf"))
    assert reader.GetXMLName() == "Xdmf3ReaderS", reader.GetXMLName()
    files = sp.snapshots(run_dir)
    times = [sp.read_snapshot_time(p) for p in files]
    # Times as written (%g-style shortest text of the double): exact to 1e-15 relative.
    np.testing.assert_allclose(reader.TimestepValues, times, rtol=1e-15)
    for path, t in zip(files, times):
        _, c, _ = sp.read_snapshot(path)
        d = fetch(reader, t)
        assert d.GetNumberOfPoints() == c["x"].size
        # One vertex cell per particle (explicit connectivity 0..N-1): without cells the default
        # Surface and the Points representations draw nothing.
        assert d.GetNumberOfCells() == c["x"].size
        assert d.GetCellType(0) == 2  # VTK_POLY_VERTEX
        conn = d.VTKObject.GetCells().GetConnectivityArray()
        assert conn.GetNumberOfTuples() == c["x"].size
        np.testing.assert_array_equal(
            [conn.GetValue(k) for k in range(conn.GetNumberOfTuples())], np.arange(c["x"].size))
        # Same binary64 values through HDF5 and VTK: exact.
        np.testing.assert_array_equal(np.asarray(d.Points),
                                      np.stack([c["x"], c["y"], c["z"]], 1))
        pd = d.PointData
        np.testing.assert_array_equal(np.asarray(pd["velocity"]),
                                      np.stack([c["vx"], c["vy"], c["vz"]], 1))
        stress = np.asarray(pd["stress"])
        assert stress.shape == (c["x"].size, 6)
        np.testing.assert_array_equal(
            stress, np.stack([c[k] for k in ("sxx", "sxy", "sxz", "syy", "syz", "szz")], 1))
        np.testing.assert_array_equal(np.asarray(pd["damage"]), c["damage"])
        np.testing.assert_array_equal(np.asarray(pd["id"]), c["id"])
        for name in ("mass", "rho", "pressure", "body"):
            assert name in pd.keys(), name


def test_meshio_time_series_reader_reads_cells_and_every_step(run_dir):
    # Debian's python3-meshio (tools/setup.sh --tests); its reader takes an Attribute's only
    # child as its data, so the units live beside the attributes.
    import meshio
    files = sp.snapshots(run_dir)
    with meshio.xdmf.TimeSeriesReader(str(run_dir / "particles.xmf")) as reader:
        points, cells = reader.read_points_cells()
        _, c0, _ = sp.read_snapshot(files[0])
        n = c0["x"].size
        assert points.shape == (n, 3)
        assert [b.type for b in cells] == ["vertex"]
        np.testing.assert_array_equal(cells[0].data.ravel(), np.arange(n))
        assert reader.num_steps == len(files)
        for k, path in enumerate(files):
            t, point_data, _ = reader.read_data(k)
            assert t == sp.read_snapshot_time(path)
            _, c, _ = sp.read_snapshot(path)
            np.testing.assert_array_equal(point_data["damage"], c["damage"])
