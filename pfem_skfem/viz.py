"""Figures, in one home: matplotlib helpers for triangle meshes and fields, the geometry
stages of PFEM (:func:`plot_points`, :func:`plot_alpha_shape`, :func:`plot_particle_mesh`
for a skfem MeshTri and its particles) and pyvista pictures.

Meshes of :func:`plot_mesh` and :func:`plot_field` are the arrays of :mod:`pfem_skfem.io` (``points`` (n, 2), ``cells`` (m, 3)
or (m, 6); for quadratic cells only the corners are drawn).

pyvista renders off-screen through EGL. Without the system libraries (Debian
``libegl1 libgl1-mesa-dri``) creating a plotter kills the Python process with a
segmentation fault, so :func:`render_png` renders in a subprocess,
``python -m pfem_skfem.viz <vtu> <png> --scalars NAME``, and reports failure as a
warning and ``False`` instead.
"""
import argparse
import os
from pathlib import Path
import subprocess
import sys
import warnings

import numpy as np


def _triangulation(points, cells):
    from matplotlib.tri import Triangulation

    points = np.asarray(points, dtype=float)
    cells = np.asarray(cells)
    if points.ndim != 2 or points.shape[1] < 2:
        raise ValueError(f"points must be an (n, 2) array, got shape {points.shape}")
    if cells.ndim != 2 or cells.shape[1] not in (3, 6):
        raise ValueError(f"cells must be an (m, 3) or (m, 6) array, got shape {cells.shape}")
    return Triangulation(points[:, 0], points[:, 1], cells[:, :3])


def plot_mesh(ax, points, cells, *, color="0.3", linewidth=0.5, **kwargs):
    """Draw the edges of a triangle mesh on a matplotlib axis (equal aspect)."""
    lines = ax.triplot(_triangulation(points, cells), color=color, linewidth=linewidth,
                       **kwargs)
    ax.set_aspect("equal")
    return lines


def plot_field(ax, points, cells, values, *, at="auto", cmap="viridis", label=None,
               colorbar=True, edges=False, **kwargs):
    """Colour a triangle mesh by a scalar field, one value per element or per node.

    Parameters
    ----------
    ax : matplotlib axis.
    points, cells : the mesh (see the module docstring).
    values : (m,) values per element (flat colour) or (n,) values per node
        (interpolated colour).
    at : "elements", "points" or "auto" (by the length of ``values``).
    label : colour-bar label.
    edges : draw the mesh edges on top.

    Returns
    -------
    The matplotlib mappable (for ``clim`` or another colour bar).
    """
    tri = _triangulation(points, cells)
    values = np.asarray(values, dtype=float)
    n_cells, n_points = len(tri.triangles), len(tri.x)
    if at == "auto":
        if n_cells == n_points:
            raise ValueError("values fit both elements and points: pass at='elements' "
                             "or at='points'")
        at = "elements" if len(values) == n_cells else "points"
    expected = {"elements": n_cells, "points": n_points}
    if at not in expected:
        raise ValueError(f"at must be 'elements', 'points' or 'auto', got {at!r}")
    if values.shape != (expected[at],):
        raise ValueError(f"values must have shape ({expected[at]},) for at={at!r}, "
                         f"got {values.shape}")
    if at == "elements":
        mappable = ax.tripcolor(tri, facecolors=values, cmap=cmap, **kwargs)
    else:
        mappable = ax.tripcolor(tri, values, shading="gouraud", cmap=cmap, **kwargs)
    if edges:
        ax.triplot(tri, color="k", linewidth=0.2, alpha=0.5)
    ax.set_aspect("equal")
    if colorbar:
        ax.figure.colorbar(mappable, ax=ax, label=label)
    return mappable


# -- the geometry stages of PFEM (cloud, alpha-shape, meshes) ---------------------------
def plot_alpha_shape(ax, shape, *, title=None, show_removed=False, point_size=4):
    """Kept triangles (shaded), boundary edges (outer blue, holes red), particles, free ones hollow."""
    from matplotlib.collections import LineCollection, PolyCollection

    p = shape.points
    if show_removed and len(shape.delaunay):
        ax.add_collection(PolyCollection(p[shape.delaunay[~shape.kept]], facecolor="none",
                                         edgecolor="0.8", linewidth=0.4))
    if len(shape.triangles):
        ax.add_collection(PolyCollection(p[shape.triangles], facecolor="#cfe3f3",
                                         edgecolor="#8fb3d0", linewidth=0.3))
    if len(shape.edges):
        hole = shape.loop_area[shape.edge_loop] < 0
        ax.add_collection(LineCollection(p[shape.edges[~hole]], colors="#1f4e9c", linewidths=1.2))
        ax.add_collection(LineCollection(p[shape.edges[hole]], colors="#c0392b", linewidths=1.2))
    inside = ~shape.free
    ax.plot(*p[inside].T, "k.", ms=point_size)
    ax.plot(*p[shape.free].T, "o", mfc="none", mec="0.3", ms=point_size * 0.8)
    _frame_cloud(ax, p, title)


def plot_particle_mesh(ax, mesh, *, title=None, particle=None, color="#8fb3d0"):
    """Triangles of a MeshTri of a PFEM step; vertices that are particles (``particle`` >= 0,
    :class:`~pfem_skfem.pfem.remesh.ParticleMesh`) black, added nodes orange."""
    from matplotlib.collections import PolyCollection

    p = mesh.p.T
    ax.add_collection(PolyCollection(p[mesh.t.T], facecolor="#eef4fa", edgecolor=color,
                                     linewidth=0.4))
    if particle is not None:
        ax.plot(*p[particle >= 0].T, "k.", ms=2)
        ax.plot(*p[particle < 0].T, ".", color="#e67e22", ms=3)
    _frame_cloud(ax, p, title)


def plot_points(ax, points, *, title=None, point_size=4):
    """A bare particle cloud."""
    ax.plot(*np.asarray(points).T, "k.", ms=point_size)
    _frame_cloud(ax, np.asarray(points), title)


def _frame_cloud(ax, p, title):
    # the cloud's box with a small margin, equal axes, no ticks
    lo, hi = p.min(axis=0), p.max(axis=0)
    pad = 0.03 * max(hi - lo) if len(p) else 1.0
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xticks([]), ax.set_yticks([])
    if title:
        ax.set_title(title, fontsize=10)


# -- particles and fields at several times, bounds of limit analysis -------------------
def snapshot_grid(panels, *, label, title, ncols=1, size=(9.0, 2.0), scale=1.0,
                  axes=("x [m]", "y [m]"), colours=None, draw=None, limits=(None, None),
                  dots="C0"):
    """A grid of panels, one per snapshot, coloured by one field on one colour scale,
    read by one colour bar.

    Parameters
    ----------
    panels : dict
        Panel title -> ``(points, values)`` (particles, a dot each, ``values`` one per
        point; None: the particles alone, dots of the colour ``dots``) or
        ``(points, values, cells)`` (a triangle mesh, ``values`` one per cell).
    label : the colour bar's label (the field and its unit); None where no panel has values.
    title : the figure's title (``suptitle``).
    ncols : panels per row.
    size : (width of the figure, height of a row) in inches.
    scale : lengths are shown divided by it (``axes`` then name the scaled lengths).
    axes : (x label, y label), or None: ``draw`` labels them.
    colours : keywords of the colour map, ``cmap`` (viridis), ``vmin`` (0) and ``vmax``
        (default the largest value of every panel).
    draw : ``draw(ax)`` called on each panel before its snapshot (a background, a frame).
    limits : (xlim, ylim) in scaled lengths, None for either: matplotlib's.

    Returns
    -------
    (figure, array of axes)
    """
    from matplotlib.tri import Triangulation

    from .harness.figures import pyplot

    colours = dict(colours or {})
    top = max((float(np.max(p[1], initial=0.0)) for p in panels.values() if p[1] is not None),
              default=0.0)
    colours.setdefault("cmap", "viridis")
    colours.setdefault("vmin", 0.0)
    colours.setdefault("vmax", top or 1.0)
    nrow = -(-len(panels) // ncols)
    # one row of a wide panel is a strip: at least a quarter as high as wide, a page reads it
    height = max(size[1] * nrow + 1.0, size[0] / 4.0)
    fig, grid = pyplot().subplots(nrow, ncols, figsize=(size[0], height), squeeze=False,
                                  layout="constrained")
    mappable = None
    for ax, (name, (points, values, *cells)) in zip(grid.flat, panels.items()):
        if draw is not None:
            draw(ax)
        x, y = (np.asarray(points, dtype=float) / scale).T
        if values is None:
            ax.plot(x, y, ".", ms=2, color=dots)
        elif cells:
            mappable = ax.tripcolor(Triangulation(x, y, cells[0]),
                                    facecolors=np.asarray(values, dtype=float), **colours)
        else:
            mappable = ax.scatter(x, y, c=values, s=2, **colours)
        ax.set_aspect("equal")
        ax.set_title(name, fontsize=9)
        if limits[0] is not None:
            ax.set_xlim(*limits[0])
        if limits[1] is not None:
            ax.set_ylim(*limits[1])
        if axes is not None:
            ax.set_xlabel(axes[0], fontsize=8)
            ax.set_ylabel(axes[1], fontsize=8)
        ax.tick_params(labelsize=8)
    for ax in list(grid.flat)[len(panels):]:
        ax.set_visible(False)
    fig.suptitle(title, fontsize=10)
    if mappable is not None:
        fig.colorbar(mappable, ax=list(grid.flat), label=label, shrink=0.8)
    return fig, grid


def plot_histories(ax, runs, x, y, label, *, style="-", scale=1.0, floor=None, log=False):
    """One line per run of a study, so that runs read side by side: ``run[y]`` times
    ``scale`` (no lower than ``floor`` if given, for a log axis) against ``run[x]``, in the
    ``style`` of :meth:`~matplotlib.axes.Axes.plot`; each labelled by ``label``, a format of
    the run's keys (``"mu = {mu:g}"``) or a function of the run. ``log``: a log y axis."""
    if log:
        ax.set_yscale("log")
    for r in runs:
        values = scale * np.asarray(r[y], dtype=float)
        ax.plot(r[x], values if floor is None else np.maximum(values, floor), style,
                label=label(r) if callable(label) else label.format(**r))


def plot_ground(ax, x, z_ground, z_before=None, *, xlim=None,
                axes=("horizontal distance x [m]", "elevation [m]")):
    """A ground profile under particles, lengths at one scale: the ground below
    ``z_ground(x)`` grey under its line, the ground before a failure ``z_before(x)``
    dashed; the frame ``xlim`` (default the profile's) and 8 below the ground, 8 above the
    highest surface in it, labelled ``axes`` (a slide, a deposit drawn where it lies)."""
    from .harness.figures import labelled

    x, z_ground = np.asarray(x, dtype=float), np.asarray(z_ground, dtype=float)
    xlim = (x[0], x[-1]) if xlim is None else xlim
    ax.fill_between(x, z_ground, min(z_ground) - 10, color="0.85", lw=0)
    ax.plot(x, z_ground, "k-", lw=1)
    top = z_ground if z_before is None else np.asarray(z_before, dtype=float)
    if z_before is not None:
        ax.plot(x, top, color="0.5", lw=0.8, ls="--")
    ax.set_xlim(*xlim)
    ax.set_ylim(min(z_ground) - 8, np.max(top[(x >= xlim[0]) & (x <= xlim[1])]) + 8)
    labelled(ax, *axes, legend=None).set_aspect("equal")


def plot_bound_fields(axes, problem, lower, upper, what):
    """The fields of a pair of limit bounds on one mesh: the upper bound's dissipation per
    area (log colours, six decades) on ``axes[0]``, the lower bound's yield ratio (the
    largest of each element's vertices, 1 at yield) on ``axes[1]``, each with its colour bar.

    ``problem`` a :class:`~pfem_skfem.problems.bounds.LimitProblem`, ``lower`` and
    ``upper`` its :func:`~pfem_skfem.problems.bounds.lower_bound` and
    :func:`~pfem_skfem.problems.bounds.upper_bound`; ``what`` begins the panels' titles."""
    from matplotlib.colors import LogNorm

    from .discretisation.bounds import element_gradients

    mesh = problem.mesh
    x, y = mesh.p
    density = np.maximum(upper.dissipation / element_gradients(mesh)[1], 1e-300)
    top = density.max()
    ratio = problem.criterion.yield_ratio(lower.sigma).reshape(-1, 3).max(axis=1)
    for ax, values, kw, label in (
            (axes[0], np.maximum(density, top * 1e-6),
             dict(norm=LogNorm(top * 1e-6, top), cmap="magma"), "dissipation / area"),
            (axes[1], np.minimum(ratio, 1.0), dict(vmin=0.0, vmax=1.0, cmap="viridis"),
             "yield ratio (1 = at yield)")):
        art = ax.tripcolor(x, y, mesh.t.T, facecolors=values, **kw)
        ax.triplot(x, y, mesh.t.T, lw=0.1, color="0.6")
        ax.figure.colorbar(art, ax=ax, label=label, shrink=0.8)
        ax.set_aspect("equal")
        ax.set_xlabel("x")
        ax.set_ylabel("y")
    axes[0].set_title(f"{what}: upper bound, {mesh.t.shape[1]} el", fontsize=9)
    axes[1].set_title(f"{what}: lower bound, max over vertices", fontsize=9)


def plot_rounds(ax, rounds, scale=1.0, *, hollow=False, what="", reference=None,
                label=None):
    """Lower (circles) and upper (squares) bounds against the elements of their meshes, on
    a log axis with plain numbers: ``rounds`` of :func:`~pfem_skfem.drivers.bounds.adapt`
    or :func:`~pfem_skfem.drivers.bounds.bracket_safety` (``elements``, ``lower``,
    ``upper``), the bounds times ``scale``; ``hollow``: dashed, hollow marks (a second
    series, e.g. uniform meshes), its labels ending with ``what``. The value they bracket,
    ``reference`` (a number: a dashed line; (low, high): a grey band), is drawn with its
    ``label``."""
    from matplotlib.ticker import LogLocator, NullFormatter, ScalarFormatter

    n = [r.elements for r in rounds]
    style = dict(mfc="none", ls="--") if hollow else dict(ls="-")
    for key, mark, colour in (("lower", "o", "C0"), ("upper", "s", "C3")):
        ax.plot(n, [getattr(r, key) * scale for r in rounds], marker=mark, color=colour,
                label=f"{key} bound{what}", **style)
    if np.ndim(reference) == 1:
        ax.axhspan(*reference, color="0.8", label=label)
    elif reference is not None:
        ax.axhline(reference, color="k", ls="--", lw=1, label=label)
    ax.set_xscale("log")
    lo, hi = ax.dataLim.intervalx
    ax.set_xlim(min(lo, min(n)) / 1.3, max(hi, max(n)) * 1.3)
    ax.xaxis.set_major_locator(LogLocator(subs=(1, 1.5, 2, 3, 5, 7)))
    ax.xaxis.set_major_formatter(ScalarFormatter())
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("elements")


def plot_order(ax, sizes, errors, label, *, slope=None):
    """A convergence study on log axes: ``errors`` against ``sizes`` (an element count, a
    spacing) marked and joined, with its ``label`` (its observed order, say); ``slope``: the
    line error ~ size^slope through the first point, dashed grey, for the order expected."""
    ax.loglog(sizes, errors, "o-", label=label)
    if slope is not None:
        sizes = np.asarray(sizes, dtype=float)
        ax.loglog(sizes, errors[0] * (sizes / sizes[0]) ** slope, "--", color="0.5",
                  label=f"slope {abs(slope):g}")


def plot_groups(axes, series, x, ys, *, curves=(), log=False, labels=None):
    """Groups of cases beside curves (fits), one quantity a panel: the figure of a study
    that compares measured points with a formula, or cases along a parameter.

    ``series``: (label, rows, format) each, ``rows`` dicts drawn as their ``x`` against their
    ``ys[i]`` on ``axes[i]`` in increasing ``x`` (a group without rows is left out);
    ``curves``: (panel, x values, y values, format, label) each, drawn first; ``log``:
    log-log axes; ``labels``: (x label, the y label of each panel[, a title for every
    panel]) labels the panels and draws their legends (:func:`~pfem_skfem.harness.figures
    .labelled`). Returns ``axes``."""
    from .harness.figures import labelled

    def draw(ax, *line, **keywords):
        return (ax.loglog if log else ax.plot)(*line, **keywords)

    for panel, cx, cy, fmt, label in curves:
        draw(axes[panel], cx, cy, fmt, label=label)
    for label, rows, fmt in series:
        rows = sorted(rows, key=lambda r: r[x])
        for ax, y in zip(axes, ys if rows else ()):
            draw(ax, [r[x] for r in rows], [r[y] for r in rows], fmt, label=label)
    for ax, ylabel in zip(axes, labels[1] if labels else ()):
        labelled(ax, labels[0], ylabel, *labels[2:], title_size=9)
    return axes


def groups_figure(path, title, series, x, ys, **panels):
    """One row of :func:`plot_groups` panels (5 x 4 inches each), titled ``title``, saved at
    ``path`` (the keywords ``panels`` are :func:`plot_groups`'); returns ``path``, or None
    where no series has a row (a study not asked for: no figure of its fits alone)."""
    from .harness.figures import pyplot, save_figure

    if not any(rows for _, rows, _ in series):
        return None
    fig, axes = pyplot().subplots(1, len(ys), figsize=(5 * len(ys), 4), squeeze=False)
    plot_groups(axes[0], series, x, ys, **panels)
    fig.suptitle(title)
    save_figure(fig, path)
    return path


def plot_mass_profiles(axes, deposits, *, scale=1.0, title=None):
    """Deposits compared as their particles and as their mass by radius, on a pair of
    panels: the particles, r and z over ``scale``, on ``axes[0]`` (with ``title``), and the
    share of the mass within each radius (:func:`~pfem_skfem.pfem.measure.mass_within`) on
    ``axes[1]``, whose largest difference between two deposits is
    :func:`~pfem_skfem.pfem.measure.mass_moved`. ``deposits``: (label, points, masses) each."""
    from .harness.figures import labelled
    from .pfem.measure import mass_within

    for label, points, mass in deposits:
        r, z = np.asarray(points, dtype=float)[:, 0], np.asarray(points, dtype=float)[:, 1]
        axes[0].plot(r / scale, z / scale, ".", ms=2, label=label)
        radii, share = mass_within(r, mass)
        axes[1].step(radii / scale, share, where="post", label=label)
    labelled(axes[0], "r / r0", "z / r0", title, title_size=9).set_aspect("equal")
    labelled(axes[1], "r / r0", "share of the mass within r")
    return axes


def mass_profiles_figure(path, title, columns):
    """Deposits of a study compared a column of :func:`plot_mass_profiles` panels per group
    (an aspect ratio, say: 4.2 inches wide, 6 high), titled ``title``, saved at ``path``.
    ``columns``: (column title, length scale, deposits) each, the deposits (label, points,
    masses) as :func:`plot_mass_profiles` takes them. Returns ``path``, or None without
    columns (nothing to compare: no figure)."""
    from .harness.figures import pyplot, save_figure

    if not columns:
        return None
    fig, axes = pyplot().subplots(2, len(columns), figsize=(4.2 * len(columns), 6),
                                  squeeze=False)
    for j, (name, scale, deposits) in enumerate(columns):
        plot_mass_profiles(axes[:, j], deposits, scale=scale, title=name)
    fig.suptitle(title)
    save_figure(fig, path)
    return path


def lines_figure(path, lines, labels, *, size=(6, 4), title_size=None):
    """One panel of curves (histories against time, say), saved at ``path``: the figure of a
    quantity that needs no second panel. ``lines``: (x, y, format or None, label) each,
    drawn in order; ``labels``: (x label, y label[, title]) with its legend
    (:func:`~pfem_skfem.harness.figures.labelled`, the title ``title_size`` points);
    ``size`` in inches. Returns ``path``."""
    from .harness.figures import labelled, pyplot, save_figure

    fig, ax = pyplot().subplots(figsize=size)
    for x, y, fmt, label in lines:
        ax.plot(x, y, *([fmt] if fmt else []), label=label)
    labelled(ax, *labels, title_size=title_size)
    save_figure(fig, path)
    return path


def render_png(vtu_path, png_path, scalars=None, *, cmap="viridis", clim=None,
               show_edges=True, window_size=(1200, 800), timeout=300, title=None,
               bar_title=None, axes="m"):
    """Render a VTU file to a PNG with pyvista, off-screen, in a subprocess.

    Parameters
    ----------
    vtu_path : mesh file (e.g. from :func:`pfem_skfem.io.write_vtu`).
    png_path : picture to write.
    scalars : name of the point or cell array to colour by (None: plain mesh).
    cmap, clim : colour map and its (min, max).
    show_edges : draw the element edges.
    window_size : (width, height) in pixels.
    timeout : seconds before the renderer is abandoned.
    title : a line at the top saying what the picture shows.
    bar_title : the title of the vertical colour bar (default ``scalars``), above it.
    axes : the units of the x and y axes drawn with ticks around the mesh ('m'), or None:
        no axes.

    Returns
    -------
    bool
        True if the PNG was written. False, with a warning that says why, if the
        renderer failed (e.g. no libEGL, which makes pyvista segfault).
    """
    png_path = Path(png_path)
    cmd = [sys.executable, "-m", "pfem_skfem.viz", str(vtu_path), str(png_path),
           "--cmap", cmap, "--window-size", str(window_size[0]), str(window_size[1])]
    if scalars is not None:
        cmd += ["--scalars", scalars]
    if clim is not None:
        cmd += ["--clim", str(float(clim[0])), str(float(clim[1]))]
    if not show_edges:
        cmd += ["--no-edges"]
    if title:
        cmd += ["--title", title]
    if bar_title:
        cmd += ["--bar-title", bar_title]
    cmd += ["--units", axes] if axes else ["--no-axes"]
    env = dict(os.environ, PYVISTA_OFF_SCREEN="true")
    # the subprocess imports this copy of the package, installed or not
    package_parent = str(Path(__file__).resolve().parents[1])
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [package_parent,
                                                      env.get("PYTHONPATH")]))
    if png_path.exists():
        png_path.unlink()
    try:
        proc = subprocess.run(cmd, env=env, capture_output=True, text=True,
                              timeout=timeout, stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        warnings.warn(f"pyvista rendering of {vtu_path} timed out after {timeout} s",
                      RuntimeWarning, stacklevel=2)
        return False
    if proc.returncode != 0 or not png_path.is_file():
        tail = "\n".join(proc.stderr.strip().splitlines()[-5:])
        why = (f"killed by signal {-proc.returncode} (missing libEGL? install Debian "
               f"libegl1 libgl1-mesa-dri)" if proc.returncode < 0
               else f"exit code {proc.returncode}")
        warnings.warn(f"pyvista rendering of {vtu_path} failed, {why}:\n{tail}",
                      RuntimeWarning, stacklevel=2)
        return False
    return True


def _render(vtu_path, png_path, scalars=None, cmap="viridis", clim=None,
            show_edges=True, window_size=(1200, 800), title=None, bar_title=None,
            axes=True, units="m"):
    """Render in this process (may segfault without libEGL: use render_png)."""
    import pyvista as pv

    pv.OFF_SCREEN = True
    grid = pv.read(vtu_path)
    if scalars is not None and scalars not in grid.array_names:
        raise ValueError(f"scalars {scalars!r} not in {vtu_path}; it has "
                         f"{grid.array_names}")
    plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
    plotter.set_background("white")
    plotter.add_mesh(grid, scalars=scalars, cmap=cmap, clim=clim,
                     show_edges=show_edges, edge_color="gray", line_width=0.5,
                     lighting=False,   # true colour-map colours on a flat mesh
                     show_scalar_bar=False)
    if scalars is not None:
        # vertical, at the right, its title above it: no title over the tick labels
        plotter.add_scalar_bar(title=(bar_title or scalars) + "\n", vertical=True,
                               position_x=0.86, position_y=0.12, width=0.06, height=0.7,
                               title_font_size=18, label_font_size=15, n_labels=5,
                               fmt="%.3g", color="black")
    if title:
        plotter.add_text(title, position="upper_edge", font_size=12, color="black")
    plotter.view_xy()
    plotter.enable_parallel_projection()
    if axes:
        plotter.show_bounds(xtitle=f"x [{units}]", ytitle=f"y [{units}]", ztitle="",
                            location="outer", ticks="outside", color="black",
                            font_size=16, show_zaxis=False, show_zlabels=False,
                            use_2d=True)
    plotter.reset_camera()
    plotter.camera.zoom(1.05 if axes else 1.2)   # room for the axes and the colour bar
    Path(png_path).parent.mkdir(parents=True, exist_ok=True)
    plotter.screenshot(str(png_path))
    plotter.close()


def main(argv=None):
    """Command line of the renderer subprocess; returns the exit code."""
    p = argparse.ArgumentParser(prog="python -m pfem_skfem.viz",
                                description="Render a VTU file to a PNG off-screen.")
    p.add_argument("vtu")
    p.add_argument("png")
    p.add_argument("--scalars", default=None)
    p.add_argument("--cmap", default="viridis")
    p.add_argument("--clim", type=float, nargs=2, default=None)
    p.add_argument("--window-size", type=int, nargs=2, default=(1200, 800))
    p.add_argument("--no-edges", action="store_true")
    p.add_argument("--title", default=None)
    p.add_argument("--bar-title", default=None)
    p.add_argument("--no-axes", action="store_true")
    p.add_argument("--units", default="m")
    args = p.parse_args(argv)
    try:
        _render(args.vtu, args.png, args.scalars, args.cmap, args.clim,
                not args.no_edges, tuple(args.window_size), args.title, args.bar_title,
                not args.no_axes, args.units)
    except (OSError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
