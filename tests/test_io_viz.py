"""VTU/PVD output and figures: round trips, node order, off-screen rendering."""
import ctypes.util
import os
from pathlib import Path
import sys
import xml.etree.ElementTree as ET

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from skfem import Basis, MeshTri  # noqa: E402

from pfem_skfem.discretisation.elements import displacement_element  # noqa: E402
from pfem_skfem.io import (TimeSeries, mesh_arrays, per_element, write_pvd,  # noqa: E402
                           write_vtu)
from pfem_skfem.viz import plot_field, plot_mesh, render_png  # noqa: E402

HAVE_EGL = ctypes.util.find_library("EGL") is not None


@pytest.fixture
def mesh():
    return MeshTri.init_tensor(np.linspace(0, 2, 5), np.linspace(0, 1, 4))


def test_p2_nodes_are_edge_midpoints_in_vtk_and_skfem_order(mesh):
    points, cells = mesh_arrays(mesh, order=2)
    assert cells.shape == (mesh.nelements, 6)
    corner = points[cells[:, :3]]
    # VTK quadratic triangle: midside nodes of edges 01, 12, 20
    for k, (i, j) in enumerate([(0, 1), (1, 2), (2, 0)]):
        np.testing.assert_allclose(points[cells[:, 3 + k]], 0.5 * (corner[:, i] + corner[:, j]))
    # scikit-fem's P2 vector dofs are node-major in the same node order, so a
    # displacement vector reshaped to (n, 2) is a point field of this mesh
    basis = Basis(mesh, displacement_element())
    np.testing.assert_allclose(basis.doflocs[:, 0::2].T, points)
    np.testing.assert_allclose(basis.doflocs[:, 1::2].T, points)
    np.testing.assert_array_equal(basis.element_dofs[0::2].T // 2, cells)


@pytest.mark.parametrize("order", [1, 2])
def test_vtu_round_trip(tmp_path, mesh, order):
    import pyvista as pv

    points, cells = mesh_arrays(mesh, order=order)
    rng = np.random.default_rng(0)
    u = rng.normal(size=(len(points), 2))
    pressure = rng.normal(size=len(points))
    stress = rng.normal(size=(len(cells), 4))
    path = write_vtu(tmp_path / "sub" / "mesh.vtu", points, cells,
                     point_data={"u": u, "p": pressure}, cell_data={"stress": stress})
    grid = pv.read(path)
    np.testing.assert_array_equal(grid.points[:, :2], points)
    np.testing.assert_array_equal(grid.points[:, 2], 0.0)
    cell_type = pv.CellType.TRIANGLE if order == 1 else pv.CellType.QUADRATIC_TRIANGLE
    np.testing.assert_array_equal(grid.cells_dict[cell_type], cells)
    np.testing.assert_array_equal(grid.point_data["u"][:, :2], u)
    np.testing.assert_array_equal(grid.point_data["u"][:, 2], 0.0)   # padded to a 3-vector
    np.testing.assert_array_equal(grid.point_data["p"], pressure)
    np.testing.assert_array_equal(grid.cell_data["stress"], stress)


def test_per_element_averages_points_of_each_element():
    owner = np.array([0, 0, 1, 1, 1, 2])
    values = np.array([[1.0, 10.0], [3.0, 30.0], [2.0, 0.0], [4.0, 0.0], [6.0, 3.0], [5.0, 5.0]])
    np.testing.assert_allclose(per_element(values, owner, 3),
                               [[2.0, 20.0], [4.0, 1.0], [5.0, 5.0]])
    np.testing.assert_allclose(per_element(values[:, 0], owner, 3), [2.0, 4.0, 5.0])


def test_time_series_pvd_lists_its_files(tmp_path, mesh):
    import pyvista as pv

    points, cells = mesh_arrays(mesh)
    series = TimeSeries(tmp_path / "run", "box")
    times = [0.0, 0.1, 0.25]
    for k, t in enumerate(times):
        series.write(t, points + k, cells, point_data={"t": np.full(len(points), t)})
    root = ET.parse(series.pvd_path).getroot()
    assert root.get("type") == "Collection"
    datasets = root.find("Collection").findall("DataSet")
    assert [float(d.get("timestep")) for d in datasets] == times
    assert [d.get("file") for d in datasets] == ["box_0000.vtu", "box_0001.vtu", "box_0002.vtu"]
    for k, d in enumerate(datasets):
        grid = pv.read(series.pvd_path.parent / d.get("file"))
        np.testing.assert_array_equal(grid.points[:, :2], points + k)
        np.testing.assert_array_equal(grid.point_data["t"], times[k])


def test_a_resumed_time_series_goes_on_after_the_checkpoint_s_steps(tmp_path, mesh):
    """resume(t): the steps at times <= t stay, the later ones (written after the
    checkpoint) are deleted, and the next step is numbered after the kept ones."""
    points, cells = mesh_arrays(mesh)
    first = TimeSeries(tmp_path, "box")
    for t in (0.0, 0.1, 0.2, 0.3):
        first.write(t, points, cells)
    series = TimeSeries(tmp_path, "box").resume(0.1)
    assert [t for t, _ in series.entries] == [0.0, 0.1]
    assert sorted(f.name for f in tmp_path.glob("*.vtu")) == ["box_0000.vtu", "box_0001.vtu"]
    assert series.write(0.2, points + 1, cells).name == "box_0002.vtu"
    datasets = ET.parse(series.pvd_path).getroot().find("Collection").findall("DataSet")
    assert [float(d.get("timestep")) for d in datasets] == [0.0, 0.1, 0.2]
    assert TimeSeries(tmp_path / "none", "box").resume(1.0).entries == []


def test_pvd_stores_paths_relative_to_itself(tmp_path):
    (tmp_path / "steps").mkdir()
    path = write_pvd(tmp_path / "out" / "c.pvd", [(1.5, tmp_path / "steps" / "a.vtu")])
    (d,) = ET.parse(path).getroot().iter("DataSet")
    assert d.get("file") == "../steps/a.vtu"
    assert float(d.get("timestep")) == 1.5


def test_a_stop_while_the_pvd_is_written_leaves_the_previous_collection(tmp_path,
                                                                      monkeypatch):
    # the PVD is rewritten after every frame; a SIGTERM inside that write (met in CI)
    # left an empty file that no run could resume from
    path = write_pvd(tmp_path / "c.pvd", [(0.0, tmp_path / "a.vtu")])
    before = path.read_bytes()

    def cut(fd):                                      # the new file written, not yet
        raise KeyboardInterrupt                       # renamed: the stop
    monkeypatch.setattr(os, "fsync", cut)
    with pytest.raises(KeyboardInterrupt):
        write_pvd(path, [(0.0, tmp_path / "a.vtu"), (0.1, tmp_path / "b.vtu")])
    assert path.read_bytes() == before
    assert [f.name for f in tmp_path.iterdir()] == ["c.pvd"]          # no temporary left


@pytest.mark.parametrize("kwargs, word", [
    ({"cells": np.array([[0, 1, 99]])}, "cells"),
    ({"cells": np.array([[0.0, 1.0, 2.0]])}, "cells"),
    ({"point_data": {"u": np.zeros(2)}}, "point_data"),
    ({"cell_data": {"s": np.zeros((5, 4))}}, "cell_data"),
    ({"points": np.zeros((3, 4))}, "points"),
])
def test_write_vtu_rejects_bad_input(tmp_path, kwargs, word):
    args = {"points": np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
            "cells": np.array([[0, 1, 2]])}
    args.update(kwargs)
    with pytest.raises(ValueError, match=word):
        write_vtu(tmp_path / "bad.vtu", **args)


def test_plot_field_per_element_and_per_point(mesh):
    points, cells = mesh_arrays(mesh, order=2)
    fig, (a, b, c) = plt.subplots(1, 3)
    plot_mesh(a, points, cells)
    by_element = plot_field(b, points, cells, np.arange(len(cells), dtype=float))
    by_point = plot_field(c, points, cells, points[:, 0])
    assert len(by_element.get_array()) == len(cells)
    assert by_point.get_clim() == (0.0, 2.0)
    with pytest.raises(ValueError, match="values"):
        plot_field(c, points, cells, np.zeros(7))
    plt.close(fig)


def test_render_png_reports_failure_instead_of_raising(tmp_path):
    with pytest.warns(RuntimeWarning, match="failed"):
        ok = render_png(tmp_path / "missing.vtu", tmp_path / "x.png", "u")
    assert ok is False
    assert not (tmp_path / "x.png").exists()


def test_render_png_survives_a_crashing_renderer(tmp_path, monkeypatch):
    # what pyvista does without libEGL: the renderer process dies of SIGSEGV
    crash = tmp_path / "crash.sh"
    crash.write_text("#!/bin/sh\nkill -SEGV $$\n")
    crash.chmod(0o755)
    monkeypatch.setattr(sys, "executable", str(crash))
    with pytest.warns(RuntimeWarning, match="signal 11"):
        assert render_png(tmp_path / "m.vtu", tmp_path / "m.png", "x") is False


@pytest.mark.skipif(not HAVE_EGL, reason="no libEGL: install Debian libegl1 libgl1-mesa-dri")
def test_render_png_draws_the_field(tmp_path, mesh):
    points, cells = mesh_arrays(mesh, order=2)
    vtu = write_vtu(tmp_path / "m.vtu", points, cells, point_data={"x": points[:, 0]})
    png = tmp_path / "m.png"
    assert render_png(vtu, png, "x", window_size=(400, 300), show_edges=False)
    image = plt.imread(png)
    assert image.shape[:2] == (300, 400)
    # the field x runs from the first to the last colour of the map across the mesh
    row = image[150, :, :3]
    colours = {tuple(np.round(px, 2)) for px in row}
    assert len(colours) > 20
    viridis = matplotlib.colormaps["viridis"]
    lo, hi = np.array(viridis(0.0)[:3]), np.array(viridis(1.0)[:3])
    assert np.min(np.linalg.norm(row - lo, axis=1)) < 0.1
    assert np.min(np.linalg.norm(row - hi, axis=1)) < 0.1
    left = np.argmin(np.linalg.norm(row - lo, axis=1))
    right = np.argmin(np.linalg.norm(row - hi, axis=1))
    assert left < right


# -- what a ParaView user reads (issue 36, item 8) -----------------------------------------
def test_a_run_s_vtu_names_each_stress_component_states_units_and_starts_at_t_0(tmp_path):
    import pyvista as pv
    from pfem_skfem import cli
    from pfem_skfem.scene.files import example_text
    scene = tmp_path / "column.toml"
    scene.write_text(example_text("column"))
    assert cli.main(["run", str(scene), "--out", str(tmp_path / "o"), "--steps", "1",
                     "--quiet"]) == 0
    pvd = (tmp_path / "o" / "scene.pvd").read_text()
    assert "units:" in pvd and "Pa" in pvd and "m/s" in pvd
    datasets = ET.parse(tmp_path / "o" / "scene.pvd").getroot().iter("DataSet")
    assert [float(d.get("timestep")) for d in datasets][0] == 0.0
    for frame in ("scene_0000.vtu", "scene_0001.vtu"):     # t = 0, step 1
        grid = pv.read(tmp_path / "o" / frame)
        stress = grid.cell_data["stress"]
        for k, name in enumerate(("sxx", "syy", "sxy")):
            np.testing.assert_array_equal(grid.cell_data[name], stress[:, k])
        assert {"velocity", "speed", "mean_stress", "pressure"} <= set(grid.point_data.keys())
    grid = pv.read(tmp_path / "o" / "scene_0000.vtu")
    assert np.all(grid.point_data["speed"] == 0) and grid.n_cells > 0


def test_the_initial_frame_of_an_axisymmetric_state_has_the_hoop_stress():
    from pfem_skfem.io import initial_fields
    from pfem_skfem.pfem.state import initial_state
    x = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    stress = np.tile([-1.0, -2.0, -3.0, 0.5], (4, 1))
    state = initial_state(x, np.ones(4), stress=stress)
    points, cells, pd, cd = initial_fields(state, 1.6, axisymmetric=True)
    assert len(cells) == 2
    np.testing.assert_array_equal(cd["stt"], -3.0)
    np.testing.assert_array_equal(cd["hoop_stress"], -3.0)
    np.testing.assert_array_equal(cd["sxy"], 0.5)
    assert "stt" not in initial_fields(state, 1.6)[3]


def test_a_series_without_its_pvd_refuses_to_resume_and_deletes_nothing(tmp_path, mesh):
    points, cells = mesh_arrays(mesh)
    series = TimeSeries(tmp_path, "box")
    for t in (0.0, 0.1):
        series.write(t, points, cells)
    series.pvd_path.unlink()
    with pytest.raises(ValueError, match="box.pvd is missing"):
        TimeSeries(tmp_path, "box").resume(0.1)
    assert len(list(tmp_path.glob("box_*.vtu"))) == 2
    series.pvd_path.write_text("<VTKFile")
    with pytest.raises(ValueError, match="damaged"):
        TimeSeries(tmp_path, "box").resume(0.1)
    assert len(list(tmp_path.glob("box_*.vtu"))) == 2


def test_a_nearly_full_disk_stops_a_series_before_vtk_s_writer(tmp_path, mesh, monkeypatch):
    import errno
    import shutil
    points, cells = mesh_arrays(mesh)
    series = TimeSeries(tmp_path, "box")
    series.write(0.0, points, cells)
    real = shutil.disk_usage
    monkeypatch.setattr(shutil, "disk_usage", lambda p: real(p)._replace(free=100))
    with pytest.raises(OSError) as err:
        series.write(0.1, points, cells)
    assert err.value.errno == errno.ENOSPC
    assert [p.name for p in tmp_path.glob("box_*.vtu")] == ["box_0000.vtu"]
    assert len(series.entries) == 1
