"""Matplotlib pictures of the PFEM geometry stages (cloud, alpha-shape, meshes)."""
import numpy as np


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
    _frame(ax, p, title)


def plot_mesh(ax, mesh, *, title=None, particle=None, color="#8fb3d0"):
    """Triangles of a MeshTri; vertices that are particles black, added nodes orange."""
    from matplotlib.collections import PolyCollection

    p = mesh.p.T
    ax.add_collection(PolyCollection(p[mesh.t.T], facecolor="#eef4fa", edgecolor=color,
                                     linewidth=0.4))
    if particle is not None:
        ax.plot(*p[particle >= 0].T, "k.", ms=2)
        ax.plot(*p[particle < 0].T, ".", color="#e67e22", ms=3)
    _frame(ax, p, title)


def plot_points(ax, points, *, title=None, point_size=4):
    """A bare particle cloud."""
    ax.plot(*np.asarray(points).T, "k.", ms=point_size)
    _frame(ax, np.asarray(points), title)


def _frame(ax, p, title):
    lo, hi = p.min(axis=0), p.max(axis=0)
    pad = 0.03 * max(hi - lo) if len(p) else 1.0
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xticks([]), ax.set_yticks([])
    if title:
        ax.set_title(title, fontsize=10)
