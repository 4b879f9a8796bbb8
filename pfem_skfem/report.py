"""Backwards compatibility (issue 37): import from pfem_skfem.harness (report, options,
progress, sweeps, store, figures) and pfem_skfem.drivers.resumable (save_run, load_run,
sitting). This module re-exports them for one release."""
from .harness.figures import *            # noqa: F401,F403
from .harness.options import *            # noqa: F401,F403
from .harness.progress import *           # noqa: F401,F403
from .harness.report import *             # noqa: F401,F403
from .harness.store import *              # noqa: F401,F403
from .harness.sweeps import *             # noqa: F401,F403
from .harness.report import __doc__ as _contract   # noqa: F401
from .harness.progress import _CaseBars   # noqa: F401
from .harness.sweeps import _dask_client  # noqa: F401
from .drivers.resumable import load_run, save_run, sitting   # noqa: F401
