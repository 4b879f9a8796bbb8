"""Output for ParaView and the book: meshes with fields as VTU, time series as PVD.

A mesh is plain arrays: ``points`` (n, 2) and ``cells`` (m, 3) for linear triangles
or (m, 6) for quadratic ones, whose nodes are ordered corners 0, 1, 2, then the
midside nodes of edges 01, 12, 20. That is both VTK's quadratic triangle and the
order of scikit-fem's P2 dofs, so a P2 displacement vector ``u`` reshaped to
(n, 2) is a point field of the mesh returned by :func:`mesh_arrays` with
``order=2``. Results as JSON are written by :mod:`pfem_skfem.harness.report`.
"""
from pathlib import Path
import os
import secrets
import xml.etree.ElementTree as ET

import numpy as np

from .discretisation.fields import element_mean, vertex_dofs
from .discretisation.geometry import as_geometry

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


def write_pvd(path, entries, note=None):
    """Write a ParaView collection (PVD) of time steps.

    Parameters
    ----------
    path : file name ending in ``.pvd``.
    entries : iterable of (time, file) pairs, each file as a path from the current
        directory (e.g. as returned by :func:`write_vtu`); the PVD stores it
        relative to its own directory, so the collection moves with its files.
    note : optional text stored as an XML comment at the top (e.g. the units).

    Returns
    -------
    pathlib.Path of the file written.
    """
    path = Path(path)
    if path.suffix != ".pvd":
        raise ValueError(f"path must end in .pvd, got {str(path)!r}")
    root = ET.Element("VTKFile", type="Collection", version="0.1",
                      byte_order="LittleEndian")
    if note:
        root.append(ET.Comment(f" {note} "))
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
    # written whole: a stop while writing (a SIGTERM between two steps' frames, met in
    # CI) leaves the previous collection
    write_text_atomic(path, ET.tostring(root, encoding="unicode", xml_declaration=True))
    return path


def write_text_atomic(path, text):
    """Write ``text`` to ``path`` whole: a temporary file unique to this writer, synced,
    then renamed over ``path`` (a stop while writing leaves the old file)."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")
    try:
        with open(tmp, "w") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


class TimeSeries:
    """VTU files ``<name>_0000.vtu, ...`` of a run and their PVD ``<name>.pvd``.

    The PVD is rewritten after every step, so an interrupted run leaves a valid
    collection of the steps written so far. Before each file the free space is checked
    against twice the size of the last one (or an estimate for the first) plus
    ``reserve`` bytes: a full disk stops the run with an ``OSError`` (ENOSPC) before
    VTK's writer fails (it crashes the process), leaving room for a checkpoint.

    Parameters
    ----------
    directory, name : where and under which name the files are written.
    note : text put in the PVD as a comment (e.g. :data:`STEP_UNITS`).
    reserve : bytes to leave free after a frame (e.g. for a checkpoint).
    reserve_for : what the reserve is, for the message of a full disk (e.g. "1 MB for
        the checkpoint").
    """

    def __init__(self, directory, name, note=None, reserve=0, reserve_for=None):
        self.directory = Path(directory)
        self.name = name
        self.note = note
        self.reserve = reserve
        self.reserve_for = reserve_for
        self.entries = []

    @property
    def pvd_path(self):
        return self.directory / f"{self.name}.pvd"

    def resume(self, until):
        """Go on from a checkpoint at time ``until``: the series keeps the steps of its PVD
        at times <= ``until`` and deletes the VTU files numbered after them (written by
        the run after its checkpoint), so the next step is numbered after the kept ones
        instead of overwriting the first.

        Raises
        ------
        ValueError, deleting nothing, when the PVD is missing while VTU files of the
        series are there, or cannot be read.
        """
        self.entries = []
        vtus = list(self.directory.glob(f"{self.name}_*.vtu"))
        if not self.pvd_path.exists():
            if vtus:
                raise ValueError(f"{self.pvd_path} is missing while {len(vtus)} VTU file(s) "
                                 f"of the series are in {self.directory}/: restore it, or "
                                 "move the VTU files away to go on without them")
            return self
        try:
            for ds in ET.parse(self.pvd_path).getroot().iter("DataSet"):
                t = float(ds.get("timestep"))
                if t <= until * (1 + 1e-12):
                    self.entries.append((t, self.directory / ds.get("file")))
        except (ET.ParseError, TypeError, ValueError) as err:
            raise ValueError(f"{self.pvd_path} is damaged ({err}): restore it, or delete "
                             "it and move the VTU files away to go on without them") from None
        for old in vtus:
            number = old.stem.rsplit("_", 1)[1]
            if number.isdigit() and int(number) >= len(self.entries):
                old.unlink()
        return self

    def _check_space(self, vtu, n_points):
        import errno
        import shutil
        last = self.entries[-1][1] if self.entries else None
        size = last.stat().st_size if last is not None and last.exists() else 400 * n_points
        free = shutil.disk_usage(self.directory).free
        need = 2 * size + self.reserve
        if free < need:
            reserve = ("" if not self.reserve else f" and a reserve of {self.reserve:,} bytes"
                       if self.reserve_for is None else
                       f" and a reserve of {self.reserve_for}, {self.reserve:,} bytes")
            raise OSError(errno.ENOSPC, f"disk nearly full: {free:,} bytes free, {need:,} "
                          f"needed (twice a frame of about {size:,}{reserve}): {vtu.name} "
                          "not written", str(self.directory))

    def write(self, time, points, cells, point_data=None, cell_data=None):
        """Write one step; returns the VTU path."""
        vtu = self.directory / f"{self.name}_{len(self.entries):04d}.vtu"
        self.directory.mkdir(parents=True, exist_ok=True)
        self._check_space(vtu, len(points))
        write_vtu(vtu, points, cells, point_data, cell_data)
        self.entries.append((float(time), vtu))
        write_pvd(self.pvd_path, self.entries, note=self.note)
        return vtu


# -- PFEM steps -----------------------------------------------------------------------------
#: The units of the PFEM fields, for the PVD (the scene's units are consistent SI).
STEP_UNITS = ("units: x, y (or r, z) in m; time in s; velocity, speed in m/s; stresses "
              "(stress, sxx, syy, sxy, stt, hoop_stress, mean_stress, pressure) in Pa when "
              "rho is in kg/m^3 (kPa when rho is in t/m^3); tension positive, pressure "
              "= -mean_stress; plastic_strain_increment per step, dimensionless; "
              "plastic_shear_strain (gamma^p of a softening material) accumulated, "
              "dimensionless; strength (its c(gamma^p) in the step) as the stresses")


def _stress_components(cell_data, stress, axisymmetric):
    """Each stress component as its own scalar array (what ParaView lists by name)."""
    cell_data["sxx"], cell_data["syy"], cell_data["sxy"] = stress[:, 0], stress[:, 1], \
        stress[:, 3]
    if axisymmetric:                          # x = r, y = z; the hoop stress s_tt
        cell_data["stt"] = stress[:, 2]
    return cell_data


def step_fields(state, result):
    """Points, triangles and fields of a step for VTU output.

    Point data: velocity (3 components, z = 0 for ParaView), speed, smoothed mean stress
    and pressure p = -(sx + sy)/2, the tags free_surface and contact (0/1), region;
    cell data: element mean stress (sx, sy, sxy) as one array ``stress`` and as the
    scalars ``sxx``, ``syy``, ``sxy``, equivalent plastic strain increment, the accumulated
    plastic shear strain ``plastic_shear_strain`` of a softening material (in
    axisymmetry x = r and y = z: the stress is (s_rr, s_zz, s_rz), the hoop stress s_tt
    beside it as ``hoop_stress`` and ``stt``, and the mean stress the material's lag,
    I1/3). A saturated scene's (``Scene.water``) stresses are the effective ones, and the
    point data add ``pore_pressure`` (p, compression positive, in the stresses' unit) and
    ``excess_pore_pressure`` (p less the hydrostatic of the water table; p without one).
    Units: :data:`STEP_UNITS`.
    """
    disc, inc = result.disc, result.increment
    points = state.mesh_p
    mp = state.mesh_particle
    kept = mp >= 0                     # none when every particle left in the step
    vel = np.zeros((len(points), 3))
    vel[:, :2] = inc.v[vertex_dofs(disc)]               # a discharged vertex: the solution's
    vel[kept, :2] = state.v[mp[kept]]                   # the particles' (put out of walls)
    sm = result.sigma_m

    def tag(a):                        # a particle's value at its vertex, 0 elsewhere
        values = np.zeros(len(mp))
        values[kept] = a[mp[kept]]
        return values

    stress = element_mean(disc, inc.sigma)
    point_data = {"velocity": vel, "speed": np.linalg.norm(vel, axis=1),
                  "pressure": -sm, "mean_stress": sm,
                  "free_surface": tag(state.free_surface), "contact": tag(state.contact),
                  "region": tag(state.region)}
    cell_data = {"stress": stress[:, [0, 1, 3]],
                 "plastic_strain_increment": element_mean(disc, result.plastic_strain)}
    if state.gamma_p is not None:             # a softening material's (pfem.softening)
        cell_data["plastic_shear_strain"] = element_mean(disc, state.gamma_p)
    if getattr(result, "strength", None) is not None:     # c(gamma^p) the step used
        cell_data["strength"] = element_mean(disc, result.strength)
    if disc.geometry.axisymmetric:            # (s_rr, s_zz, s_rz) above; the hoop stress
        cell_data["hoop_stress"] = stress[:, 2]
    _stress_components(cell_data, stress, disc.geometry.axisymmetric)
    if getattr(result, "pore_pressure", None) is not None:     # a saturated scene
        point_data["pore_pressure"] = result.pore_pressure
        point_data["excess_pore_pressure"] = result.excess_pore_pressure
    return points, disc.mesh.t.T, point_data, cell_data


def initial_fields(state, alpha, axisymmetric=False, water=None):
    """The fields of :func:`step_fields` at t = 0, before any step: the particles and
    the triangles of their alpha-shape, at rest, with the initial stresses (the
    particles' ``stress0`` averaged over each triangle; zero without) and the lagged
    mean stress.

    Parameters
    ----------
    state : the initial PFEMState.
    alpha : the scene's alpha-shape parameter.
    axisymmetric : add the hoop stress arrays.
    water : the scene's :class:`~pfem_skfem.scene.water.Water` (None: a scene without):
        add the initial pore pressure and its excess over the hydrostatic.

    Returns
    -------
    points, cells, point_data, cell_data (as :func:`step_fields`).
    """
    from .pfem import alpha_shape
    cells = alpha_shape(state.x, state.h, alpha).triangles
    n = state.n
    vel = np.zeros((n, 3))
    vel[:, :2] = state.v
    sm = np.asarray(state.sigma_m, dtype=float)
    point_data = {"velocity": vel, "speed": np.linalg.norm(vel, axis=1),
                  "pressure": -sm, "mean_stress": sm,
                  "free_surface": state.free_surface.astype(float),
                  "contact": state.contact.astype(float),
                  "region": state.region.astype(float)}
    s0 = np.zeros((n, 4)) if state.stress0 is None else state.stress0
    stress = s0[cells].mean(axis=1)
    cell_data = {"stress": stress[:, [0, 1, 3]],
                 "plastic_strain_increment": np.zeros(len(cells))}
    if axisymmetric:
        cell_data["hoop_stress"] = stress[:, 2]
    _stress_components(cell_data, stress, axisymmetric)
    if water is not None and state.pore_pressure is not None:
        point_data["pore_pressure"] = state.pore_pressure
        point_data["excess_pore_pressure"] = state.pore_pressure - water.hydrostatic(state.x)
    return state.x, cells, point_data, cell_data


def open_series(directory, name, resume_at=None, initial=None):
    """A VTU series ``name`` in ``directory`` (created), or None when ``directory`` is None.

    The PVD states the fields' units (:data:`STEP_UNITS`).
    ``resume_at``: the time of the checkpoint a run goes on from; the series keeps its
    frames up to that time (:meth:`TimeSeries.resume`).
    ``initial``: (state, scene) of a run at its start, whose frame at t = 0 is written
    (:func:`initial_fields`); nothing for a resumed run."""
    if directory is None:
        return None
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    series = TimeSeries(directory, name, note=STEP_UNITS)
    if resume_at is not None:
        series.resume(resume_at)
    elif initial is not None and initial[0].step == 0:
        state, scene = initial
        series.write(0.0, *initial_fields(state, scene.alpha,
                                          as_geometry(scene.geometry).axisymmetric,
                                          getattr(scene, "water", None)))
    return series
