"""What ``pfem-skfem run`` says of a run (issue 56, items 3 and 4): what it is and what it
will cost at the start, why it stopped and its main figures at the end, and a warning
(exit 4 unless --force) when a step is too long for the method."""
import re

import pytest

from pfem_skfem import cli, runreport
from pfem_skfem.scene.files import example_text


def _scene(tmp_path, name, *edits):
    """The example ``name`` with each (old, new) text replaced, in tmp_path."""
    text = example_text(name)
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


def _run(path, *args):
    return cli.main(["run", str(path), "--out", str(path.with_suffix("")), "--every", "0",
                     "--no-progress", *map(str, args)])


def test_a_run_says_what_it_is_what_it_costs_and_that_it_reached_its_steps(tmp_path, capsys):
    assert _run(_scene(tmp_path, "column"), "--steps", 2) == 0
    out, err = capsys.readouterr()
    assert "steps 1-2 of dt = 0.00319438 s" in err and "64 particles" in err
    assert re.search(r"step 1: \d+ elements, [\d.e-]+ s: about \d+ s for the 2 steps", err)
    assert "stopped: step 2 reached, as asked" in out
    assert re.search(r"2 steps, t = 0.00638877 s, \d+ particles, mass kept 100 %, "
                     r"largest speed", out)
    assert "warning" not in err


def test_the_column_at_rest_says_it_came_to_rest_and_reached_t_end(tmp_path, capsys):
    # the column example with its right wall kept: at rest from the first step (the full
    # example comes to rest at step 499, a minute of CPU)
    path = _scene(tmp_path, "column", ("removed_at = 0.0", ""),
                  ("t_end = 1.6 ", "t_end = 0.0095831 "))
    assert _run(path) == 0
    out = capsys.readouterr().out
    assert "stopped: t_end = 0.0095831 s reached (step 3); at rest since step 1" in out


def test_the_silo_says_it_is_empty(tmp_path, capsys):
    # the silo example's hopper alone (31 particles): empty at step 31 of 600
    path = _scene(tmp_path, "silo", ("[0.25, 0.35], [0.25, 1.35], [-0.25, 1.35], [-0.25, 0.35],",
                                     "[0.14, 0.18], [-0.14, 0.18],"))
    assert _run(path) == 0
    out = capsys.readouterr().out
    assert re.search(r"stopped: no material left: every particle discharged \(through "
                     r"orifice\) by step \d+, t = [\d.]+ s, before step 600", out)
    assert re.search(r"\d+ steps, t = [\d.]+ s, 0 particles, mass kept 0 %", out)


@pytest.mark.parametrize("force", [False, True])
def test_a_dt_156_times_the_column_s_own_warns_once_naming_dt(tmp_path, capsys, force):
    path = _scene(tmp_path, "column", ("dt = 0.003194382824999699", "dt = 0.5"))
    assert _run(path, *(["--force"] if force else [])) == (0 if force else 4)
    err = capsys.readouterr().err
    assert err.count("warning") == 1
    assert re.search(r"warning: step 1 moved particles 7\.\d+ spacings h \(more than 2: .*\): "
                     r"dt = 0\.5 s is too long", err)
    assert "the steps were too long from step 1" in err


def _records(area_changes, outlets=False):
    return [{"step": i + 1, "area_change": a, "elements": 10, "mass": 1.0,
             "max_displacement_over_h": 0.1,
             "discharged": {"orifice": 0.0} if outlets else {}}
            for i, a in enumerate(area_changes)]


def test_an_area_lost_in_a_step_is_named_but_not_where_outlets_take_material():
    records = _records([0.0, -0.01, -0.2])
    assert runreport.first_too_long(records) == 2
    assert runreport.step_too_long(records, 2)[0] == "changed the area by"
    assert runreport.first_too_long(_records([0.0, -0.01, -0.2], outlets=True)) is None
    assert runreport.first_too_long(_records([0.0, -0.01, -0.05])) is None


def test_a_solver_failure_says_its_status_and_the_figures_of_the_steps_made(tmp_path, capsys,
                                                                             monkeypatch):
    from pfem_skfem.drivers import pfem_loop
    from pfem_skfem.problems.conic import SolverError
    real = pfem_loop.run

    def failing(state, scene, steps, **kw):
        if state.step == 1:
            raise SolverError("no optimal point", "PrimalInfeasible")
        return real(state, scene, steps, **kw)

    monkeypatch.setattr(pfem_loop, "run", failing)
    assert _run(_scene(tmp_path, "column"), "--steps", 3) == 3
    err = capsys.readouterr().err
    assert "solver failed (no optimal point; status PrimalInfeasible) in step 2" in err
    assert re.search(r"pfem-skfem run: 1 step, t = 0.00319438 s, 64 particles, "
                     r"mass kept 100 %", err)


def test_a_saturated_run_is_at_rest_once_its_pore_pressure_stops_changing_too():
    """Speeds below the bound are not rest while p changes faster than 1e-6 of its largest
    per sqrt(L / |g|) (here L = 1, g = 9.81: 1e-6 x 100 x 3.13 = 3.1e-4 Pa/s)."""
    class Scene:
        gravity, length = (0.0, -9.81), 1.0
    records = [{"step": k, "max_speed": 1e-9, "pore_pressure_max": 100.0,
                "pore_pressure_rate_max": rate}
               for k, rate in enumerate([5.0, 1e-2, 1e-4, 1e-5], start=1)]
    rate = runreport.rest_pore_rate(Scene, records)
    assert rate == pytest.approx(1e-6 * 100.0 * 9.81 ** 0.5)
    assert runreport.at_rest_since(records, 1e-6, rate) == 3
    assert runreport.at_rest_since(records[:2], 1e-6, rate) is None
    assert runreport.at_rest_since(records, 1e-6) is None     # a bound of 0: never
    dry = [{"step": 1, "max_speed": 1e-9}]
    assert runreport.rest_pore_rate(Scene, dry) == 0.0
    assert runreport.at_rest_since(dry, 1e-6, 0.0) == 1
