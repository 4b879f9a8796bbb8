"""Faults and bad input of ``pfem-skfem run`` (issue 56, item 9; ../shared/RELIABILITY.md
R1-R9, R12, R13): each ends in a clean message and an exit code, never a traceback, and
never costs the user a file or a folder."""
import json

import numpy as np
import pytest

from pfem_skfem import cli
from pfem_skfem.scene.files import example_text


def _scene(tmp_path, name, *edits, file=None):
    """The example ``name`` with each (old, new) text replaced, written to tmp_path."""
    text = example_text(name)
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / (file or f"{name}.toml")
    path.write_text(text)
    return path


def _run(path, *args, out=None):
    out = path.with_suffix("") if out is None else out
    return cli.main(["run", str(path), "--out", str(out), "--no-progress", *map(str, args)])


def test_a_density_that_overflows_the_data_stops_with_exit_3_and_the_initial_state_kept(
        tmp_path, capsys):
    # R1: rho = 1e300 made the step's data non-finite; the check's ValueError escaped the
    # run loop as a traceback with no checkpoint (before the check: exit 3)
    path = _scene(tmp_path, "column", ("rho = 2.0 ", "rho = 1e300 "))
    assert _run(path, "--steps", 3, "--every", 0) == 3
    err = capsys.readouterr().err
    assert "non-finite" in err and "status NonFiniteData" in err and "in step 1;" in err
    assert "Traceback" not in err
    assert (path.with_suffix("") / "checkpoint.npz").is_file()   # step 0, resumable


def test_every_particle_leaving_in_step_1_while_vtus_are_written_ends_cleanly(
        tmp_path, capsys):
    # R2: the base removed at t = 0, gravity -1e7 and an outlet 1 cm below: every particle
    # leaves in step 1; the VTU of that step raised an IndexError (io.step_fields)
    path = _scene(tmp_path, "column",
                  ("gravity = [0.0, -9.8]", "gravity = [0.0, -1e7]"),
                  ('name = "base" ', 'name = "base"\nremoved_at = 0.0\n#'),
                  ("# -- the numerical choices",
                   '[[outlets]]\nname = "drain"\n[outlets.zone]\ntype = "HalfPlane"\n'
                   'point = [0.0, -0.01]\nnormal = [0.0, -1.0]\n\n# -- the numerical choices'))
    assert _run(path, "--steps", 3, "--every", 1) == 0
    out, err = capsys.readouterr()
    assert "Traceback" not in err and "no material left" in out
    run = path.with_suffix("")
    assert (run / "scene_0001.vtu").is_file() and (run / "checkpoint.npz").is_file()


def test_a_disk_full_before_the_first_checkpoint_says_nothing_can_be_resumed_and_a_rerun_starts_again(
        tmp_path, capsys, monkeypatch):
    # R4/R5: every checkpoint fails (ENOSPC) and step 3's VTU too; the message claimed
    # "--resume continues from step 2", and the folder was refused by --resume and by a
    # plain rerun alike
    from pfem_skfem import io, runfolder
    path = _scene(tmp_path, "column")

    def full(*args, **kwargs):
        raise OSError(28, "No space left on device")

    write, calls = io.TimeSeries.write, []

    def write_until_full(self, *args, **kwargs):
        calls.append(1)                        # call 1: the t = 0 frame; k + 1: step k's
        if len(calls) == 4:
            full()
        return write(self, *args, **kwargs)

    with monkeypatch.context() as patch:
        patch.setattr(runfolder, "save_checkpoint", full)
        patch.setattr(io.TimeSeries, "write", write_until_full)
        assert _run(path, "--steps", 5, "--every", 1) == 3
    err = capsys.readouterr().err
    assert "in step 3; steps 1-2 were computed but no checkpoint could be written" in err
    assert "run the same command again (without --resume)" in err
    assert "--resume continues" not in err
    run = path.with_suffix("")
    assert not (run / "checkpoint.npz").exists()
    assert _run(path, "--steps", 2, "--every", 1, "--resume") == 2
    assert "run without --resume to start the run again" in capsys.readouterr().err
    other = _scene(tmp_path, "column", ("rho = 2.0 ", "rho = 3.0 "), file="other.toml")
    assert _run(other, "--steps", 2, "--every", 1, out=run) == 2      # another scene: kept
    assert "holds the results of another run" in capsys.readouterr().err
    assert _run(path, "--steps", 2, "--every", 1) == 0                 # the same: started again
    assert "holds no saved step of this scene" in capsys.readouterr().err
    assert [r["step"] for r in json.loads((run / "history.json").read_text())] == [1, 2]
    assert not (run / "scene_0003.vtu").exists()


def test_a_stop_after_a_checkpoint_names_the_step_the_checkpoint_holds(tmp_path, capsys,
                                                                      monkeypatch):
    # the checkpoint of step 2 written, then every later one fails and step 4's VTU too:
    # --resume continues from step 2, not from step 3
    from pfem_skfem import io, runfolder
    path = _scene(tmp_path, "column")
    save, write, calls = runfolder.save_checkpoint, io.TimeSeries.write, []

    def save_until_full(file, state, **kwargs):
        if state.step > 2:
            raise OSError(28, "No space left on device")
        return save(file, state, **kwargs)

    def write_until_full(self, *args, **kwargs):
        calls.append(1)
        if len(calls) == 5:
            raise OSError(28, "No space left on device")
        return write(self, *args, **kwargs)

    monkeypatch.setattr(runfolder, "save_checkpoint", save_until_full)
    monkeypatch.setattr(io.TimeSeries, "write", write_until_full)
    assert _run(path, "--steps", 6, "--every", 1, "--checkpoint-every", 2) == 3
    err = capsys.readouterr().err
    assert ("in step 4; steps 1-2 are in " in err and "(step 3 was not saved) "
            "(--resume continues from step 2)" in err), err


@pytest.mark.parametrize("overwrite", [False, True])
def test_a_scene_file_named_scene_toml_run_into_its_own_folder_is_never_replaced(
        tmp_path, capsys, monkeypatch, overwrite):
    # R6: refused as "another run's results", and the suggested --overwrite replaced the
    # user's commented file by the generated copy
    path = _scene(tmp_path, "column", file="scene.toml")
    path.write_text(path.read_text() + "# my notes\n")
    before = path.read_text()
    monkeypatch.chdir(tmp_path)
    args = ["run", "scene.toml", "--out", ".", "--steps", 1, "--no-progress"]
    assert cli.main(list(map(str, args + (["--overwrite"] if overwrite else [])))) == 2
    err = capsys.readouterr().err
    assert "scene.toml is the file where the run writes its copy of the scene" in err
    assert "Rename the scene file" in err
    assert path.read_text() == before and sorted(p.name for p in tmp_path.iterdir()) == \
        ["scene.toml"]


@pytest.mark.parametrize("steps", [(), ("--steps", 3)])
def test_a_time_step_longer_than_t_end_is_refused_before_any_work(tmp_path, capsys, steps):
    # R13: dt = 100 with t_end = 0.02 ran one step to t = 100
    path = _scene(tmp_path, "column", ("dt = 0.003194382824999699", "dt = 100.0"),
                  ("t_end = 1.6 ", "t_end = 0.02 "))
    assert _run(path, *steps) == 2
    err = capsys.readouterr().err
    assert "dt = 100 s is longer than the run, t_end = 0.02 s" in err
    assert not path.with_suffix("").exists()


def _pushed_block(motion, bodies_extra=(), **scene):
    from pfem_skfem.discretisation import ThetaMethod
    from pfem_skfem.materials import ZeroDilationMohrCoulomb
    from pfem_skfem.problems.contact import RigidSegment
    from pfem_skfem.scene import Body, Region, Scene
    from pfem_skfem.scene.config import PFEMConfig
    block = Region(((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)),
                   ZeroDilationMohrCoulomb(c=0.0, phi=30.0), rho=2.0, h=0.25)
    bodies = (Body("base", RigidSegment((-5, 0), (5, 0), 0.3)),
              Body("pusher", RigidSegment((1.05, -0.1), (1.05, 5.0), 0.3), motion=motion))
    return Scene(regions=(block,), bodies=bodies + tuple(bodies_extra),
                 config=PFEMConfig(theta=ThetaMethod(dt=0.01)), **scene)


@pytest.mark.parametrize("t_end", [None, 0.05])
def test_a_motion_infinite_at_a_step_time_is_refused_naming_the_body(t_end):
    # R12: finite at t = 0 and 1 (the times as_motion checks), infinite at t = 0.02: the
    # run went on with RuntimeWarnings, every particle free at the end
    def blow(t):
        return (np.float64(1.0) / (np.float64(0.02) - np.float64(t)) - 50.0, 0.0)
    with pytest.raises(ValueError, match=r"body 'pusher': motion\(t\) must return a finite "
                                         r"\(dx, dy\) at every step time, .* at t = 0.02 "
                                         r"\(step 2 of dt = 0.01\)"):
        _pushed_block(blow, t_end=t_end)
    scene = _pushed_block(lambda t: (-0.1 * t, 0.0), t_end=t_end)     # a finite one runs
    assert scene.bodies[1].name == "pusher"


def _refused(tmp_path, capsys, path, *names):
    """The scene file ``path`` is refused before any work (exit 2, no folder), the message
    holding each of ``names``."""
    assert _run(path, "--steps", 3, "--every", 0) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and all(name in err for name in names), err
    assert not path.with_suffix("").exists()
    return err


def test_a_polygon_that_touches_itself_is_refused_naming_the_region_and_the_vertex(
        tmp_path, capsys):
    # R8: the vertex (1, 1) repeated non-adjacently: a zero-width spike to (1.5, 1) whose
    # 7 edge particles carried 9.7 % of the mass on a line outside the material
    square = "polygon = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]"
    spike = "polygon = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [1.5, 1.0], [1.0, 1.0], [0.0, 1.0]]"
    path = _scene(tmp_path, "column", (square, spike))
    _refused(tmp_path, capsys, path, "regions[0].polygon", "region 'column'",
             "touches itself: vertex 4 (1.0, 1.0) is vertex 2 again", "zero-width spike")
    from pfem_skfem.scene.regions import check_polygon
    with pytest.raises(ValueError, match=r"pinch: the polygon touches itself: vertex 4 "
                                         r"\(1.0, 0.0\) lies on edge 0 "):
        check_polygon(((0, 0), (2, 0), (2, 2), (1, 2), (1, 0), (0.5, 1)), "pinch")
    with pytest.raises(ValueError, match=r"twice: vertices 1 and 2 are the same point"):
        check_polygon(((0, 0), (1, 0), (1, 0), (1, 1), (0, 1)), "twice")
    # a ring written closed (its first vertex again, as GIS files write it) is the ring
    assert check_polygon(((0, 0), (1, 0), (1, 1), (0, 1), (0, 0)), "closed").tolist() == [
        [0, 0], [1, 0], [1, 1], [0, 1]]


def test_a_small_body_buried_between_the_particles_is_refused_naming_it(tmp_path, capsys):
    # R7: a fixed disc of radius 0.05 at the column's centre, between the lattice points
    # (h = 0.143): no particle inside it, so the run was bit for bit the column's without it
    pebble = ('[[bodies]]\nname = "pebble"\n[bodies.shape]\ntype = "RigidCircle"\n'
              'center = [0.5, 0.5]\nradius = 0.05\nmu = 0.6\n\n# -- the numerical choices')
    path = _scene(tmp_path, "column", ("# -- the numerical choices", pebble))
    _refused(tmp_path, capsys, path, "body 'pebble' reaches into the material of region",
             "its centre (0.5, 0.5) lies in the material", "no particle inside it")
    # a disc reaching in from outside, a polyline obstacle inside: refused too; a cylinder
    # resting on the surface and a wall along an edge touch the material, and run
    from pfem_skfem.problems.contact import RigidCircle, RigidPolyline, RigidSegment
    from pfem_skfem.scene import Body
    side = Body("side", RigidCircle((1.05, 0.625), 0.06))            # h = 0.25 here
    box = Body("box", RigidPolyline(((0.6, 0.6), (0.6, 0.7), (0.7, 0.7), (0.7, 0.6),
                                     (0.6, 0.6))))
    for body, said in ((side, "reaches 0.01 into the material"),
                       (box, r"its point \(0.6, 0.6\) lies 0.4 inside the material")):
        with pytest.raises(ValueError, match=rf"body '{body.name}' reaches into .*{said}"):
            _pushed_block(lambda t: (0.0, 0.0), bodies_extra=(body,))
    _pushed_block(lambda t: (0.0, 0.0),
                  bodies_extra=(Body("roller", RigidCircle((0.5, 1.5), 0.5)),
                                Body("wall", RigidSegment((0.0, 3.0), (0.0, -0.2)))))


def test_an_outlet_holding_most_of_the_material_at_the_start_is_refused_naming_it(
        tmp_path, capsys):
    # R9: the silo's outlet moved up to hold all but the top row: 396 of 409 particles
    # left in step 1 (the edge-inclusive "holds every particle" check passed by one row)
    path = _scene(tmp_path, "silo", ("point = [0.0, 0.0]", "point = [0.0, 1.34]"))
    _refused(tmp_path, capsys, path, "outlets[0]", "outlet 'orifice' holds 396 of the 409 "
             "particles at t = 0", "more than 50%")
    from pfem_skfem.scene import HalfPlane, Outlet
    half = HalfPlane((0.0, 0.45), (0.0, -1.0))           # y < 0.45 of the unit square
    _pushed_block(lambda t: (0.0, 0.0), outlets=(Outlet("low", half),))
    with pytest.raises(ValueError, match=r"outlet 'high' holds 20 of the 25 particles"):
        _pushed_block(lambda t: (0.0, 0.0),
                      outlets=(Outlet("high", HalfPlane((0.0, 0.8), (0.0, -1.0))),))


def test_a_motion_infinite_after_the_checked_times_is_refused_by_run_naming_the_body():
    # R12 through the API: the scene checks to t_end (or its first 1000 steps), and run()
    # may go past both; a motion infinite at t = 0.08 > t_end = 0.05 ran on with
    # RuntimeWarnings, every particle free at the end
    from pfem_skfem.drivers.pfem_loop import run

    def blow(t):
        return (np.float64(1.0) / (np.float64(0.08) - np.float64(t)) - 12.5, 0.0)
    scene = _pushed_block(blow, t_end=0.05)                      # accepted: finite to t_end
    state = scene.initial_state()
    with pytest.raises(ValueError, match=r"body 'pusher': motion\(t\) must return a finite "
                                         r"\(dx, dy\) at every step time, .* at t = 0.08 "
                                         r"\(step 8 of dt = 0.01\)"):
        run(state, scene, 10)
    assert state.step == 0 and state.history == {}               # refused before any step


def test_a_nearly_full_disk_at_the_start_is_a_clean_stop_naming_the_1_mb_reserve(
        tmp_path, capsys, monkeypatch):
    # R3: under about 1.1 MB free the t = 0 frame raised an OSError traceback whose message
    # said "401408 bytes free, a frame takes about 25600", not the 1 MB kept for the
    # checkpoint that refused it
    import shutil
    path = _scene(tmp_path, "column")
    real = shutil.disk_usage
    monkeypatch.setattr(shutil, "disk_usage", lambda p: real(p)._replace(free=1_000_000))
    assert _run(path, "--steps", 3, "--every", 1) == 3
    err = capsys.readouterr().err
    assert "Traceback" not in err
    assert "1,000,000 bytes free" in err and "a reserve of 1 MB" in err, err
    assert "no step was computed" in err


def _vice(t_end, dt=0.05, gate=None):
    """The open vice of squeeze.py: a 1 x 0.5 block on a base between two walls driven
    towards each other at 2 m/s (they meet at t = 0.25 s)."""
    from pfem_skfem.discretisation import ThetaMethod
    from pfem_skfem.materials import ZeroDilationMohrCoulomb
    from pfem_skfem.problems.contact import RigidSegment
    from pfem_skfem.scene import Body, ConstantVelocity, Geostatic, Region, Scene
    from pfem_skfem.scene.config import PFEMConfig
    block = Region(((0, 0), (1, 0), (1, 0.5), (0, 0.5)), ZeroDilationMohrCoulomb(0.0, 30.0),
                   rho=2.0, h=0.125, stress=Geostatic())
    bodies = (Body("base", RigidSegment((-3, 0), (4, 0))),
              Body("left", RigidSegment((0, 3), (0, -0.2)), motion=ConstantVelocity((2.0, 0))),
              Body("right", RigidSegment((1, -0.2), (1, 3)), motion=ConstantVelocity((-2.0, 0))))
    return Scene(regions=(block,), bodies=bodies + ((gate,) if gate else ()), t_end=t_end,
                 config=PFEMConfig(theta=ThetaMethod(dt)))


@pytest.mark.parametrize("dt", [0.05, 0.01])
def test_bodies_that_pass_through_each_other_are_refused_naming_both(tmp_path, capsys, dt):
    # R10: the open vice's walls cross at t = 0.25 s; the run lost 37 % of the area and
    # ended with exit 0 (and pfem-skfem run's step check blames dt, which is not the cause:
    # at dt = 0.01 the walls cross all the same)
    from pfem_skfem.problems.contact import RigidCircle, RigidSegment
    from pfem_skfem.scene import Body, ConstantVelocity, PiecewiseLinear
    from pfem_skfem.scene.files import scene_to_toml
    said = (r"bodies 'left' and 'right' pass through each other from t = 0.25 s \(before "
            rf"t_end = 0.5 s; dt = {dt:g} s\)")
    with pytest.raises(ValueError, match=said):
        _vice(0.5, dt)
    path = tmp_path / "vice.toml"
    path.write_text(scene_to_toml(_vice(0.2, dt)).replace("t_end = 0.2", "t_end = 0.5"))
    _refused(tmp_path, capsys, path, "bodies 'left' and 'right' pass through each other")
    # a cylinder pressed through the base, from above: refused; a gate lifted out through
    # the base (from behind it) and walls sliding along the base they reach below: accepted
    down = Body("roller", RigidCircle((0.5, 1.0), 0.2), motion=ConstantVelocity((0.0, -10.0)))
    with pytest.raises(ValueError, match="bodies 'roller' and 'base' pass through each "
                                         r"other from t = 0.080\d* s"):
        _vice(0.2, dt, gate=down)
    lift = PiecewiseLinear((0.0, 0.1), ((0.0, 0.0), (0.0, 5.0)))
    _vice(0.2, dt, gate=Body("gate", RigidSegment((-0.5, 3.0), (-0.5, -0.5)), motion=lift))


def _box(t_end, lid=None, right=1.1):
    """squeeze.py's closed box with a gap: a 1 x 0.5 block on a base, under a lid, between
    a wall at x = 0 and one at x = ``right`` moving in at 0.5 m/s (it reaches the block at
    t = 0.2 s when right = 1.1); ``lid``: the lid's motion."""
    from pfem_skfem.discretisation import ThetaMethod
    from pfem_skfem.materials import ZeroDilationMohrCoulomb
    from pfem_skfem.problems.contact import RigidSegment
    from pfem_skfem.scene import Body, ConstantVelocity, Geostatic, Region, Scene
    from pfem_skfem.scene.config import PFEMConfig
    block = Region(((0, 0), (1, 0), (1, 0.5), (0, 0.5)), ZeroDilationMohrCoulomb(0.0, 30.0),
                   rho=2.0, h=0.125, stress=Geostatic())
    moving = ConstantVelocity((-0.5, 0.0)) if lid is None else None
    bodies = (Body("base", RigidSegment((-1, 0), (3, 0))),
              Body("lid", RigidSegment((3, 0.5), (-1, 0.5)), motion=lid),
              Body("left", RigidSegment((0, 2), (0, -1))),
              Body("right", RigidSegment((right, -1), (right, 2)), motion=moving))
    return Scene(regions=(block,), bodies=bodies, t_end=t_end,
                 config=PFEMConfig(theta=ThetaMethod(0.02)))


def test_bodies_closing_in_on_an_incompressible_material_are_refused_naming_them(
        tmp_path, capsys):
    # R11: the closed box's right wall passes the block's side at t = 0.2 s: 248 m/s in
    # step 11, 6 % of the area lost, then the solver gave up in step 17
    from pfem_skfem.scene import ConstantVelocity
    from pfem_skfem.scene.files import scene_to_toml
    said = (r"the bodies close the material in, and as 'right' moves the room they leave "
            r"falls below its area 0.5 from t = 0.2 s \(to 9\d.\d% of it at t = 0.\d+ s, "
            r"before t_end = 0.6 s\)")
    with pytest.raises(ValueError, match=said):
        _box(0.6)
    path = tmp_path / "gap_box.toml"
    path.write_text(scene_to_toml(_box(0.2)).replace("t_end = 0.2", "t_end = 0.6"))
    _refused(tmp_path, capsys, path, "as 'right' moves the room they leave falls below")
    _box(0.6, right=1.5)                         # room to the end: 1.2 x 0.5 at t = 0.6
    _box(0.6, lid=ConstantVelocity((0.5, 0.0)), right=1.0)     # a lid sliding: a shear box
