"""What is measured on a particle cloud: the deposit, its height at a wall or a gauge, its
centre of mass, its front, its surface's height profile and level, a failed slope's run-out
and retrogression, the wedge a shortened layer builds and the pop-up of its first bands,
its radial mass distribution, its energy and the energy of a step's mesh, the water off its
mesh and what changed a run's area.

The verification scripts measure their runs with these (granular columns, plane and of
revolution; the landslide; the dam break; the block into the tank; the accretionary
wedge; the sensitive-clay slopes); each takes a :class:`~pfem_skfem.pfem.state.PFEMState`
or plain arrays and returns numbers, so a script states what it measures, not how.
"""
import numpy as np

from .alpha_shape import alpha_shape, components, triangle_areas
from .assemble import element_regions

__all__ = ["deposit_extent", "height_at", "wall_height", "deposit_at_wall", "centre_of_mass",
           "front", "front_speed", "front_speed_resolution", "main_body", "off_mesh_volume",
           "area_budget",
           "surface_height", "surface_level", "surface_profile", "ground_particles",
           "failure_extent", "wedge_geometry", "popup",
           "mass_within", "mass_moved", "particle_energy", "mesh_energy"]


def deposit_extent(state, alpha, alpha_advected=0.0):
    """Height and toe (largest x) of the main body: the detected body of largest area.

    Particles splashed off the body (free, or in a small separate body) are left out,
    as an experimentalist measures the deposit, not its outliers. The body is detected as
    the engine detects it (:func:`~pfem_skfem.drivers.pfem_loop.detect_domain`): with
    ``alpha_advected`` > 0 (``PFEMConfig.alpha_advected``) the state's mesh keeps the
    stretched triangles the run kept, which the plain alpha-shape would cut off the deposit.

    Returns
    -------
    (height, toe, main-body particle indices)
    """
    advected = None if state.mesh_p is None else (state.mesh_p, state.mesh_t)
    shape = alpha_shape(state.x, state.h, alpha, advected=advected,
                        alpha_advected=alpha_advected)
    main = int(np.argmax(shape.body_area))
    idx = np.unique(shape.triangles[shape.body == main])
    return float(state.x[idx, 1].max()), float(state.x[idx, 0].max()), idx


def height_at(state, x0, particles=None, *, within=None, default=None):
    """The height of the cloud at the abscissa ``x0``: the highest of ``particles`` (indices
    or a mask; default all) within ``within`` of the vertical x = x0 (default: each
    particle's own spacing h), as a wave gauge reads a surface. ``default`` where no
    particle lies that near (None: ValueError)."""
    idx = np.arange(state.n) if particles is None else np.asarray(particles)
    if idx.dtype == bool:
        idx = np.flatnonzero(idx)
    near = idx[np.abs(state.x[idx, 0] - x0) <= (state.h[idx] if within is None else within)]
    if near.size == 0:
        if default is None:
            raise ValueError(f"no particle lies within "
                             f"{'one spacing' if within is None else within} of x = {x0}")
        return default
    return float(state.x[near, 1].max())


def wall_height(state, particles, wall_x=0.0):
    """Height of the deposit at the wall x = ``wall_x``: the highest of ``particles`` within
    one spacing h of it (:func:`height_at`; Lube et al. 2005 and Lagree et al. 2011 measure
    the final height there, where the deposit is thickest)."""
    return height_at(state, wall_x, particles)


def deposit_at_wall(state, alpha, alpha_advected=0.0):
    """(height at the wall x = 0, highest particle, toe) of the main body, not its splashes:
    :func:`wall_height` of the body of :func:`deposit_extent` (detected as the run detects
    it, ``alpha_advected``). A column's final height is measured there: at the wall of a
    plane column, on the axis r = 0 of a column of revolution."""
    top, toe, body = deposit_extent(state, alpha, alpha_advected)
    return wall_height(state, body), top, toe


def centre_of_mass(state):
    """The particles' centre of mass, (2,)."""
    return state.mass @ state.x / state.mass.sum()


def main_body(points, triangles):
    """The vertices (sorted indices into ``points``) of the largest body of a mesh: of the
    sets of triangles joined through shared vertices, the one of largest area. Two triangles
    that share a vertex share its velocity in a step, so they move as one; a drop meshed on
    its own (a triangle or a few flying ahead) is another body, not this one. Points of no
    triangle belong to none."""
    t = np.asarray(triangles)
    n = len(points)
    _, label = components(n, t.ravel(), np.roll(t, -1, axis=1).ravel())   # the edges
    area = np.bincount(label[t[:, 0]], np.abs(triangle_areas(np.asarray(points), t)),
                       minlength=n)
    return np.unique(t[label[t[:, 0]] == np.argmax(area)])


def off_mesh_volume(state, rho):
    """The volume m / rho of the particles outside the state's mesh (of no vertex of
    ``state.mesh_particle``, the last step's mesh; every particle where there is none):
    the water a step's domain leaves out, flying or sliding free as spray (what
    :func:`~pfem_skfem.drivers.pfem_loop.kept_area` takes out of its target). ``rho``: one
    density, or one per region (each particle's by ``state.region``). A particle added on
    the surface (a midside node of a stretched edge) carries no mass and adds nothing.

    It is not the area the domain lost when they left it: a particle leaving a layer one
    particle deep takes only its slivers (the square dam break: 0.15 % of the area for
    2.3 % of m / rho, book/water_and_mud.md), so the domain's area plus this is no measure
    of the water's."""
    off = np.ones(state.n, dtype=bool)
    if state.mesh_particle is not None:
        off[state.mesh_particle[state.mesh_particle >= 0]] = False
    rho = np.asarray(rho, dtype=float)
    density = rho[state.region[off]] if rho.ndim else rho
    return float(np.sum(state.mass[off] / density))


def area_budget(history, area0):
    """The domain's area over a run split, step by step, into what changed it: (motion,
    remeshing), each (n_steps,), fractions of the first area ``area0``, from a run's
    ``history`` (its records' ``mesh_area`` and ``moved_area``; volumes in axisymmetry).

    motion[k] : step k's mesh moved to its end less itself: what the step's own motion
        changed (with ``PFEMConfig.volume_correction``, what the correction leaves);
    remeshing[k] : step k's mesh less the mesh step k - 1 moved: what the remeshing changed
        (triangles the alpha test drops or adds, particles leaving the mesh or joining it);
        at the first step its mesh less ``area0``.

    Up to any step they add up to its mesh's change, mesh_area[k] / area0 - 1 =
    sum(motion[:k]) + sum(remeshing[:k + 1]) (the record's ``area_change`` where the mesh is
    the detected domain, as the alpha-shape's)."""
    mesh = np.asarray(history["mesh_area"], dtype=float)
    moved = np.asarray(history["moved_area"], dtype=float)
    remeshing = np.r_[mesh[:1] - area0, mesh[1:] - moved[:-1]] / area0
    return (moved - mesh) / area0, remeshing


def front(state, mesh=True, *, main=False):
    """The front: the largest x of the mesh's vertices (of the mass, not a flying particle);
    with ``main`` of the vertices of the mesh's largest body only (:func:`main_body`: a drop
    meshed on its own is not the front of the water either); with ``mesh=False`` of every
    particle, a drop flying ahead included (the tip of a surge with its spray)."""
    if not mesh:
        if main:
            raise ValueError("main=True measures the mesh's main body: it needs mesh=True")
        return float(state.x[:, 0].max())
    if main:
        return float(np.max(state.mesh_p[main_body(state.mesh_p, state.mesh_t), 0]))
    return float(np.max(state.mesh_p[:, 0]))


def _windows(t, window):
    """The index ranges [i, j] of the samples within [t_i, t_i + window], for each sample t_i
    whose window the series covers."""
    for i in range(len(t)):
        j = np.searchsorted(t, t[i] + window * (1 - 1e-9), side="left")
        if j >= len(t):
            return
        yield i, j


def front_speed(t, x, window):
    """The largest speed of a front x(t) over any stretch of ``window`` in t: the largest
    slope of the least-squares lines through the samples within [t_i, t_i + window] for each
    sample t_i whose window the series covers (nan if it covers none). A front measured on
    particles is known to a particle spacing h: from one step to the next it jumps by up to
    h as a particle leaves the body or joins it, which a step-to-step difference reads as a
    speed of h / dt; over a window the slope's error is at most
    :func:`front_speed_resolution`, about 1.5 h / window."""
    t, x = np.asarray(t, dtype=float), np.asarray(x, dtype=float)
    best = np.nan
    for i, j in _windows(t, window):
        best = np.nanmax([best, np.polyfit(t[i:j + 1], x[i:j + 1], 1)[0]])
    return float(best)


def front_speed_resolution(t, window, h):
    """The most that :func:`front_speed` can read above the true speed when each sample of
    the front is known within a band of width ``h`` (x_i = x(t_i) + e_i, 0 <= e_i <= h): the
    least-squares slope of the errors, sum (t_i - mean t) e_i / sum (t_i - mean t)^2, is
    largest with e_i = h after the window's mean time and 0 before it, so the bound is
    h sum_{t_i > mean} (t_i - mean) / sum (t_i - mean)^2, the largest over the windows. It
    is sharp (that pattern attains it); for many evenly spaced samples it tends to 1.5 h /
    window (a step of h at the window's middle), for 21 samples 1.43 h / window. nan where
    the series covers no window."""
    t = np.asarray(t, dtype=float)
    best = np.nan
    for i, j in _windows(t, window):
        d = t[i:j + 1] - t[i:j + 1].mean()
        best = np.nanmax([best, h * d[d > 0].sum() / (d * d).sum()])
    return float(best)


def surface_height(state, x):
    """The height of the mesh's top above each abscissa of ``x``: the largest y at which the
    vertical line through x crosses an edge of the state's mesh (its vertices moved to t_n,
    straight-sided), so the piecewise-linear free surface of a deposit on a floor. -inf
    where no element lies above x (a gap in the body, or beyond its ends)."""
    p, t = np.asarray(state.mesh_p), np.asarray(state.mesh_t)
    edges = np.vstack([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    (x1, y1), (x2, y2) = p[edges[:, 0]].T, p[edges[:, 1]].T
    x = np.asarray(x, dtype=float)[:, None]
    vertical = x2 == x1                      # a vertical edge's top is a vertex of another edge
    w = (x - x1) / np.where(vertical, 1.0, x2 - x1)
    crossed = (x >= np.minimum(x1, x2)) & (x <= np.maximum(x1, x2)) & ~vertical
    return np.where(crossed, y1 + w * (y2 - y1), -np.inf).max(axis=1)


def surface_level(x, particles, width, x_from, x_to):
    """The level of a surface: the mean, over the columns ``width`` wide from ``x_from`` to
    ``x_to``, of the highest of ``particles`` (a mask of the points ``x``) in each column
    (the columns holding none left out; nan if none holds one)."""
    edges = np.arange(x_from, x_to + 1e-12, width)
    tops = [x[particles & (x[:, 0] >= a) & (x[:, 0] < b), 1] for a, b in zip(edges, edges[1:])]
    return float(np.mean([t.max() for t in tops if t.size])) if any(t.size for t in tops) \
        else np.nan


def surface_profile(x, h, alpha, bins):
    """Height of the material's upper boundary at the centres of ``bins`` (the highest
    particle of the main body in each bin; nan where empty): the particles ``x`` of
    spacings ``h``, the main body the body of largest area of their alpha-shape
    (:func:`~pfem_skfem.pfem.alpha_shape.alpha_shape` of parameter ``alpha``).

    Returns (bin centres, heights)."""
    shape = alpha_shape(x, h, alpha)
    main = int(np.argmax(shape.body_area))
    pts = x[np.unique(shape.triangles[shape.body == main])]
    k = np.digitize(pts[:, 0], bins) - 1
    top = np.full(len(bins) - 1, np.nan)
    for i in range(len(bins) - 1):
        if np.any(k == i):
            top[i] = pts[k == i, 1].max()
    return 0.5 * (bins[1:] + bins[:-1]), top


def ground_particles(x0, level, behind=None):
    """The original ground surface of a slope: the indices of the particles that start
    (at ``x0``) above ``level`` (a fraction of a spacing below the top) and, with ``behind``
    (the crest's x), at x <= behind (the top, not the face)."""
    x0 = np.asarray(x0, dtype=float)
    above = x0[:, 1] > level
    if behind is not None:
        above &= x0[:, 0] <= behind + 1e-9
    return np.flatnonzero(above)


def failure_extent(x, x0, ground, *, toe, crest, drop, originals=True):
    """(run-out, retrogression) of a slope failing towards +x, its particles at ``x`` (the
    first len(x0) of them started at ``x0``).

    The run-out: from ``toe`` to the furthest particle, of those that started at x0
    (``originals``) or of all of x (those added since included). The retrogression: from
    ``crest`` back to the furthest-back of the ``ground`` particles (indices,
    :func:`ground_particles`) that dropped by more than ``drop``; 0 where none did, never
    below 0."""
    x, x0 = np.asarray(x, dtype=float), np.asarray(x0, dtype=float)
    dropped = ground[x0[ground, 1] - x[ground, 1] > drop]
    retro = float(crest - x0[dropped, 0].min()) if dropped.size else 0.0
    front = x[:len(x0)] if originals else x
    return float(front[:, 0].max() - toe), max(retro, 0.0)


def wedge_geometry(xc, top, x_wall, h0, spacing):
    """The wedge a layer of height ``h0`` thickens into against a wall at ``x_wall``, from
    its surface profile (``xc``, ``top``: :func:`surface_profile`; the bins at or behind the
    wall and the empty ones left out): its crest (highest point), its front (the first x
    past the crest where the surface is back within ``spacing`` of h0; the last bin if
    none), the area lifted above h0 between wall and front, and the mean surface slope
    [deg] away from the wall: a straight-line fit over the middle two thirds from the crest
    to the front (nan with fewer than two bins there).

    Returns dict(front, length (front - x_wall), area_up, crest_x, crest, slope_deg)."""
    ok = np.isfinite(top) & (xc > x_wall)
    xc, top = xc[ok], top[ok]
    crest = int(np.argmax(top))
    beyond = np.flatnonzero((top <= h0 + spacing) & (np.arange(len(top)) > crest))
    front = xc[beyond[0]] if beyond.size else xc[-1]
    inside = xc <= front
    area_up = float(np.trapezoid(np.clip(top[inside] - h0, 0, None), xc[inside]))
    span = front - xc[crest]
    mid = (xc >= xc[crest] + span / 6) & (xc <= front - span / 6)
    slope = -np.polyfit(xc[mid], top[mid], 1)[0] if mid.sum() >= 2 else np.nan
    return {"front": float(front), "length": float(front - x_wall), "area_up": area_up,
            "crest_x": float(xc[crest]), "crest": float(top[crest]),
            "slope_deg": float(np.degrees(np.arctan(slope)))}


def popup(points, cells, deps, h0, x_wall, fraction=0.5):
    """A V of two bands rooted near the base of the wall, from the plastic strain field of
    a layer of height ``h0`` pushed by a wall at ``x_wall``: ``deps`` one value per cell
    (triangles ``cells`` of the vertices ``points``).

    The elements whose centres lie within 2.5 h0 of the wall, straining more than
    ``fraction`` of the largest increment, form the bands (fewer than four: no pop-up);
    the mean of those within h0 / 4 of the lowest is the root; the straining elements on
    either side of it are fitted by straight lines y(x). A pop-up: a back thrust rising
    towards the wall (dy/dx < 0) and a forward thrust rising away from it (dy/dx > 0),
    both dipping between 15 and 75 deg, rooted below h0 / 2.
    Returns dict(root_x (from the wall), root_y, back_dip, fore_dip, is_popup).
    """
    centre = points[cells].mean(axis=1)
    hot = deps > fraction * deps.max()
    near = hot & (centre[:, 0] < x_wall + 2.5 * h0)
    c = centre[near]
    out = {"root_x": np.nan, "root_y": np.nan, "back_dip": np.nan, "fore_dip": np.nan,
           "is_popup": False}
    if len(c) < 4:
        return out
    low = c[c[:, 1] <= c[:, 1].min() + 0.25 * h0]
    root = low.mean(axis=0)
    out["root_x"], out["root_y"] = float(root[0] - x_wall), float(root[1])
    left, right = c[c[:, 0] < root[0]], c[c[:, 0] > root[0]]
    dips = []
    for side in (left, right):
        if len(side) >= 2 and np.ptp(side[:, 0]) > 0:
            slope = np.polyfit(side[:, 0], side[:, 1], 1)[0]
            dips.append(float(np.degrees(np.arctan(slope))))
        else:
            dips.append(np.nan)
    out["back_dip"], out["fore_dip"] = -dips[0], dips[1]
    out["is_popup"] = bool(np.isfinite(dips).all() and 15 <= -dips[0] <= 75 and 15 <= dips[1] <= 75
                           and root[1] < 0.5 * h0)
    return out


def mass_within(r, m):
    """(radii in increasing order, share of the mass within each): the radial mass
    distribution F of particles at radii ``r`` of masses ``m``."""
    r, m = np.asarray(r, dtype=float), np.asarray(m, dtype=float)
    order = np.argsort(r, kind="stable")
    return r[order], np.cumsum(m[order]) / np.sum(m)


def mass_moved(r_a, m_a, r_b, m_b):
    """The largest share of the material that two deposits put on opposite sides of one
    radius: max over r of |F_a(r) - F_b(r)|, F(r) the share of the mass within radius r
    (:func:`mass_within`; particles at radii ``r_a`` of masses ``m_a``, and ``r_b``,
    ``m_b``; the Kolmogorov-Smirnov distance of the radial mass distributions). 0 for the
    same deposit, 1 for two that do not overlap; a thin tail that slides further moves
    only its own mass, where the farthest particle moves by the tail's whole reach."""
    grid = np.union1d(r_a, r_b)

    def share_at_grid(r, m):
        radii, share = mass_within(r, m)
        return np.concatenate([[0.0], share])[np.searchsorted(radii, grid, side="right")]
    return float(np.max(np.abs(share_at_grid(r_a, m_a) - share_at_grid(r_b, m_b))))


def particle_energy(state, gravity):
    """[kinetic, potential] energy the particles carry: sum m |v|^2 / 2 and -sum m g . x
    (per unit thickness in plane strain; particles without mass, the midside ones added by
    a remeshing, carry none). The kinetic energy is that of the step record's
    ``kinetic_energy`` (:func:`~pfem_skfem.pfem.bookkeeping.particle_kinetic_energy`) summed
    in another order: equal to the last bits."""
    kinetic = 0.5 * float(state.mass @ np.sum(state.v ** 2, axis=1))
    return [kinetic, -float(state.mass @ (state.x @ np.asarray(gravity, dtype=float)))]


def mesh_energy(state, scene, record, result):
    """[kinetic at t_n+1, potential at t_n, potential at t_n+1, kinetic at t_n] energy of a
    step's own masses (each element's density x area, its region the one the step gave it,
    :func:`~pfem_skfem.pfem.assemble.element_regions`): the kinetic energies of the step's
    ``record`` (its mass matrix; at t_n of the velocities mapped onto its mesh) and
    -sum rho_e A_e g . centroid_e over the step's mesh as remeshed at t_n
    (``result.disc.mesh``) and as moved to t_n+1 (``state.mesh_p``, ``state.mesh_t``). A
    step's energies at t_n less the previous step's at t_n+1 are what the remeshing added."""
    rho = np.array([r.rho for r in scene.regions], dtype=float)[element_regions(state,
                                                                                result.pm)]
    gravity = np.asarray(scene.gravity, dtype=float)

    def potential(points, triangles):
        mass = rho * np.abs(triangle_areas(points, triangles))
        return -float(mass @ (points[triangles].mean(axis=1) @ gravity))

    return [float(record["kinetic_energy"]),
            potential(result.disc.mesh.p.T, result.disc.mesh.t[:3].T),
            potential(state.mesh_p, state.mesh_t), float(record["start_kinetic_energy"])]


def largest_gain(series):
    """The largest rise of a series between two instants: max over t of E(t) - min_{s<=t} E(s)
    (0 for a series that never rises)."""
    series = np.asarray(series, dtype=float)
    return float(np.max(series - np.minimum.accumulate(series)))


def energy_budget(energy, mesh):
    """Where a run's energy went, from its series of :func:`particle_energy` (one
    [kinetic, potential] a record, the first at the start) and of :func:`mesh_energy` (one a
    step). An inviscid implicit step only loses energy; what a remeshing adds is the next
    step's energies at t_n less the previous step's at t_n+1.

    Returns a dict: ``energy_change_end`` (the particles' total less its start),
    ``energy_largest_rise`` (in one record), ``energy_largest_gain`` (:func:`largest_gain`),
    the same three of the steps' own energies (``mesh_energy_*``, from the first step),
    ``kinetic_peak`` (the particles'), ``remeshing_potential`` and ``remeshing_kinetic``
    (summed over the remeshings) and ``steps_energy`` (what the steps changed, summed)."""
    energy, mesh = np.asarray(energy, dtype=float), np.asarray(mesh, dtype=float)
    total = energy.sum(axis=1) - energy[0].sum()
    own = mesh[:, 0] + mesh[:, 2] - mesh[0, 0] - mesh[0, 2]
    return {"energy_change_end": float(total[-1]),
            "energy_largest_rise": float(np.max(np.diff(total))),
            "energy_largest_gain": largest_gain(total),
            "mesh_energy_change_end": float(own[-1]),
            "mesh_energy_largest_rise": float(np.max(np.diff(own))),
            "mesh_energy_largest_gain": largest_gain(own),
            "kinetic_peak": float(energy[:, 0].max()),
            "remeshing_potential": float(np.sum(mesh[1:, 1] - mesh[:-1, 2])),
            "remeshing_kinetic": float(np.sum(mesh[1:, 3] - mesh[:-1, 0])),
            "steps_energy": float(np.sum(mesh[:, 0] + mesh[:, 2] - mesh[:, 3] - mesh[:, 1]))}
