"""The backends of the dynamic step (4.23): who states it and who solves it, one choice.

A backend takes the scaled step (:class:`~pfem_skfem.problems.step_scaling.ScaledStep`),
the yield criterion and the terms (:mod:`~pfem_skfem.problems.step_terms`), states them and
answers a :class:`~pfem_skfem.problems.step_scaling.ScaledSolution`. Each declares what it
supports: its ``cones`` (the kinds of :data:`~pfem_skfem.problems.conic.CONE_KINDS`) and
``unsupported(criterion, terms, settings)``, asked before any work.

:data:`STEP_SOLVERS`, the one choice of a step's solver (``PFEMConfig.solver``,
``dynamic_increment(solver=...)``):

=================  ===========================================================
'clarabel'         the direct assembly, primal form, Clarabel (the default)
'clarabel-dual'    the direct assembly's dual (displacement) form, Clarabel
'qoco'             the direct assembly, primal form, QOCO
'qoco-dual'        the dual form, QOCO
'scs', 'scs-dual'  the direct assembly, SCS (first order), primal or dual form
'ipm'              the direct assembly, primal form, the package's interior point
                   (its Newton system reduced to the displacements: book, "How a
                   step is solved")
'cvxpy'            the cvxpy statement (the reference), Clarabel
'cvxpy-qoco'       the cvxpy statement, QOCO
'cvxpy-scs'        the cvxpy statement, SCS
'cvxpy-ipm'        the cvxpy statement, the package's interior point
'mosek'            the cvxpy statement, MOSEK (licensed)
=================  ===========================================================

A solver of :data:`~pfem_skfem.problems.conic.SOLVERS` keeps its name here (its direct
assembly where it has an engine), so one ``--solver`` serves the static problems (always
cvxpy) and the step alike.
"""
from ..conic import solver_backend
from .clarabel import ClarabelEngine
from .cvxpy_step import CvxpyStep
from .direct import DirectStep
from .ipm import IPMEngine
from .qoco import QOCOEngine
from .scs import SCSEngine

#: the engines of the direct assembly by name
ENGINES = {engine.name: engine for engine in (ClarabelEngine(), QOCOEngine(), SCSEngine(),
                                               IPMEngine())}

#: the step's solvers by name (module docstring)
STEP_SOLVERS = {
    "clarabel": DirectStep(ENGINES["clarabel"], "primal"),
    "clarabel-dual": DirectStep(ENGINES["clarabel"], "dual"),
    "qoco": DirectStep(ENGINES["qoco"], "primal"),
    "qoco-dual": DirectStep(ENGINES["qoco"], "dual"),
    "scs": DirectStep(ENGINES["scs"], "primal"),
    "scs-dual": DirectStep(ENGINES["scs"], "dual"),
    "ipm": DirectStep(ENGINES["ipm"], "primal"),
    "cvxpy": CvxpyStep("clarabel"),
    "cvxpy-qoco": CvxpyStep("qoco"),
    "cvxpy-scs": CvxpyStep("scs"),
    "cvxpy-ipm": CvxpyStep("ipm"),
    "mosek": CvxpyStep("mosek"),
}


def conic_solver(name):
    """The conic solver (a name of :data:`~pfem_skfem.problems.conic.SOLVERS`) behind the step
    solver ``name``."""
    backend = STEP_SOLVERS[name]
    return backend.solver if isinstance(backend, CvxpyStep) else backend.engine.name


def cvxpy_solver(conic):
    """The step solver that states the step in cvxpy and hands it to the conic solver
    ``conic`` (a name of :data:`~pfem_skfem.problems.conic.SOLVERS`): 'cvxpy', 'cvxpy-qoco',
    'cvxpy-scs', 'mosek'."""
    name = {"clarabel": "cvxpy", "mosek": "mosek"}.get(conic, f"cvxpy-{conic}")
    if name not in STEP_SOLVERS:
        raise ValueError(f"solver must be one of {('clarabel', 'qoco', 'mosek', 'scs', 'ipm')}, "
                         f"got {conic!r}")
    return name


def step_solver(name, criterion=None, terms=(), settings=None):
    """The backend named ``name`` (:data:`STEP_SOLVERS`), checked before any work: a
    ValueError for an unknown name, a cone the solver lacks (naming the term) or a step the
    backend cannot state; a SolverError (status 'unavailable') for a solver not installed
    or not licensed."""
    if name not in STEP_SOLVERS:
        raise ValueError(f"solver must be one of {tuple(STEP_SOLVERS)}, got {name!r}")
    backend = STEP_SOLVERS[name]
    for term in terms:
        missing = sorted(set(term.cones) - set(backend.cones))
        if missing:
            raise ValueError(f"solver {name!r} does not support the {', '.join(missing)} "
                             f"cone(s) of the step's {term.name} term; it supports "
                             f"{', '.join(sorted(backend.cones))} (use 'clarabel')")
    solver_backend(conic_solver(name))          # installed, licensed (its cones: above)
    why = backend.unsupported(criterion, terms, settings or {})
    if why is not None:
        raise ValueError(f"solver {name!r}: {why}")
    return backend
