"""Command-line options of the verification scripts: the parser (``--quick``, the checks,
the output paths), the typed validators (an error names the option, its range and the
value given) and the option groups several scripts share, each option declared once with
its validator and help: :func:`material_options`, :func:`pfem_options` (PFEM numerics),
:func:`time_options`, :func:`adaptive_options` (a limit-bound loop), :func:`saturated_options`
(a saturated soil), :func:`softening_options` (a softening law), :func:`sweep_options`,
:func:`checkpoint_options`. One spelling (:data:`OPTION_SPELLING`): hyphens join the parts
of a name. The table of the validators is in :mod:`pfem_skfem.harness.report`.
"""
import argparse
import math
import re
from pathlib import Path


class _DefaultsOnce(argparse.ArgumentDefaultsHelpFormatter):
    """argparse's "(default: ...)", once: not where the help states its default itself,
    nor for a flag or an option whose default is None (it said "(default: False)")."""

    def _get_help_string(self, action):
        text = action.help or ""
        if "default" in text.lower() or action.default is None or action.default is False:
            return text
        return super()._get_help_string(action)


# options naming files or folders the run writes: checked when parsed (a usage error)
# rather than after the computation, which was lost (dest -> what it names)
OUTPUT_PATHS = {"json": "file", "outdir": "directory", "results_dir": "directory",
                "checkpoint_dir": "directory"}


#: the folder under ``--outdir`` of a ``--quick`` run's figures and VTU files
QUICK_SUBDIR = "quick"


class ScriptParser(argparse.ArgumentParser):
    """An argument parser whose ``parse_args`` applies ``--quick`` and the script's checks.

    With ``--quick``, each option named in ``quick`` takes its quick value unless
    the user gave it (even at its default value); then ``check(args)`` may
    return a message, reported as a usage error (exit code 2), and ``cones(args)`` names
    the cones the problems need with these options: a ``--solver`` without one of them is
    a usage error too. A ``--quick`` run's ``outdir`` is ``OUTDIR/quick``
    (:data:`QUICK_SUBDIR`), so that its figures and VTU never replace a full-size run's.
    """

    def __init__(self, description, quick=None, check=None, cones=None):
        super().__init__(description=description,
                         formatter_class=_DefaultsOnce)
        self.quick = dict(quick or {})
        self.check = check
        self.cones = cones

    def format_help(self):
        """The help, ``--quick`` saying its sizes as options (``--t-end 3.0``)."""
        actions = {a.dest: a for a in self._actions if a.option_strings}
        quick = actions.get("quick")

        def given(dest, value):                 # as on the command line
            flags = actions[dest].option_strings if dest in actions else [f"--{dest}"]
            if isinstance(value, bool):
                return flags[-1] if not value and len(flags) > 1 else flags[0]
            values = value if isinstance(value, (list, tuple)) else [value]
            return " ".join([flags[0], *map(str, values)])
        if quick is not None and self.quick and ":" not in quick.help:
            quick.help += ": " + ", ".join(given(k, v) for k, v in self.quick.items())
        return super().format_help()

    def parse_args(self, args=None, namespace=None):
        parsed = super().parse_args(args, namespace)
        if hasattr(parsed, "quiet"):             # progress is the default; --quiet turns it off
            parsed.progress = not parsed.quiet
        if parsed.quick and self.quick:
            # given on the command line, even at its default value, an option keeps it:
            # argparse leaves a name the namespace already holds (here unset) unless given
            unset = object()
            probe = super().parse_args(args, argparse.Namespace(**dict.fromkeys(self.quick,
                                                                                unset)))
            for key, value in self.quick.items():
                if getattr(probe, key) is unset:
                    setattr(parsed, key, value)
        message = self.check(parsed) if self.check else None
        if message:
            self.error(message)
        if self.cones is not None and getattr(parsed, "solver", None) in SOLVER_CONES:
            missing = sorted(set(self.cones(parsed)) - SOLVER_CONES[parsed.solver])
            if missing:
                able = [n for n in SOLVER_NAMES if not set(missing) - SOLVER_CONES[n]]
                self.error(f"argument --solver: {parsed.solver} has no {', '.join(missing)} "
                           f"cone, which the problems of these options have; use one of "
                           f"{', '.join(able)}")
        for dest, kind in OUTPUT_PATHS.items():
            value = getattr(parsed, dest, None)
            if value is None or (dest == "outdir" and value == self.get_default(dest)
                                 and getattr(parsed, "no_figures", False)
                                 and not getattr(parsed, "save_every", 0)):
                continue                         # the default outdir, unused
            from .store import output_path_problem      # numpy: not for --help and list
            problem = output_path_problem(value, kind)
            if problem:
                self.error(f"argument --{dest.replace('_', '-')}: {problem}")
        if getattr(parsed, "quick", False) and getattr(parsed, "outdir", None) is not None:
            # apart from a full-size run's, as its <case>.quick.json is: OUTDIR/quick/<case>/
            parsed.outdir = str(Path(parsed.outdir) / QUICK_SUBDIR)
        return parsed


def base_parser(description, quick=None, check=None, solver=True, cones=None):
    """An argument parser with the options every verification script shares.

    Parameters
    ----------
    description : str
        First line of ``--help``.
    quick : dict, optional
        Option (dest) name -> value for ``--quick``; applied only to the options the
        user did not give.
    check : callable, optional
        ``check(args) -> str or None``: a message for options that are
        inconsistent (a usage error), None when they are fine.
    solver : bool or str
        Add ``--solver`` (:func:`solver_option`), the conic solver of every problem the
        script solves; a str is appended to its help. False for a script that solves no
        conic problem (an option that did nothing would mislead).
    cones : callable, optional
        ``cones(args) -> set``: the cone kinds (:data:`SOLVER_CONES`) the script's
        problems have with these options (``{"exp"}`` for mu(I)'s implicit rate term); a
        ``--solver`` that lacks one is a usage error, before any work.

    Returns
    -------
    ScriptParser
    """
    p = ScriptParser(description, quick, check, cones)
    p.add_argument("--quick", action="store_true",
                   help="a small size that runs in seconds to a minute (tests, CI)")
    p.add_argument("--json", metavar="PATH", help="write the results as JSON to PATH")
    p.add_argument("--outdir", default="results",
                   help="figures and VTU: OUTDIR/<case>/, a --quick run's OUTDIR/quick/<case>/")
    p.add_argument("--no-figures", action="store_true", help="skip figures")
    p.add_argument("--quiet", action="store_true",
                   help="no progress bars on stderr (they are on by default)")
    p.add_argument("--progress", action="store_true",
                   help="progress bars on stderr (the default; kept for older command lines)")
    if solver:
        solver_option(p, why=solver if isinstance(solver, str) else "")
    return p


#: the names of :data:`pfem_skfem.problems.conic.SOLVERS` (the harness imports no science
#: module; tests/test_solvers.py checks that the two agree)
SOLVER_NAMES = ("clarabel", "qoco", "mosek", "scs", "ipm")
#: the names of problems.backends.STEP_SOLVERS (who states and solves a PFEM step), a copy for
#: the same reason (tests/test_solvers.py checks it)
STEP_SOLVER_NAMES = ("clarabel", "clarabel-dual", "qoco", "qoco-dual", "scs", "scs-dual",
                     "ipm", "cvxpy", "cvxpy-qoco", "cvxpy-scs", "cvxpy-ipm", "mosek")


def solver_option(parser, default="clarabel", why=""):
    """``--solver``: the conic solver of every problem the script solves
    (:func:`pfem_skfem.problems.conic.solve`: 'qoco' has no exponential cone, 'mosek'
    needs a licence; each refused, saying why, before any work); ``why`` is appended to
    the help."""
    parser.add_argument("--solver", choices=SOLVER_NAMES, default=default,
                        help="the conic solver of every problem solved (clarabel: the "
                             "library's default)" + (f"; {why}" if why else ""))
    return parser


def solver_keyword(args):
    """``--solver`` as a case's keyword: none for clarabel, the default, so that the results
    kept of earlier runs (``--results-dir``, keyed by the case's keywords) are found."""
    solver = getattr(args, "solver", "clarabel")
    return {} if solver == "clarabel" else {"solver": solver}


_ALL_CONES = frozenset({"zero", "nonneg", "soc", "exp", "psd", "power"})
#: the cone kinds each solver supports (``SolverBackend.cones`` of
#: :data:`pfem_skfem.problems.conic.SOLVERS`; tests/test_options.py checks that they agree)
SOLVER_CONES = {"clarabel": _ALL_CONES, "qoco": frozenset({"zero", "nonneg", "soc"}),
                "mosek": _ALL_CONES, "scs": _ALL_CONES,
                "ipm": frozenset({"zero", "nonneg", "soc"})}


class OptionError(ValueError):
    """An option found wrong only when used (an unreachable ``--scheduler``): a usage
    error of the script (:func:`script_main`), not a traceback."""


def in_range(low=-math.inf, high=math.inf, *, low_open=False, high_open=False,
             integer=False, unit="", what=None):
    """argparse type: a number in an interval, its error naming the range and the value.

    Parameters
    ----------
    low, high : float or None
        The ends of the interval (infinite or None: unbounded).
    low_open, high_open : bool
        Whether the ends are excluded.
    integer : bool
        Accept integers only.
    unit : str
        Shown after the interval ("degrees").
    what : str, optional
        The whole description ("a positive integer"); by default built from the rest.

    Returns
    -------
    callable
        ``parse(text) -> float or int``, raising ``argparse.ArgumentTypeError``; argparse
        prefixes its message with the option (``argument --phi: ...``).
    """
    low = -math.inf if low is None else low
    high = math.inf if high is None else high
    if what is None:
        kind = "an integer" if integer else "a number"
        if math.isinf(low) and math.isinf(high):
            what = kind
        elif math.isinf(high):
            what = f"{kind} {'>' if low_open else '>='} {low:g}"
        elif math.isinf(low):
            what = f"{kind} {'<' if high_open else '<='} {high:g}"
        else:
            what = (f"{kind} in {'(' if low_open else '['}{low:g}, {high:g}"
                    f"{')' if high_open else ']'}")
        what += f" {unit}" if unit else ""

    def parse(text):
        try:
            value = int(text) if integer else float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be {what}, got {text!r}") from None
        inside = (math.isfinite(value)
                  and (value > low if low_open else value >= low)
                  and (value < high if high_open else value <= high))
        if not inside:
            raise argparse.ArgumentTypeError(f"must be {what}, got {text!r}")
        return value
    parse.__name__ = what                       # argparse's name for the type
    parse.what = what
    parse.low, parse.high, parse.low_open, parse.high_open = low, high, low_open, high_open
    parse.integer = integer
    return parse


positive_float = in_range(0, low_open=True, what="a positive number")
nonnegative_float = in_range(0, what="a number >= 0")
positive_int = in_range(1, integer=True, what="a positive integer")
nonnegative_int = in_range(0, integer=True, what="an integer >= 0")
workers = in_range(1, integer=True, what="a number of workers >= 1")
friction_angle = in_range(0, 90, high_open=True, what="an angle in [0, 90) degrees")
slope_angle = in_range(0, 90, low_open=True, high_open=True, what="an angle in (0, 90) degrees")


def positive_angle(why):
    """argparse type: an angle in (0, 90) degrees, for a script whose physics or reference
    needs phi > 0; ``why`` is said in the message (``friction_angle`` allows 0, as TOML)."""
    return in_range(0, 90, low_open=True, high_open=True,
                    what=f"an angle in (0, 90) degrees ({why})")
#: the friction angle of a material without cohesion (c = 0), where phi = 0 has no strength
cohesionless_angle = positive_angle("c = 0: phi = 0 is a material without strength")
poisson_ratio = in_range(-1, 0.5, low_open=True, high_open=True,
                         what="a Poisson's ratio in (-1, 0.5)")
fraction = in_range(0, 1, what="a fraction in [0, 1]")
theta_weight = in_range(0.5, 1, what="a theta-method weight in [1/2, 1]")
element_count = in_range(4, integer=True, what="a number of elements >= 4")


SCHEDULER_SCHEMES = ("tcp", "tls", "inproc", "ucx", "ws", "wss")


def scheduler_address(text):
    """argparse type: a Dask scheduler's address, ``[tcp://]host:port`` (``--scheduler``).

    Only its form is checked here (no connection is made while options are parsed);
    :func:`run_cases` connects before any case runs, and an unreachable scheduler is an
    error naming ``--scheduler``.
    """
    match = re.fullmatch(r"(?:(?P<scheme>[a-z]+)://)?(?P<host>[^\s:/]+|\[[0-9a-fA-F:]+\])"
                         r":(?P<port>\d{1,5})", text.strip())
    if match is None or (match["scheme"] or "tcp") not in SCHEDULER_SCHEMES \
            or not 0 < int(match["port"]) < 65536:
        raise argparse.ArgumentTypeError(
            f"must be a Dask scheduler address [SCHEME://]HOST:PORT with SCHEME in "
            f"{', '.join(SCHEDULER_SCHEMES)} (e.g. tcp://127.0.0.1:8786), got {text!r}")
    return text.strip() if match["scheme"] else f"tcp://{text.strip()}"


scheduler_address.__name__ = "a Dask scheduler address"
scheduler_address.bad = ("x:0", "ftp://host:1")   # a bad port, a scheme not known


def sweep_options(parser, default_workers=None, what="the cases of the sweep"):
    """Add ``--workers``, ``--scheduler`` and ``--results-dir``, the options of
    :func:`run_cases`, to ``parser``.

    Parameters
    ----------
    parser : argparse.ArgumentParser
    default_workers : int, optional
        Default of ``--workers``; the number of cores when None.
    what : str
        What runs in parallel (the help text).
    """
    import os
    parser.add_argument("--workers", type=workers, default=default_workers or os.cpu_count() or 1,
                        help=f"local Dask worker processes (one thread each) for {what}; "
                             "1: one after the other in this process")
    parser.add_argument("--scheduler", type=scheduler_address, metavar="ADDRESS",
                        help=f"run {what} on the existing Dask cluster at ADDRESS "
                             "(tcp://host:port; its workers must import pfem_skfem); "
                             "--workers is then ignored")
    parser.add_argument("--results-dir", metavar="DIR", default=None,
                        help=f"keep the result of each of {what} in DIR as it finishes, and "
                             "take those already there instead of running them again (a "
                             "long study stopped and resumed; for the same code)")
    return parser


def checkpoint_options(parser, what="run", every=20, directory=True):
    """Add ``--checkpoint-dir DIR`` and ``--checkpoint-every K`` to ``parser``: each
    ``what`` saves itself in DIR (every K steps and at the end, :func:`checkpoint_path`)
    and goes on from its own checkpoint when the script is run again.

    With ``directory=False`` only ``--checkpoint-every`` (the script names the folder):
    0 (never) is then a choice, and ``every`` its default."""
    if not directory:
        parser.add_argument("--checkpoint-every", type=nonnegative_int, default=every,
                            help=f"save each {what}'s state every this many steps (0: never); "
                                 "a rerun resumes")
        return parser
    parser.add_argument("--checkpoint-dir", default=None,
                        help=f"save each {what}'s state in this directory (every "
                             f"--checkpoint-every steps and at the end) and go on from a "
                             f"{what}'s checkpoint if there is one: a long study can be "
                             f"stopped and resumed")
    parser.add_argument("--checkpoint-every", type=positive_int, default=every,
                        help=f"steps between a {what}'s checkpoints")
    return parser


# -- option groups: one declaration of each option several scripts share --------------------
doerfler_fraction = in_range(0, 1, low_open=True, what="a Doerfler fraction in (0, 1]")
on_off = ("on", "off")

#: the units of a script's quantities (``material_options(units=...)``): the thesis' kN, m,
#: t, s (stresses in kPa), SI (Pa), the trusses' N and mm, or none (a dimensionless study)
UNITS = {"kPa": dict(density="t/m3", stress="kPa", acceleration="m/s2", angle="deg",
                    unit_weight="kN/m3", compliance="1/kPa"),
         "Pa": dict(density="kg/m3", stress="Pa", acceleration="m/s2", angle="deg",
                   unit_weight="N/m3", compliance="1/Pa"),
         "N/mm2": dict(stress="N/mm^2", angle="deg"),
         None: dict(angle="deg")}


#: the spelling of every option of the scripts and of ``pfem-skfem`` (CONTRIBUTING.md): its
#: parts, words or a symbol and its subscript, joined by hyphens, never an underscore
#: (``--save-every``, ``--k-min``, ``--mu-2``, ``--T-end``); argparse's dest, the name the
#: code reads, has underscores in their place (``args.save_every``, ``args.mu_2``)
OPTION_SPELLING = re.compile(r"-[A-Za-z0-9]|--[A-Za-z0-9]+(-[A-Za-z0-9]+)*")


class opt:
    """One option of a group as a script declares it, where the script differs from the
    group: its ``default``, and the ``help`` (replacing the group's) or ``why`` (appended to
    it), the validator ``type``, ``nargs``, ``dest`` or ``metavar``.

    ``material_options(p, phi=opt([31.0], nargs="+", why="the thesis: 31 and 35"))``
    """

    def __init__(self, default, help=None, *, why=None, type=None, nargs=None, dest=None,
                 metavar=None):
        self.default, self.help, self.why, self.type = default, help, why, type
        self.nargs, self.dest, self.metavar = nargs, dest, metavar


class _Spec:
    """A group's option: its validator (or choices), its help and the quantity of its unit."""

    def __init__(self, type=None, help="", unit=None, choices=None):
        self.type, self.help, self.unit, self.choices = type, help, unit, choices


MATERIAL = {
    "rho": _Spec(positive_float, "density", "density"),
    "g": _Spec(positive_float, "gravity", "acceleration"),
    "E": _Spec(positive_float, "Young's modulus", "stress"),
    "G": _Spec(positive_float, "shear modulus G", "stress"),
    "nu": _Spec(poisson_ratio, "Poisson's ratio"),
    "c": _Spec(positive_float, "cohesion", "stress"),
    "su": _Spec(positive_float, "undrained shear strength Su", "stress"),
    "phi": _Spec(friction_angle, "friction angle", "angle"),
}

PFEM = {
    "h": _Spec(positive_float, "particle spacing [m]"),
    "alpha": _Spec(positive_float, "alpha-shape parameter"),
    "passes": _Spec(positive_int, "fixed-point passes on the mean stress a step"),
    "k_min": _Spec(positive_float, "least cone radius k_min"),
    "alpha_advected": _Spec(nonnegative_float,
                            "keep a Delaunay triangle inside the previous step's moved mesh "
                            "while its circumradius is at most this many h "
                            "(PFEMConfig.alpha_advected; 0: off, the plain alpha-shape)"),
    "volume_correction": _Spec(help="shift the moved particles so that every vertex patch "
                                    "keeps the volume their linearised motion states "
                                    "(PFEMConfig.volume_correction)", choices=on_off),
    "keep_area": _Spec(help="give back the area each remeshing adds (PFEMConfig.keep_area)",
                       choices=on_off),
    "keep_area_step": _Spec(nonnegative_float,
                            "the most of the domain's area keep_area gives back in one step, "
                            "a fraction (PFEMConfig.keep_area_step; 0: all at once)"),
    "keep_surface": _Spec(help="thin the free surface without moving it "
                               "(AlphaMesh(keep_surface))", choices=on_off),
    "spread_mass": _Spec(help="spread each region's mass over its particles by their lumped "
                              "areas at each remeshing (PFEMConfig.spread_mass)", choices=on_off),
    "thin": _Spec(in_range(0, 1, high_open=True),
                  "thin particles crowded closer than this x h at each remeshing "
                  "(AlphaMesh(thin); 0: none)"),
    "refine_interior": _Spec(nonnegative_float,
                             "an interior edge stretched longer than this x h gets its P2 "
                             "midside node as a new particle (PFEMConfig.refine_interior; 0: "
                             "never)"),
}

TIME = {
    "dt": _Spec(positive_float, "time step [s]"),
    "steps": _Spec(positive_int, "time steps"),
    "t_end": _Spec(positive_float, "end time [s]"),
    "theta1": _Spec(theta_weight, "theta1 of the theta-method (4.4)"),
    "theta2": _Spec(theta_weight, "theta2 of the theta-method (4.4)"),
    "settle": _Spec(nonnegative_float, "after the end time, go on for at most this long (same "
                                       "units) until at rest"),
    "save_every": _Spec(nonnegative_int, "write a VTU every this many steps (0: none)"),
}

ADAPTIVE = {
    "elements": _Spec(element_count, "elements of the first mesh"),
    "size": _Spec(positive_float, "element size of the first mesh"),
    "ratio": _Spec(positive_float, "h_max / h_min of the graded meshes"),
    "theta": _Spec(doerfler_fraction, "Doerfler fraction of the marking"),
    "rounds": _Spec(positive_int, "adaptive rounds"),
    "target_gap": _Spec(positive_float, "relative gap of the bounds to reach"),
    "target_elements": _Spec(element_count, "most elements to reach the target gap with"),
    "max_elements": _Spec(element_count, "largest adapted mesh"),
}

#: a saturated soil (Biot, Terzaghi): its water, its storage, its load, its time factor T_v
SATURATED = {
    "k": _Spec(positive_float, "hydraulic conductivity k [m/s]"),
    "gamma_w": _Spec(positive_float, "unit weight of water gamma_w", "unit_weight"),
    "M_inv": _Spec(nonnegative_float, "1/M, the storage (inverse Biot modulus)", "compliance"),
    "q": _Spec(positive_float, "load q", "stress"),
    "dTv": _Spec(positive_float, "time step in T_v"),
    "Tv_end": _Spec(positive_float, "the last T_v"),
}

#: a softening law (c_p to c_r over the plastic shear strain), its regularisation and the
#: steps of a softening run
SOFTENING = {
    "c_p": _Spec(positive_float, "peak strength c_p", "stress"),
    "c_r": _Spec(positive_float, "residual strength c_r", "stress"),
    "sensitivities": _Spec(in_range(1.0), "sensitivity S_t = c_p / c_r"),
    "H": _Spec(in_range(high=0, high_open=True, what="a negative number"),
               "softening modulus H = dc/dgamma^p", "stress"),
    "gamma_r": _Spec(positive_float, "plastic shear strain gamma_r at the residual strength"),
    "gamma_95": _Spec(positive_float, "gamma_95 of the exponential law"),
    "ell": _Spec(nonnegative_float, "regularisation length ell [m] (0: local softening)"),
    "ell_nonlocal": _Spec(positive_float, "length of the nonlocal average of gamma^p [m]"),
    "regularisation": _Spec(help="the softening material's regularisation: none (local "
                                 "softening), fracture-energy (FractureEnergy: the strain "
                                 "scale of a band ell thick) or nonlocal (NonlocalAverage: "
                                 "each step's Delta gamma^p averaged over ell)",
                            choices=("none", "fracture-energy", "nonlocal")),
    "epsilon": _Spec(in_range(0, 1, low_open=True, high_open=True),
                     "the weak zone starts this fraction down the law"),
    "max_drop": _Spec(in_range(0, 1, low_open=True),
                      "cap on the strength drop of an increment, / (c_p - c_r)"),
    "increments": _Spec(positive_int, "base increments (halved where the cap asks)"),
}

#: group name -> its options (the vocabulary: tests/test_options.py checks that no script
#: declares one of these names by hand unless it names another thing)
GROUPS = {"material": MATERIAL, "pfem": PFEM, "time": TIME, "adaptive": ADAPTIVE,
          "saturated": SATURATED, "softening": SOFTENING}


def option_name(name, prefix=""):
    """The option of keyword ``name`` (``save_every`` -> ``--save-every``; with a prefix,
    ``--mc-rounds``): its parts joined by hyphens (CONTRIBUTING.md)."""
    return "--" + "-".join(part for part in (prefix, name) if part).replace("_", "-")


def _declare(parser, group, given, *, prefix="", units="kPa", what=""):
    """Add the options ``given`` (keyword -> default or :class:`opt`) of ``group``."""
    specs = GROUPS[group]
    unknown = set(given) - set(specs)
    if unknown:
        raise TypeError(f"{group}_options has no option {', '.join(sorted(unknown))} "
                        f"(it has {', '.join(specs)})")
    unit_of = UNITS[units]
    for name, value in given.items():
        spec, o = specs[name], value if isinstance(value, opt) else opt(value)
        text = spec.help + (f" [{unit_of[spec.unit]}]" if spec.unit in unit_of else "")
        text = o.help if o.help is not None else text + (f" ({what})" if what else "")
        kwargs = dict(default=o.default, help=text + (f"; {o.why}" if o.why else ""))
        if spec.choices is not None:
            kwargs["choices"] = spec.choices
        else:
            kwargs["type"] = o.type or spec.type
        for key in ("nargs", "dest", "metavar"):
            if getattr(o, key) is not None:
                kwargs[key] = getattr(o, key)
        if prefix and "dest" not in kwargs:
            kwargs["dest"] = f"{prefix}_{name}".replace("-", "_")
        if o.dest is not None and o.metavar is None:        # --k-min K_MIN, not FLOOR
            kwargs["metavar"] = option_name(name, prefix)[2:].replace("-", "_").upper()
        parser.add_argument(option_name(name, prefix), **kwargs).option_group = group
    return parser


def material_options(parser, units="kPa", **options):
    """Add the material options given, each keyword the option's default or an :class:`opt`:
    ``--rho``, ``--g``, ``--E``, ``--nu``, ``--c``, ``--su``, ``--phi`` (:data:`MATERIAL`),
    their units those of ``units`` (:data:`UNITS`).

    ``material_options(p, rho=2.0, g=9.8, E=opt(None, "... (default: rigid-plastic)"))``
    """
    return _declare(parser, "material", options, units=units)


def pfem_options(parser, **options):
    """Add the PFEM numerics given (:data:`PFEM`): ``--h``, ``--alpha``, ``--passes``,
    ``--k-min``, ``--alpha-advected``, ``--volume-correction`` and the other switches of
    ``PFEMConfig`` and ``AlphaMesh``; each keyword the option's default or an :class:`opt`.
    An on/off switch is read as ``args.volume_correction == "on"``."""
    return _declare(parser, "pfem", options)


def time_options(parser, **options):
    """Add the time-stepping options given (:data:`TIME`): ``--dt``, ``--steps``,
    ``--t-end``, ``--theta1``, ``--theta2``, ``--settle``, ``--save-every``; each keyword the
    option's default or an :class:`opt`."""
    return _declare(parser, "time", options)


def adaptive_options(parser, prefix="", what="", **options):
    """Add the options of one adaptive limit-bound loop (:data:`ADAPTIVE`: ``elements``,
    ``size``, ``ratio``, ``theta``, ``rounds``, ``target_gap``, ``target_elements``,
    ``max_elements``), named ``--PREFIX-NAME`` (``adaptive_options(g, "mc", rounds=5)``:
    ``--mc-rounds``, ``args.mc_rounds``); ``what`` names the loop in the help."""
    return _declare(parser, "adaptive", options, prefix=prefix, what=what)


def saturated_options(parser, units="kPa", **options):
    """Add the options of a saturated soil given (:data:`SATURATED`): ``--k``, ``--gamma-w``,
    ``--M-inv``, the load ``--q`` and the time factor's ``--dTv``, ``--Tv-end``; each keyword
    the option's default or an :class:`opt`."""
    return _declare(parser, "saturated", options, units=units)


def softening_options(parser, units="kPa", **options):
    """Add the options of a softening law given (:data:`SOFTENING`): ``--c-p``, ``--c-r``,
    ``--sensitivities``, ``--H``, ``--gamma-r``, ``--gamma-95``, ``--ell``,
    ``--ell-nonlocal``, ``--regularisation``, ``--epsilon``, ``--max-drop``, ``--increments``; each keyword the
    option's default or an :class:`opt`."""
    return _declare(parser, "softening", options, units=units)


def bad_values(action):
    """Values the option of ``action`` refuses when parsed (a usage error naming it), known
    from its validator: below and above its range, a fraction for an integer, NaN; a name
    not among its choices; a word for a bare ``float``. Empty for a flag, a free string, or
    a validator whose refusals are not known here."""
    if action.nargs == 0 or not action.option_strings:
        return []
    if action.choices is not None:
        return ["none-of-these"]
    kind = action.type
    if hasattr(kind, "bad"):
        return list(kind.bad)
    if hasattr(kind, "low"):
        values = []
        if math.isfinite(kind.low):
            values.append(kind.low if kind.low_open else kind.low - 1)
        if math.isfinite(kind.high):
            values.append(kind.high if kind.high_open else kind.high + 1)
        finite = [v for v in (kind.low, kind.high) if math.isfinite(v)]
        if kind.integer:
            values.append(max(finite, default=0) + 0.5 if finite else 0.5)
        values = [f"{v:g}" for v in values] + ["nan"]
        return values
    if kind in (float, int):
        return ["x"]
    return []
