"""Output for ParaView and the book: meshes with fields as VTU, time series as PVD.

A mesh is plain arrays: ``points`` (n, 2) and ``cells`` (m, 3) for linear triangles
or (m, 6) for quadratic ones, whose nodes are ordered corners 0, 1, 2, then the
midside nodes of edges 01, 12, 20. That is both VTK's quadratic triangle and the
order of scikit-fem's P2 dofs, so a P2 displacement vector ``u`` reshaped to
(n, 2) is a point field of the mesh returned by :func:`mesh_arrays` with
``order=2``. Results as JSON are written by :mod:`pfem_skfem.report`.
"""
from pathlib import Path
import os
import xml.etree.ElementTree as ET

import numpy as np

from .fields import element_mean, vertex_dofs

_VTK_CELL_TYPE = {3: 5, 6: 22}   # VTK_TRIANGLE, VTK_QUADRATIC_TRIANGLE


def mesh_arrays(mesh, order=1):
    """Points and cells of a scikit-fem triangle mesh.

    Parameters
    ----------
    mesh : skfem.MeshTri
    order : 1 for the corner nodes only, 2 to add the edge midpoints (the nodes of
        the P2 displacement element, in scikit-fem's dof order).

    Returns
    -------
    points : (n, 2) array
    cells : (m, 3) or (m, 6) int array
    """
    points = np.asarray(mesh.p, dtype=float).T
    cells = np.asarray(mesh.t, dtype=np.int64).T
    if order == 1:
        return points, cells
    if order != 2:
        raise ValueError(f"order must be 1 or 2, got {order!r}")
    midpoints = 0.5 * (mesh.p[:, mesh.facets[0]] + mesh.p[:, mesh.facets[1]]).T
    edge_nodes = mesh.nvertices + np.asarray(mesh.t2f, dtype=np.int64).T
    return np.vstack([points, midpoints]), np.hstack([cells, edge_nodes])


def per_element(values, owner, n_elements):
    """Average of point values (one row per stress point) over each element.

    Parameters
    ----------
    values : (n_points,) or (n_points, k) array, e.g. a stress field (n_points, 4).
    owner : (n_points,) element of each point (``Discretisation.point_element``).
    n_elements : number of elements.

    Returns
    -------
    (n_elements,) or (n_elements, k) array; NaN for an element with no point.
    """
    values = np.asarray(values, dtype=float)
    owner = np.asarray(owner)
    if owner.shape != values.shape[:1]:
        raise ValueError(f"owner must have one entry per row of values "
                         f"({values.shape[0]}), got shape {owner.shape}")
    flat = values.reshape(len(values), -1)
    count = np.bincount(owner, minlength=n_elements).astype(float)
    total = np.stack([np.bincount(owner, weights=flat[:, j], minlength=n_elements)
                      for j in range(flat.shape[1])], axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = total / count[:, None]
    return mean.reshape((n_elements,) + values.shape[1:])


def _check_fields(name, fields, n):
    out = {}
    for key, value in (fields or {}).items():
        a = np.asarray(value)
        if a.shape[:1] != (n,) or a.ndim > 2:
            raise ValueError(f"{name}[{key!r}] must have shape ({n},) or ({n}, k), "
                             f"got {a.shape}")
        if a.ndim == 2 and a.shape[1] == 2:   # 3-vectors, so ParaView can warp by them
            a = np.hstack([a, np.zeros((n, 1), dtype=a.dtype)])
        out[key] = a
    return out


def to_grid(points, cells, point_data=None, cell_data=None):
    """A ``pyvista.UnstructuredGrid`` of a triangle mesh with its fields.

    Two-component arrays (displacements, velocities) get a zero third component so
    that ParaView treats them as vectors; other arrays are stored as given.
    """
    import pyvista as pv

    points = np.asarray(points, dtype=float)
    cells = np.asarray(cells)
    if points.ndim != 2 or points.shape[1] not in (2, 3) or len(points) == 0:
        raise ValueError(f"points must be an (n, 2) or (n, 3) array, got shape {points.shape}")
    if cells.ndim != 2 or cells.shape[1] not in _VTK_CELL_TYPE or len(cells) == 0:
        raise ValueError("cells must be an (m, 3) (linear) or (m, 6) (quadratic) "
                         f"array of triangles, got shape {cells.shape}")
    if not np.issubdtype(cells.dtype, np.integer):
        raise ValueError(f"cells must be integers, got dtype {cells.dtype}")
    if cells.min() < 0 or cells.max() >= len(points):
        raise ValueError(f"cells refer to nodes outside 0..{len(points) - 1}")
    xyz = np.zeros((len(points), 3))
    xyz[:, :points.shape[1]] = points
    n_nodes = cells.shape[1]
    connectivity = np.hstack([np.full((len(cells), 1), n_nodes), cells]).astype(np.int64)
    cell_types = np.full(len(cells), _VTK_CELL_TYPE[n_nodes], dtype=np.uint8)
    grid = pv.UnstructuredGrid(connectivity.ravel(), cell_types, xyz)
    for key, a in _check_fields("point_data", point_data, len(points)).items():
        grid.point_data[key] = a
    for key, a in _check_fields("cell_data", cell_data, len(cells)).items():
        grid.cell_data[key] = a
    return grid


def write_vtu(path, points, cells, point_data=None, cell_data=None):
    """Write a triangle mesh with point and cell fields to a VTU file.

    Parameters
    ----------
    path : file name ending in ``.vtu`` (parent directories are created).
    points : (n, 2) node coordinates.
    cells : (m, 3) or (m, 6) node numbers of each triangle (see the module docstring).
    point_data, cell_data : dicts name -> array with one row per node / per cell.

    Returns
    -------
    pathlib.Path of the file written.
    """
    path = Path(path)
    if path.suffix != ".vtu":
        raise ValueError(f"path must end in .vtu, got {str(path)!r}")
    grid = to_grid(points, cells, point_data, cell_data)
    path.parent.mkdir(parents=True, exist_ok=True)
    grid.save(path)
    return path


def write_pvd(path, entries):
    """Write a ParaView collection (PVD) of time steps.

    Parameters
    ----------
    path : file name ending in ``.pvd``.
    entries : iterable of (time, file) pairs, each file as a path from the current
        directory (e.g. as returned by :func:`write_vtu`); the PVD stores it
        relative to its own directory, so the collection moves with its files.

    Returns
    -------
    pathlib.Path of the file written.
    """
    path = Path(path)
    if path.suffix != ".pvd":
        raise ValueError(f"path must end in .pvd, got {str(path)!r}")
    root = ET.Element("VTKFile", type="Collection", version="0.1",
                      byte_order="LittleEndian")
    collection = ET.SubElement(root, "Collection")
    base = path.parent.resolve()
    for time, file in entries:
        time = float(time)
        if not np.isfinite(time):
            raise ValueError(f"time must be finite, got {time!r} for {file}")
        rel = os.path.relpath(Path(file).resolve(), base)
        ET.SubElement(collection, "DataSet", timestep=repr(time), group="", part="0",
                      file=Path(rel).as_posix())
    ET.indent(root)
    path.parent.mkdir(parents=True, exist_ok=True)
    ET.ElementTree(root).write(path, xml_declaration=True, encoding="utf-8")
    return path


class TimeSeries:
    """VTU files ``<name>_0000.vtu, ...`` of a run and their PVD ``<name>.pvd``.

    The PVD is rewritten after every step, so an interrupted run leaves a valid
    collection of the steps written so far.
    """

    def __init__(self, directory, name):
        self.directory = Path(directory)
        self.name = name
        self.entries = []

    @property
    def pvd_path(self):
        return self.directory / f"{self.name}.pvd"

    def resume(self, until):
        """Go on from a checkpoint at time ``until``: the series keeps the steps of its PVD
        at times <= ``until`` and deletes the VTU files numbered after them (written by
        the run after its checkpoint), so the next step is numbered after the kept ones
        instead of overwriting the first."""
        import xml.etree.ElementTree as ET
        self.entries = []
        if self.pvd_path.exists():
            for ds in ET.parse(self.pvd_path).getroot().iter("DataSet"):
                t = float(ds.get("timestep"))
                if t <= until * (1 + 1e-12):
                    self.entries.append((t, self.directory / ds.get("file")))
        for old in self.directory.glob(f"{self.name}_*.vtu"):
            number = old.stem.rsplit("_", 1)[1]
            if number.isdigit() and int(number) >= len(self.entries):
                old.unlink()
        return self

    def write(self, time, points, cells, point_data=None, cell_data=None):
        """Write one step; returns the VTU path."""
        vtu = self.directory / f"{self.name}_{len(self.entries):04d}.vtu"
        write_vtu(vtu, points, cells, point_data, cell_data)
        self.entries.append((float(time), vtu))
        write_pvd(self.pvd_path, self.entries)
        return vtu


# -- PFEM steps -----------------------------------------------------------------------------
def step_fields(state, result):
    """Points, triangles and fields of a step for VTU output.

    Point data: velocity (3 components, z = 0 for ParaView), speed, smoothed mean stress
    and pressure p = -(sx + sy)/2, the tags free_surface and contact (0/1), region;
    cell data: element mean stress (sx, sy, sxy), equivalent plastic strain increment (in
    axisymmetry x = r and y = z: the stress is (s_rr, s_zz, s_rz), the hoop stress s_tt
    beside it, and the mean stress the material's lag, I1/3).
    """
    disc, inc = result.disc, result.increment
    points = state.mesh_p
    mp = state.mesh_particle
    vel = np.zeros((len(points), 3))
    vel[:, :2] = inc.v[vertex_dofs(disc)]               # a discharged vertex: the solution's
    vel[mp >= 0, :2] = state.v[mp[mp >= 0]]             # the particles' (put out of walls)
    sm = result.sigma_m
    tag = lambda a: np.where(mp >= 0, a[np.maximum(mp, 0)], 0).astype(float)  # noqa: E731
    stress = element_mean(disc, inc.sigma)
    point_data = {"velocity": vel, "speed": np.linalg.norm(vel, axis=1),
                  "pressure": -sm, "mean_stress": sm,
                  "free_surface": tag(state.free_surface), "contact": tag(state.contact),
                  "region": tag(state.region)}
    cell_data = {"stress": stress[:, [0, 1, 3]],
                 "plastic_strain_increment": element_mean(disc, result.plastic_strain)}
    if disc.geometry.axisymmetric:            # (s_rr, s_zz, s_rz) above; the hoop stress
        cell_data["hoop_stress"] = stress[:, 2]
    return points, disc.mesh.t.T, point_data, cell_data
