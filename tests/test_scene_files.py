"""Scene files: TOML round trip, located errors, and ``pfem-skfem run`` of the example."""
from dataclasses import fields, is_dataclass, replace
import json

import numpy as np
import pytest

from pfem_skfem import cli
from pfem_skfem.drivers import pfem_loop
from pfem_skfem.scene.config import PFEMConfig
from pfem_skfem.pfem.state import load_checkpoint
from pfem_skfem.materials import (ExponentialSoftening, FractureEnergy, LinearSoftening,
                                  NonlocalAverage, SofteningMohrCoulomb,
                                  SofteningMohrCoulombAxisymmetric, SofteningTresca,
                                  SofteningTrescaAxisymmetric)
from pfem_skfem.materials import (CohesiveTresca, DavisMohrCoulomb, Elastic, MuIRheology,
                                  MuIRheologyAxisymmetric, ZeroDilationDruckerPrager,
                                  ZeroDilationMohrCoulombAxisymmetric, BinghamFluid,
                                  BinghamFluidAxisymmetric, NewtonianFluid,
                                  NewtonianFluidAxisymmetric)
from pfem_skfem.pfem.remesh import AlphaMesh, QualityRemesh
from pfem_skfem.pfem.transfer import Interpolation
from pfem_skfem.problems.conic import SolverError
from pfem_skfem.problems.contact import LaggedFriction, RigidCircle, RigidPolyline, RigidSegment
from pfem_skfem.discretisation import ThetaMethod
from pfem_skfem.scene import (Body, ConstantVelocity, FunctionMotion, Geostatic, HalfPlane,
                              Outlet, Output, Phase, PiecewiseLinear, PolygonZone, Region,
                              Scene)
from pfem_skfem.scene import files
from pfem_skfem.scene.loads import SurfaceLoad
from pfem_skfem.scene.water import Drained, Water
from pfem_skfem.scene.files import (EXAMPLES, SceneFileError, example_text, key_lines,
                                    scene_from_toml, scene_to_toml)

from verification.granular_column_plane import granular_column

# every test of this file on one xdist worker: its module fixture is computed once
pytestmark = pytest.mark.xdist_group("test_scene_files")

EXAMPLE = example_text("column")
T_END = 1.6                                          # the example's


def rich_scene():
    """A scene using every kind of object a file can hold."""
    soil = CohesiveTresca(c=10.0, elastic=Elastic(1e4, 0.3))
    block = Region(((0, 0), (2, 0), (2, 1), (0, 1)), soil, 1.5, 0.25, lattice="triangular",
                   holes=(((0.5, 0.25), (0.75, 0.25), (0.75, 0.5)),),
                   stress=Geostatic(k0=0.5, top=1.0), name="block")
    top = tuple((x, 1.5) for x in np.linspace(2, 0, 9))      # a long list: one point a line
    cap = Region(((0, 1), (2, 1)) + top, soil, 2.0, 0.25, name="cap")
    bodies = (Body("base", RigidSegment((-5, 0), (5, 0), 0.3, sharp_ends=True)),
              Body("slope", RigidPolyline(((4, 3), (1, 3.5), (-2, 3)), 0.1, sharp_ends=True),
                   motion=ConstantVelocity((0.5, -0.25)), removed_at=2.0),
              Body("pipe", RigidCircle((1, 2.5), 0.4),
                   motion=PiecewiseLinear((0, 1, 3), ((0, 0), (0, -0.5), (1, -0.5))),
                   reference=(1.0, 2.0)))
    outlets = (Outlet("right", HalfPlane((3, 0), (1, 0))),
               Outlet("pit", PolygonZone(((-2, -1), (-1, -1), (-1, 0.5), (-2, 0.5)))))
    phases = (Phase(0.5, hold="free_surface", name="hold"), Phase(1.0, name="free"))
    config = PFEMConfig(theta=ThetaMethod(0.01, 0.5, 0.75), passes=3, contact=LaggedFriction(),
                        remesher=QualityRemesh(1.25), remesh_interval=2, stress_mapping="ida",
                        velocity=Interpolation(), search=1.5, solver="cvxpy-qoco", bulge=False,
                        refine_surface=0.0, volume_correction=True)
    return Scene((block, cap), bodies, outlets, phases, gravity=(0.1, -9.81), alpha=1.4,
                 adaptive_alpha=True, t_end=3.0, length=1.5, config=config,
                 output=Output("out dir \"q\"", 5, 7))


def _specs(spec, seen=None):
    """Every Spec reachable from ``spec`` (the classes a file can hold)."""
    seen = [] if seen is None else seen
    if spec not in seen:
        seen.append(spec)
        for kind in spec.keys.values():
            for sub in getattr(kind, "specs", {}).values():
                _specs(sub, seen)
            if hasattr(kind, "spec"):
                _specs(kind.spec, seen)
    return seen


def make_scene(name):
    """The scenes of the round trip: between them every type a file can name."""
    rich = rich_scene()
    if name == "rich":
        return rich
    if name == "davis":
        soil = DavisMohrCoulomb(c=1.0, phi=30.0, psi=10.0, k_min=0.01, elastic=Elastic(1e4, 0.3))
        return replace(rich, regions=tuple(replace(r, material=soil) for r in rich.regions),
                       t_end=None)
    if name == "axisymmetric":
        ep = Elastic(1e4, 0.3)
        soils = (ZeroDilationDruckerPrager(c=1.0, phi=30.0, k_min=0.01, match="plane-strain",
                                           elastic=ep),
                 ZeroDilationMohrCoulombAxisymmetric(c=0.0, phi=25.0, elastic=ep))
        return replace(rich, regions=tuple(replace(r, material=m)
                                           for r, m in zip(rich.regions, soils)),
                       geometry="axisymmetric")
    if name in ("softening", "softening_mc"):
        law = (LinearSoftening(30.0, 10.0, 0.2) if name == "softening"
               else ExponentialSoftening(30.0, 10.0, 0.5))
        soil = (SofteningTresca(law, Elastic(1e4, 0.45), FractureEnergy(0.1), eta=0.5)
                if name == "softening" else
                SofteningMohrCoulomb(law, Elastic(1e4, 0.3), NonlocalAverage(0.3), phi=20.0,
                                     k_min=0.01))
        return replace(rich, regions=(replace(rich.regions[0], material=soil),))
    if name in ("softening_axisymmetric", "softening_mc_axisymmetric"):
        law = LinearSoftening(30.0, 10.0, 0.2)
        soil = (SofteningTrescaAxisymmetric(law, Elastic(1e4, 0.45), FractureEnergy(0.1))
                if name == "softening_axisymmetric" else
                SofteningMohrCoulombAxisymmetric(law, Elastic(1e4, 0.3), NonlocalAverage(0.3),
                                                 phi=20.0, k_min=0.01))
        return replace(rich, regions=(replace(rich.regions[0], material=soil),),
                       geometry="axisymmetric")
    if name == "mu_i":
        soil = MuIRheology(mu_2=0.7, d=1e-3, lag="friction", elastic=Elastic(1e4, 0.3))
        return replace(rich, regions=tuple(replace(r, material=soil) for r in rich.regions))
    if name == "mu_i_axisymmetric":
        soil = MuIRheologyAxisymmetric(I_0=0.3, p_min=2e-3, lag="implicit")
        return replace(rich, regions=tuple(replace(r, material=soil) for r in rich.regions),
                       geometry="axisymmetric")
    if name in ("fluids", "fluids_axisymmetric"):
        axi = name == "fluids_axisymmetric"
        water = (NewtonianFluidAxisymmetric if axi else NewtonianFluid)(mu=1e-3)
        mud = (BinghamFluidAxisymmetric if axi else BinghamFluid)(tau_y=20.0, mu=2.5)
        return replace(rich, regions=tuple(replace(r, material=m)
                                           for r, m in zip(rich.regions, (water, mud))),
                       geometry="axisymmetric" if axi else "plane",
                       config=replace(rich.config, keep_area=True, keep_area_step=0.002,
                                      spread_mass=True,
                                      refine_interior=1.5,
                                      remesher=AlphaMesh(thin=0.4, keep_surface=True)))
    if name == "saturated":                           # a water table needs gravity along -y
        water = Water(k=1e-6, gamma_w=9.81, M=1e5, alpha=0.9, table=1.2,
                      drained=(Drained(HalfPlane((0, 1.4), (0, 1)), p=-5.0),
                               Drained(PolygonZone(((-1, -1), (3, -1), (3, 0.1), (-1, 0.1))))),
                      regions=(rich.regions[0].name,))          # the others free-draining
        return replace(rich, gravity=(0.0, -9.81), water=water,
                       config=replace(rich.config, theta=ThetaMethod(0.01, 1.0, 0.75)))
    if name == "loaded":          # a pressure on the cap's top, a traction on the hole's edges
        loads = (SurfaceLoad(HalfPlane((0, 1.49), (0, 1)), pressure=2.5, name="top"),
                 SurfaceLoad(PolygonZone(((0.4, 0.2), (0.8, 0.2), (0.8, 0.6), (0.4, 0.6))),
                             traction=(0.5, -1.0), name="hole"))
        return replace(rich, loads=loads)
    return scene_from_toml(EXAMPLE)


ROUND_TRIP = ("rich", "davis", "axisymmetric", "mu_i", "mu_i_axisymmetric", "fluids",
              "fluids_axisymmetric", "saturated", "softening", "softening_mc",
              "softening_axisymmetric", "softening_mc_axisymmetric", "loaded", "example")


@pytest.mark.parametrize("name", ROUND_TRIP)
def test_round_trip(name):
    scene = make_scene(name)
    text = scene_to_toml(scene)
    assert scene_from_toml(text) == scene
    assert scene_to_toml(scene_from_toml(text)) == text
    if name == "rich":
        assert "polygon = [\n    [0.0, 1.0],\n" in text


def test_the_round_trip_writes_every_type_of_the_schema():
    text = "".join(scene_to_toml(make_scene(name)) for name in ROUND_TRIP)
    names = [n for spec in _specs(files.SCHEMA) for kind in spec.keys.values()
             for n in getattr(kind, "specs", {})]
    assert len(names) == 50       # HalfPlane, PolygonZone thrice: outlets, drained, loads;
    #                               the laws and regularisations once per softening material
    for name in names:
        assert f'type = "{name}"' in text, name


@pytest.mark.parametrize("spec", _specs(files.SCHEMA), ids=lambda s: s.name)
def test_the_schema_has_every_field_of_each_class(spec):
    """A field added to a scene class must be added to its TOML form (else it is lost)."""
    if spec.name == "RigidSegment":                  # written as a RigidPolyline's two points
        assert set(spec.keys) == {"a", "b", "mu", "sharp_ends"}
        return
    assert is_dataclass(spec.cls)
    earlier = set(files._EARLIER_KEYS) if spec.name == "PFEMConfig" else set()
    assert set(spec.keys) == {f.name for f in fields(spec.cls)} | earlier


def test_the_example_is_the_column_of_the_column_script():
    scene = scene_from_toml(EXAMPLE)
    state0, column = granular_column(1, 8, t_end=T_END)
    assert scene.output == Output("column_run", 1, 50)
    assert replace(scene, output=column.output) == column
    state = scene.initial_state()
    assert state.n == 64
    for key in ("x", "h", "mass", "sigma_m", "region"):
        np.testing.assert_array_equal(getattr(state, key), getattr(state0, key), err_msg=key)


def test_key_lines_follow_tables_arrays_and_multiline_values():
    text = ('a = 1\n[[r]]\nname = "x"\np = [\n  [0, 1],  # a = 2\n  [1, "]"],\n]\n'
            '[r.m]\ntype = "T"\n[[r]]\ns = """\nq = 3\n"""\n"quoted.key" = 4\n[r.m]\n'
            'c.d = 5\n')
    lines = key_lines(text)
    assert lines[("a",)] == 1
    assert lines[("r", 0)] == 2 and lines[("r", 0, "p")] == 4
    assert lines[("r", 0, "m", "type")] == 9
    assert lines[("r", 1)] == 10 and lines[("r", 1, "s")] == 11
    assert ("r", 1, "q") not in lines                # inside the multi-line string
    assert lines[("r", 1, "quoted.key")] == 14
    assert lines[("r", 1, "m", "c", "d")] == 16


SECOND_REGION = """
[[regions]]
name = "second"
polygon = [[3.0, 0.0], [4.0, 0.0], [4.0, 1.0], [3.0, 1.0]]
h = 0.25
rho = 2.0
[regions.material]
type = "ZeroDilationMohrCoulomb"
phi = 95.0
"""
STONE = """
[[bodies]]
name = "stone"
[bodies.shape]
type = "RigidCircle"
center = [0.5, 0.5]
radius = 0.2
"""
PHASES = "\n[[phases]]\nuntil = 1.0\n[[phases]]\nuntil = 0.5\n"
FUNCTION = '\n[[bodies]]\nname = "f"\n[bodies.shape]\ntype = "RigidSegment"\n' \
           'a = [5.0, 0.0]\nb = [6.0, 0.0]\n[bodies.motion]\ntype = "FunctionMotion"\n'

WATER = '\n[water]\nk = 1e-6\nM = 0.0\n[[water.drained]]\np = -1.0\n'
# (what is changed, the text after the change, key path, the line's text, words of the message)
BAD_FILES = [
    ("unknown key", ("phi = 31.0 ", "phii = 31.0 "), "regions[0].material.phii",
     "phii = 31.0", "did you mean 'phi'"),
    ("missing key", ("rho = 2.0 ", "# rho"), "regions[0]", "[[regions]]",
     "missing key 'rho'"),
    ("wrong type", ("rho = 2.0 ", 'rho = "two" '), "regions[0].rho", 'rho = "two"',
     "must be a number"),
    ("not an integer", ("every = 1 ", "every = 1.5 "), "output.every", "every = 1.5",
     "must be an integer"),
    ("bad angle", ("phi = 31.0 ", "phi = 95.0 "), "regions[0].material.phi", "phi = 95.0",
     "friction angle"),
    ("second region", ("", SECOND_REGION), "regions[1].material.phi", "phi = 95.0",
     "friction angle"),
    ("negative output", ("every = 1 ", "every = -1 "), "output.every", "every = -1",
     ">= 0"),
    ("bad time step", ("dt = 0.0031", "dt = -0.0031"), "config.theta.dt", "dt = -0.0031",
     "time step"),
    ("bad lattice", ('lattice = "square"', 'lattice = "hex"'), "regions[0].lattice",
     'lattice = "hex"', "lattice must be one of"),
    ("unknown type", ('type = "AlphaMesh"', 'type = "Alpha"'), "config.remesher.type",
     'type = "Alpha"', "one of AlphaMesh, QualityRemesh"),
    ("missing type", ('type = "Fixed"', ''), "bodies[0].motion", "[bodies.motion]",
     "missing key 'type'"),
    ("short point", ("a = [-30.0, 0.0]", "a = [-30.0]"), "bodies[0].shape.a", "a = [-30.0]",
     "a point [x, y]"),
    ("self-intersecting polygon", ("[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]",
                                   "[[0.0, 0.0], [2.0, 0.0], [0.0, 1.0], [1.0, 2.0]]"),
     "regions[0].polygon", "polygon = [[0.0, 0.0], [2.0, 0.0]", "intersects itself"),
    ("particles inside a body", ("", STONE), "bodies[3]", '[[bodies]]\nname = "stone"',
     "lie inside it"),
    ("phases out of order", ("", PHASES), "phases", "[[phases]]\nuntil = 1.0", "increasing"),
    ("a Python function", ("", FUNCTION), "bodies[3].motion.type", 'type = "FunctionMotion"',
     "Python function"),
    ("a table, not an array", ("[[regions]]", "[regions]"), "regions", "[regions]",
     "must be an array of tables"),
    ("syntax", ("rho = 2.0 ", "rho = = 2.0 "), "", "rho = = 2.0", "TOML syntax"),
    ("a water's modulus", ("", WATER), "water.M", "M = 0.0",
     "M (Biot's modulus) must be > 0"),
    ("a negative permeability",
     ("", WATER.replace("M = 0.0", "k = -1.0").replace("k = 1e-6\n", "")), "water.k",
     "k = -1.0", "k (hydraulic conductivity) must be >= 0"),
]


@pytest.mark.parametrize("change, key, line_text, words", [c[1:] for c in BAD_FILES],
                         ids=[c[0] for c in BAD_FILES])
def test_a_bad_file_is_refused_naming_the_key_and_its_line(change, key, line_text, words):
    old, new = change
    assert old in EXAMPLE
    text = EXAMPLE.replace(old, new, 1) if old else EXAMPLE + new
    at = text.rindex(line_text) if not old else text.index(line_text)
    line = text[:at].count("\n") + 1
    with pytest.raises(SceneFileError) as err:
        scene_from_toml(text)
    assert (err.value.key, err.value.line) == (key, line), str(err.value)
    assert words in str(err.value)
    assert f"line {line}" in str(err.value) and key in str(err.value)


def test_a_function_motion_cannot_be_written():
    scene = rich_scene()
    body = Body("spin", RigidCircle((5, 5), 0.5), motion=lambda t: (np.sin(t), 0.0))
    assert isinstance(body.motion, FunctionMotion)
    with pytest.raises(ValueError, match=r"bodies\.motion: FunctionMotion is a Python function"):
        scene_to_toml(replace(scene, bodies=scene.bodies + (body,)))


# -- the command line -------------------------------------------------------------------------
TIMING = ("seconds", "t_", "t_compile", "t_conic")


def _physics(record):
    return {k: v for k, v in record.items() if not k.startswith(TIMING)}


def _run(*args):
    return cli.main(["run", *map(str, args), "--no-progress"])


@pytest.fixture(scope="module")
def example_run(tmp_path_factory):
    """The example written by --example and run for 7 steps (of the 501 to its t_end)."""
    tmp = tmp_path_factory.mktemp("example")
    assert cli.main(["run", "--example", "column", str(tmp / "column.toml")]) == 0
    assert _run(tmp / "column.toml", "--out", tmp / "full", "--steps", 7) == 0
    return tmp


def test_run_of_the_example_writes_series_history_scene_and_checkpoint(example_run, capsys):
    assert (example_run / "column.toml").read_text() == EXAMPLE
    out = example_run / "full"
    steps = 7
    records = json.loads((out / "history.json").read_text())
    assert [r["step"] for r in records] == list(range(1, steps + 1)) and steps == 7
    assert records[-1]["particles"] == 64 and records[-1]["status"]
    assert records[-1]["forces"]["base"][1] < 0       # the column presses on its base
    assert len(list(out.glob("scene_*.vtu"))) == steps + 1          # and t = 0
    assert (out / "scene.pvd").read_text().count("<DataSet") == steps + 1
    assert load_checkpoint(out / "checkpoint.npz").step == steps
    ran = files.load_scene(out / "scene.toml")
    assert ran.output.directory == str(out)
    assert replace(ran, output=Output("column_run", 1, 50)) == scene_from_toml(EXAMPLE)
    assert cli.main(["run", "--example", "column", str(example_run / "column.toml")]) == 2
    assert "not overwritten" in capsys.readouterr().err


def test_resume_continues_bit_identically(example_run):
    full, part = example_run / "full", example_run / "part"
    scene = example_run / "column.toml"
    assert _run(scene, "--out", part, "--steps", 3) == 0
    assert load_checkpoint(part / "checkpoint.npz").step == 3
    assert _run(scene, "--out", part, "--resume", "--steps", 7) == 0
    a, b = load_checkpoint(full / "checkpoint.npz"), load_checkpoint(part / "checkpoint.npz")
    assert a.step == b.step == 7
    for f in ("x", "v", "h", "mass", "sigma_m", "mesh_p", "mesh_t", "v_dofs", "sigma",
              "free_surface", "contact"):
        np.testing.assert_array_equal(getattr(a, f), getattr(b, f), err_msg=f)
    ha = json.loads((full / "history.json").read_text())
    hb = json.loads((part / "history.json").read_text())
    assert [_physics(r) for r in ha] == [_physics(r) for r in hb]
    assert (full / "scene_0006.vtu").read_bytes() == (part / "scene_0006.vtu").read_bytes()
    assert (full / "scene.pvd").read_text() == (part / "scene.pvd").read_text()


def test_a_bad_file_exits_non_zero_with_one_line(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text(EXAMPLE.replace("phi = 31.0 ", "phi = 95.0 "))
    assert _run(bad, "--out", tmp_path / "o") == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "bad.toml, line 36: regions[0].material.phi:" in err
    assert not (tmp_path / "o").exists()             # refused before any work


def test_resume_refuses_a_missing_checkpoint_or_another_scene(example_run, tmp_path, capsys):
    scene = example_run / "column.toml"
    assert _run(scene, "--out", tmp_path / "none", "--resume") == 2
    assert "nothing to resume" in capsys.readouterr().err
    other = tmp_path / "other.toml"
    other.write_text(EXAMPLE.replace("rho = 2.0 ", "rho = 3.0 "))
    assert _run(other, "--out", example_run / "full", "--resume") == 2
    assert "differs" in capsys.readouterr().err


def test_a_solver_failure_exits_3_and_keeps_the_last_step(tmp_path, monkeypatch, capsys):
    scene = tmp_path / "column.toml"
    scene.write_text(EXAMPLE)
    real, calls = pfem_loop.pfem_step, []

    def failing(state, sc):
        calls.append(state.step)
        if len(calls) == 2:
            raise SolverError("the conic solver did not converge", "MaxIterations")
        return real(state, sc)

    monkeypatch.setattr(pfem_loop, "pfem_step", failing)
    assert _run(scene, "--out", tmp_path / "o", "--steps", 3) == 3
    err = capsys.readouterr().err
    assert "solver failed" in err and "MaxIterations" in err and "step 2" in err
    assert load_checkpoint(tmp_path / "o" / "checkpoint.npz").step == 1
    assert len(json.loads((tmp_path / "o" / "history.json").read_text())) == 1


@pytest.mark.parametrize("t_end, dt, steps", [(0.02, 0.003194382824999699, 7),
                                              (0.1, 0.01, 10),  # 10.000000000000002
                                              (0.3, 0.1, 3),        # 2.9999999999999996
                                              (0.001, 0.01, 1)])
def test_steps_until_t_end_round_up_but_not_round_off(t_end, dt, steps):
    assert cli.steps_until(t_end, dt) == steps


def test_the_progress_bar_shows_the_steps_time_iterations_and_the_end():
    import io
    stream = io.StringIO()
    from pfem_skfem.harness.progress import StepBar
    bar = StepBar(5, 25, stream=stream)
    for i in range(1, 21):
        bar(i, 20, {"time": 0.01 * (5 + i), "iterations": 40})
    last = stream.getvalue().replace("\r", "\n").strip().splitlines()[-1]
    assert last.startswith("steps 6-25: 100%") and "20/20" in last
    assert "t = 0.25" in last and "it = 40" in last

@pytest.mark.parametrize("name", EXAMPLES)
def test_run_example_writes_each_example(name, tmp_path):
    """``pfem-skfem run --example NAME PATH`` writes the commented example, which loads."""
    path = tmp_path / f"{name}.toml"
    assert cli.main(["run", "--example", name, str(path)]) == 0
    assert scene_from_toml(path.read_text()) == scene_from_toml(example_text(name))


def test_a_scene_holding_numpy_scalars_writes_and_reads_back():
    """np.float64 == () is an empty array, not False: a scene built with numpy numbers (a
    dt from np.sqrt) once made scene_to_toml raise."""
    from pfem_skfem.discretisation import ThetaMethod
    rich = rich_scene()
    dt = np.float64(0.01) * np.sqrt(2.0)
    scene = replace(rich, config=replace(rich.config, theta=ThetaMethod(dt)),
                    alpha=np.float64(1.5))
    assert scene_from_toml(scene_to_toml(scene)) == scene


@pytest.mark.parametrize("keys, solver", [
    ('backend = "cvxpy"', "cvxpy"), ('form = "dual"', "clarabel-dual"),
    ('backend = "cvxpy"\nsolver = "qoco"', "cvxpy-qoco"),
    ('solver = "qoco"\nform = "dual"', "qoco-dual"),
    ('backend = "clarabel"\nsolver = "scs"', "cvxpy-scs"),
    ('backend = "cvxpy"\nsolver = "mosek"', "mosek")])
def test_an_earlier_file_s_backend_and_form_are_read_into_one_solver(keys, solver):
    """The keys that chose the step's solver before one name did are read into that name,
    with a warning that says what to write; a bad value is located as any other."""
    text = example_text("column").replace('solver = "clarabel"', keys)
    with pytest.warns(FutureWarning, match=f"solver = '{solver}'"):
        scene = scene_from_toml(text)
    assert scene.config.solver == solver
    with pytest.raises(SceneFileError, match="backend must be one of"):
        scene_from_toml(example_text("column").replace('solver = "clarabel"',
                                                       'backend = "mosek"'))

