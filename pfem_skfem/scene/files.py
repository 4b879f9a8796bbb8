"""Scenes as TOML files: :func:`scene_from_toml` and :func:`scene_to_toml`.

A scene file holds the same objects as a :class:`~pfem_skfem.scene.Scene` built in
Python, key for key: every table is one object, named by its class in ``type`` where
there is a choice (a material, a rigid shape, a motion, a zone, a contact rule, a
remesher, a velocity map), and its keys are the constructor's parameters. A key left
out takes the constructor's default (TOML has no null: a ``None`` is an omitted key)::

    t_end = 0.02
    gravity = [0.0, -9.8]

    [[regions]]
    name = "column"
    polygon = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    rho = 2.0
    h = 0.125
    [regions.material]
    type = "ZeroDilationMohrCoulomb"
    phi = 31.0
    [regions.stress]
    type = "Geostatic"

    [[bodies]]
    name = "base"
    [bodies.shape]
    type = "RigidSegment"            # or RigidPolyline (points), RigidCircle (center, radius)
    a = [-30.0, 0.0]
    b = [30.0, 0.0]
    mu = 0.6
    [bodies.motion]
    type = "PiecewiseLinear"         # or Fixed, ConstantVelocity (velocity)
    times = [0.0, 80.0, 280.0]
    displacements = [[0.0, 0.0], [0.0, -0.8], [2.0, -0.8]]

    [config.theta]
    dt = 0.003

A saturated scene (:mod:`pfem_skfem.scene.water`) has a ``[water]`` table (``k``,
``gamma_w``, ``M``, ``alpha``, ``table``, ``regions``: the saturated regions' names, the
others free-draining) and its drained faces as ``[[water.drained]]``
(``p``, and a ``[water.drained.zone]``; without a zone, the free surface);
surface loads (:mod:`pfem_skfem.scene.loads`) are ``[[loads]]`` (``name``, ``traction`` or
``pressure``, and a ``[loads.zone]``; constant in time: a ramp is Python only);

so that ``scene_from_toml(scene_to_toml(scene)) == scene`` (a
:class:`~pfem_skfem.scene.bodies.FunctionMotion`, a Python callable, has no TOML form).

Errors. The file is checked whole before any object is used: unknown keys, missing
keys, wrong types, and the scene classes' own checks (which raise ValueError naming
their parameter) all raise :class:`SceneFileError`, a ValueError naming the key path
(``regions[1].material.phi``) and the line. tomllib gives no positions, so
:func:`key_lines` finds them by scanning the text itself: it follows the table headers
(``[a.b]``, ``[[regions]]``, counting the array's elements) and the ``key = value``
lines, skipping values that run over several lines (arrays, multi-line strings) by
their brackets and quotes. A key inside an inline table or an element of an array is
reported at the line of the key that holds it.
"""
import difflib
import warnings
from dataclasses import MISSING, fields, is_dataclass
import json
import math
import re
import tomllib

from ..materials import (BinghamFluid, BinghamFluidAxisymmetric, NewtonianFluid,
                         NewtonianFluidAxisymmetric)
from ..materials import (CohesiveTresca, DavisMohrCoulomb, Elastic, MuIRheology,
                         MuIRheologyAxisymmetric, ZeroDilationDruckerPrager,
                         ZeroDilationMohrCoulomb, ZeroDilationMohrCoulombAxisymmetric)
from ..materials import (ExponentialSoftening, FractureEnergy, LinearSoftening,
                         NonlocalAverage, SofteningMohrCoulomb,
                         SofteningMohrCoulombAxisymmetric, SofteningTresca,
                         SofteningTrescaAxisymmetric)
from ..pfem.remesh import AlphaMesh, QualityRemesh
from ..pfem.transfer import Interpolation, L2Projection
from ..problems.contact import CoulombCones, LaggedFriction, RigidCircle, RigidPolyline, \
    RigidSegment
from ..discretisation.theta import ThetaMethod
from .bodies import Body, ConstantVelocity, Fixed, PiecewiseLinear
from .config import PFEMConfig, legacy_solver
from .outlets import HalfPlane, Outlet, PolygonZone
from .regions import Geostatic, Region
from .scene import Output, Phase, Scene
from .key_lines import key_lines
from .loads import SurfaceLoad
from .water import Drained, Water

__all__ = ["SceneFileError", "scene_from_toml", "scene_to_toml", "load_scene", "key_lines",
           "example_text", "EXAMPLES", "SCHEMA"]

EXAMPLES = ("column", "silo", "dam_break")


class SceneFileError(ValueError):
    """A bad scene file: ``key`` is the TOML key path, ``line`` its line (None if unknown),
    ``detail`` what is wrong, ``source`` the file's name (None for a text)."""

    def __init__(self, key, line, detail, source=None):
        where = ", ".join(w for w in (source, f"line {line}" if line else None) if w)
        super().__init__(f"{where + ': ' if where else ''}{key or '(top level)'}: {detail}")
        self.key, self.line, self.detail, self.source = key, line, detail, source


def key_path(path):
    """('regions', 1, 'material', 'phi') -> 'regions[1].material.phi'."""
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else p)
    return out


# -- value kinds: check a TOML value (load) and write one (dump) -------------------------
def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _float_text(x):
    x = float(x)
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return repr(x)                                   # shortest text that reads back exactly


class _Scalar:
    """A leaf value: ``check(v)`` says whether it is one, ``convert`` makes the Python value."""

    def __init__(self, what, check, convert, dump):
        self.what, self.check, self.convert, self.dump_value = what, check, convert, dump

    def load(self, value, path, ctx):
        if not self.check(value):
            ctx.fail(path, f"must be {self.what}, got {_shown(value)}")
        return self.convert(value)

    def dump(self, value):
        return self.dump_value(value)


class _List:
    """A list of ``item`` values (an empty list allowed unless ``least`` > 0)."""

    def __init__(self, item, what, least=0, exact=None):
        self.item, self.what, self.least, self.exact = item, what, least, exact

    def load(self, value, path, ctx):
        if not isinstance(value, list):
            ctx.fail(path, f"must be {self.what}, got {_shown(value)}")
        if self.exact is not None and len(value) != self.exact:
            ctx.fail(path, f"must be {self.what}, got {_shown(value)}")
        if len(value) < self.least:
            ctx.fail(path, f"must be {self.what} (at least {self.least}), got {_shown(value)}")
        return tuple(self.item.load(v, path + (i,), ctx) for i, v in enumerate(value))

    def dump(self, value):
        items = [self.item.dump(v) for v in value]
        one_line = "[" + ", ".join(items) + "]"
        if len(one_line) <= 80 or not isinstance(self.item, _List):
            return one_line
        return "[\n" + "".join(f"    {s},\n" for s in items) + "]"     # a point per line


NUMBER = _Scalar("a number", _is_number, float, _float_text)
INTEGER = _Scalar("an integer", lambda v: isinstance(v, int) and not isinstance(v, bool), int,
                  lambda v: str(int(v)))
BOOLEAN = _Scalar("true or false", lambda v: isinstance(v, bool), bool,
                  lambda v: "true" if v else "false")
STRING = _Scalar("a string", lambda v: isinstance(v, str), str,
                 lambda v: json.dumps(v, ensure_ascii=False))   # JSON's escapes are TOML's
POINT = _List(NUMBER, "a point [x, y]", exact=2)
NUMBERS = _List(NUMBER, "a list of numbers", least=1)
STRINGS = _List(STRING, "a list of strings", least=1)
POINTS = _List(POINT, "a list of points [[x, y], ...]", least=1)
POLYGONS = _List(POINTS, "a list of polygons [[[x, y], ...], ...]")


class _NoForm:
    """A key whose value is Python only (a function): refused when read and when written."""

    def __init__(self, reason):
        self.reason = reason

    def load(self, value, path, ctx):
        ctx.fail(path, self.reason)

    def dump(self, value):
        raise ValueError(self.reason)


def _shown(value):
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


# -- tables: one object each ----------------------------------------------------------------
class Spec:
    """The TOML form of one class: its keys and their kinds.

    ``build`` makes the object from the keys given (default: the class); ``required``
    defaults to the dataclass fields without a default; ``get`` reads a key's value
    from an object for writing; ``matches`` picks the spec of an object when writing.
    """

    def __init__(self, cls, keys, *, name=None, build=None, required=None, get=None,
                 matches=None):
        self.cls, self.keys, self.name = cls, keys, name or cls.__name__
        self.build = build or cls
        if required is None:
            required = [f.name for f in fields(cls) if f.default is MISSING
                        and f.default_factory is MISSING]
        self.required = tuple(required)
        self.get = get or (lambda obj, key: getattr(obj, key))
        self.matches = matches or (lambda obj: type(obj) is cls)

    def default(self, key):
        """The constructor's default of ``key`` (MISSING if it has none)."""
        if not is_dataclass(self.cls):
            return MISSING
        for f in fields(self.cls):
            if f.name == key:
                return f.default if f.default_factory is MISSING else f.default_factory()
        return MISSING

    def load(self, table, path, ctx, typed=False):
        if not isinstance(table, dict):
            ctx.fail(path, f"must be a table ({self.name}), got {_shown(table)}")
        allowed = set(self.keys) | ({"type"} if typed else set())
        for key in table:
            if key not in allowed:
                close = difflib.get_close_matches(key, sorted(allowed), n=1)
                hint = f"; did you mean {close[0]!r}?" if close else ""
                ctx.fail(path + (key,), f"unknown key for {self.name} (its keys: "
                         f"{', '.join(self.keys) or 'none'}){hint}")
        for key in self.required:
            if key not in table:
                ctx.fail(path, f"missing key {key!r} ({self.name} needs "
                         f"{', '.join(self.required)})")
        kwargs = {key: self.keys[key].load(table[key], path + (key,), ctx)
                  for key in self.keys if key in table}
        try:
            return self.build(**kwargs)
        except ValueError as err:                    # the class's own check, located
            ctx.fail(ctx.locate(str(err), path, table), str(err))

    def dump(self, obj, header, out, array=False, typed=False):
        nested = []
        body = [f"type = {STRING.dump(self.name)}"] if typed else []
        for key, kind in self.keys.items():
            value = self.get(obj, key)
            default = self.default(key)
            if value is None:
                if default not in (None, MISSING):   # a None TOML cannot say apart from the default
                    raise ValueError(f"{header}.{key}: None has no TOML form")
                continue
            if isinstance(kind, (OneOf, Table, Tables)):
                nested.append((key, kind, value))
            elif not (isinstance(value, tuple) and value == () and default == ()):
                # (a numpy scalar == () is an empty array, not False)
                try:
                    body.append(f"{key} = {kind.dump(value)}")
                except ValueError as err:            # a value with no TOML form
                    raise ValueError(f"{header}.{key}: {err}") from None
        if header:
            out.append("")
            out.append(f"[[{header}]]" if array else f"[{header}]")
        out.extend(body)
        for key, kind, value in nested:
            kind.dump(value, f"{header}.{key}" if header else key, out)


class Table:
    """A nested table of one fixed class (no ``type`` key)."""

    def __init__(self, spec):
        self.spec = spec

    def load(self, value, path, ctx):
        return self.spec.load(value, path, ctx)

    def dump(self, value, header, out):
        self.spec.dump(value, header, out)


class Tables:
    """An array of tables ``[[key]]``, each one object of ``spec``."""

    def __init__(self, spec):
        self.spec = spec

    def load(self, value, path, ctx):
        if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
            ctx.fail(path, f"must be an array of tables ([[{path[-1]}]] ...), got "
                     f"{_shown(value)}")
        return tuple(self.spec.load(v, path + (i,), ctx) for i, v in enumerate(value))

    def dump(self, value, header, out):
        for obj in value:
            self.spec.dump(obj, header, out, array=True)


class OneOf:
    """A table whose ``type`` names its class among ``specs``; ``refused`` maps type names
    that have no TOML form to the reason."""

    def __init__(self, *specs, refused=None):
        self.specs = {s.name: s for s in specs}
        self.refused = refused or {}

    def load(self, value, path, ctx):
        names = ", ".join(self.specs)
        if not isinstance(value, dict):
            ctx.fail(path, f"must be a table with a type (one of {names}), got {_shown(value)}")
        if "type" not in value:
            ctx.fail(path, f"missing key 'type' (one of {names})")
        kind = value["type"]
        if kind in self.refused:
            ctx.fail(path + ("type",), self.refused[kind])
        if kind not in self.specs:
            ctx.fail(path + ("type",), f"must be one of {names}, got {_shown(kind)}")
        return self.specs[kind].load(value, path, ctx, typed=True)

    def dump(self, value, header, out):
        for spec in self.specs.values():
            if spec.matches(value):
                return spec.dump(value, header, out, typed=True)
        name = type(value).__name__
        if name in self.refused:
            raise ValueError(f"{header}: {self.refused[name]}")
        raise ValueError(f"{header}: {name} has no TOML form (one of {', '.join(self.specs)})")


# -- the schema: every scene class and its keys ---------------------------------------------
ELASTIC = Table(Spec(Elastic, {"E": NUMBER, "nu": NUMBER}))
SOFTENING_LAW = OneOf(
    Spec(LinearSoftening, {"c_p": NUMBER, "c_r": NUMBER, "gamma_r": NUMBER}),
    Spec(ExponentialSoftening, {"c_p": NUMBER, "c_r": NUMBER, "gamma_95": NUMBER}))
REGULARISATION = OneOf(Spec(FractureEnergy, {"length": NUMBER}),
                       Spec(NonlocalAverage, {"length": NUMBER}))
MATERIAL = OneOf(
    Spec(ZeroDilationMohrCoulomb, {"c": NUMBER, "phi": NUMBER, "k_min": NUMBER,
                                   "elastic": ELASTIC}),
    Spec(DavisMohrCoulomb, {"c": NUMBER, "phi": NUMBER, "psi": NUMBER, "k_min": NUMBER,
                            "elastic": ELASTIC}),
    Spec(CohesiveTresca, {"c": NUMBER, "elastic": ELASTIC}),
    Spec(ZeroDilationDruckerPrager, {"c": NUMBER, "phi": NUMBER, "k_min": NUMBER,
                                     "match": STRING, "elastic": ELASTIC}),
    Spec(ZeroDilationMohrCoulombAxisymmetric, {"c": NUMBER, "phi": NUMBER, "k_min": NUMBER,
                                               "elastic": ELASTIC}),
    *(Spec(cls, {"mu_s": NUMBER, "mu_2": NUMBER, "I_0": NUMBER, "d": NUMBER, "rho_s": NUMBER,
                 "p_min": NUMBER, "k_min": NUMBER, "elastic": ELASTIC, "lag": STRING})
      for cls in (MuIRheology, MuIRheologyAxisymmetric)),
    *(Spec(cls, {"mu": NUMBER}) for cls in (NewtonianFluid, NewtonianFluidAxisymmetric)),
    *(Spec(cls, {"law": SOFTENING_LAW, "elastic": ELASTIC, "regularisation": REGULARISATION,
                 "eta": NUMBER}) for cls in (SofteningTresca, SofteningTrescaAxisymmetric)),
    *(Spec(cls, {"law": SOFTENING_LAW, "elastic": ELASTIC, "regularisation": REGULARISATION,
                 "eta": NUMBER, "phi": NUMBER, "k_min": NUMBER})
      for cls in (SofteningMohrCoulomb, SofteningMohrCoulombAxisymmetric)),
    *(Spec(cls, {"tau_y": NUMBER, "mu": NUMBER})
      for cls in (BinghamFluid, BinghamFluidAxisymmetric)),
    refused={"RegionCones": "RegionCones is the step's combination of the regions' "
             "materials, made by the engine: give each region its own material",
             "SofteningStep": "SofteningStep is a softening material bound to one step's "
             "gamma^p, made by the engine: give the region a SofteningTresca or a "
             "SofteningMohrCoulomb"})
STRESS = OneOf(Spec(Geostatic, {"k0": NUMBER, "top": NUMBER}))
REGION = Spec(Region, {"name": STRING, "polygon": POINTS, "holes": POLYGONS, "lattice": STRING,
                       "h": NUMBER, "rho": NUMBER, "material": MATERIAL, "stress": STRESS})
SHAPE = OneOf(
    # a two-point polyline is written as the segment it is
    Spec(RigidPolyline, {"a": POINT, "b": POINT, "mu": NUMBER, "sharp_ends": BOOLEAN},
         name="RigidSegment", build=RigidSegment, required=("a", "b"),
         get=lambda s, k: getattr(s, k) if k in ("mu", "sharp_ends")
         else s.points[0 if k == "a" else 1],
         matches=lambda s: type(s) is RigidPolyline and len(s.points) == 2),
    Spec(RigidPolyline, {"points": POINTS, "mu": NUMBER, "sharp_ends": BOOLEAN}),
    Spec(RigidCircle, {"center": POINT, "radius": NUMBER, "mu": NUMBER}))
MOTION = OneOf(
    Spec(Fixed, {}),
    Spec(ConstantVelocity, {"velocity": POINT}),
    Spec(PiecewiseLinear, {"times": NUMBERS, "displacements": POINTS}),
    refused={"FunctionMotion": "FunctionMotion is a Python function of time, which a TOML "
             "file cannot hold: use Fixed, ConstantVelocity or PiecewiseLinear (or build "
             "the scene in Python)"})
BODY = Spec(Body, {"name": STRING, "shape": SHAPE, "motion": MOTION, "removed_at": NUMBER,
                   "reference": POINT})
ZONE = OneOf(Spec(HalfPlane, {"point": POINT, "normal": POINT}),
             Spec(PolygonZone, {"vertices": POINTS}))
OUTLET = Spec(Outlet, {"name": STRING, "zone": ZONE})
DRAINED = Spec(Drained, {"zone": ZONE, "p": NUMBER})
WATER = Spec(Water, {"k": NUMBER, "gamma_w": NUMBER, "M": NUMBER, "alpha": NUMBER,
                     "table": NUMBER, "drained": Tables(DRAINED), "regions": STRINGS})
LOAD = Spec(SurfaceLoad, {"name": STRING, "zone": ZONE, "traction": POINT, "pressure": NUMBER,
                          "ramp": _NoForm("ramp is a Python function of time, which a TOML "
                                          "file cannot hold: give a constant traction or "
                                          "pressure (or build the scene in Python)")})
PHASE = Spec(Phase, {"name": STRING, "until": NUMBER, "hold": STRING})
#: keys of [config] that earlier scene files used for the step's solver (PFEMConfig.solver)
_EARLIER_KEYS = ("backend", "form")


def _config(**keys):
    """PFEMConfig of a [config] table; an earlier file's ``backend`` and ``form`` (beside
    ``solver``) are read into the one ``solver`` name they chose, with a FutureWarning that
    says what to write instead."""
    if any(key in keys for key in _EARLIER_KEYS):
        earlier = {key: keys.pop(key) for key in ("backend", "solver", "form") if key in keys}
        keys["solver"] = legacy_solver(**earlier)
        warnings.warn(f"config: {', '.join(f'{k} = {v!r}' for k, v in earlier.items())} read as "
                      f"solver = {keys['solver']!r} (one key now says who states and solves "
                      "the step; write that)", FutureWarning, stacklevel=2)
    return PFEMConfig(**keys)


CONFIG = Spec(PFEMConfig, {
    "theta": Table(Spec(ThetaMethod, {"dt": NUMBER, "theta1": NUMBER, "theta2": NUMBER})),
    "passes": INTEGER, "pass_tolerance": NUMBER,
    "contact": OneOf(Spec(CoulombCones, {}), Spec(LaggedFriction, {})),
    "remesher": OneOf(Spec(AlphaMesh, {"thin": NUMBER, "keep_surface": BOOLEAN}),
                      Spec(QualityRemesh, {"size": NUMBER})),
    "remesh_interval": INTEGER, "stress_mapping": STRING,
    "velocity": OneOf(Spec(L2Projection, {}), Spec(Interpolation, {})),
    "search": NUMBER, "solver": STRING, "backend": STRING, "form": STRING,
    "bulge": BOOLEAN,
    "refine_surface": NUMBER, "refine_interior": NUMBER, "volume_correction": BOOLEAN,
    "keep_area": BOOLEAN, "keep_area_step": NUMBER, "spread_mass": BOOLEAN,
    "alpha_advected": NUMBER}, build=lambda **keys: _config(**keys),
    get=lambda config, key: None if key in _EARLIER_KEYS else getattr(config, key))
OUTPUT = Spec(Output, {"directory": STRING, "every": INTEGER, "checkpoint_every": INTEGER})
SCHEMA = Spec(Scene, {
    "t_end": NUMBER, "gravity": POINT, "alpha": NUMBER, "adaptive_alpha": BOOLEAN,
    "length": NUMBER, "regions": Tables(REGION), "bodies": Tables(BODY),
    "outlets": Tables(OUTLET), "phases": Tables(PHASE), "config": Table(CONFIG),
    "output": Table(OUTPUT), "geometry": STRING, "water": Table(WATER), "loads": Tables(LOAD),
    "max_particles": INTEGER})


# -- loading --------------------------------------------------------------------------------
class _Context:
    """Where the keys are in the text, for the errors."""

    def __init__(self, text):
        self.lines = key_lines(text)

    def line(self, path):
        while path and path not in self.lines:       # inline tables, array items: their key
            path = path[:-1]
        return self.lines.get(path) if path else None

    def fail(self, path, message):
        raise SceneFileError(key_path(path), self.line(path), message)

    def locate(self, message, path, table):
        """The key a constructor's message is about: a named entry ("body 'wall'", "hole 2")
        or a key of ``table`` named in it (the first one named); else the table itself."""
        hits = []
        for key, value in table.items():
            if isinstance(value, list) and key.endswith("s"):
                singular = {"bodies": "body"}.get(key, key[:-1])
                for i, item in enumerate(value):
                    name = item.get("name") if isinstance(item, dict) else None
                    if name is not None:
                        m = re.search(rf"\b{singular} {re.escape(repr(name))}", message)
                        if m:
                            hits.append((m.start(), path + (key, i)))
                for m in re.finditer(rf"\b{singular} (\d+)\b", message):
                    if int(m.group(1)) < len(value):
                        hits.append((m.start(), path + (key, int(m.group(1)))))
        plain = re.sub(r"'[^']*'", "''", message)    # names are not keys
        for key in table:
            m = re.search(rf"(?<!\w){re.escape(key)}(?!\w)", plain)
            if m:
                hits.append((m.start(), path + (key,)))
        return min(hits)[1] if hits else path


def scene_from_toml(text):
    """The :class:`~pfem_skfem.scene.Scene` a TOML text describes.

    Parameters
    ----------
    text : str, the scene file (see the module docstring for its form).

    Returns
    -------
    Scene

    Raises
    ------
    SceneFileError (a ValueError) naming the key path and its line: a TOML syntax error,
    an unknown, missing or mistyped key, or a value the scene's classes refuse.
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        m = re.search(r"line (\d+)", str(err))
        raise SceneFileError("", int(m.group(1)) if m else None, f"TOML syntax: {err}") from None
    return SCHEMA.load(data, (), _Context(text))


def load_scene(path):
    """The scene of the TOML file at ``path``; errors name the file, key and line."""
    from pathlib import Path
    try:
        return scene_from_toml(Path(path).read_text())
    except SceneFileError as err:
        raise SceneFileError(err.key, err.line, err.detail, source=str(path)) from None


# -- writing --------------------------------------------------------------------------------
def scene_to_toml(scene, header=None):
    """The TOML text of ``scene`` (every value written, None as an omitted key), such that
    ``scene_from_toml(scene_to_toml(scene)) == scene``.

    Parameters
    ----------
    scene : Scene.
    header : optional comment put at the top (each line gets a ``#`` and a space).

    Raises
    ------
    ValueError naming the key for what TOML cannot hold (a FunctionMotion).
    """
    out = [f"# {line}".rstrip() for line in header.splitlines()] if header else []
    SCHEMA.dump(scene, "", out)
    return "\n".join(out).lstrip("\n") + "\n"


def example_text(name):
    """The commented example scene file ``name`` (one of :data:`EXAMPLES`)."""
    if name not in EXAMPLES:
        raise ValueError(f"no example {name!r}; examples: {', '.join(EXAMPLES)}")
    from importlib.resources import files
    return (files("pfem_skfem.scene") / "examples" / f"{name}.toml").read_text()
