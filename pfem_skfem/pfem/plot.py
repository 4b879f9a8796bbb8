"""Backwards compatibility (issue 37): import from pfem_skfem.viz (``plot_mesh`` of this
module is :func:`pfem_skfem.viz.plot_particle_mesh`)."""
from ..viz import plot_alpha_shape, plot_points  # noqa: F401
from ..viz import plot_particle_mesh as plot_mesh  # noqa: F401
