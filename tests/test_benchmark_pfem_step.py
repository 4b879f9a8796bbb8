"""benchmarks/pfem_step.py: its options (--solvers, --settings) and one tiny run."""
import pytest

from benchmarks import pfem_step as bench


def test_configurations():
    # a solver with a direct engine (Clarabel, QOCO) on each backend, the settings variants
    # on the direct one only (QOCO: the forms); another solver once, on the cvxpy statement
    assert bench.configurations(["clarabel", "cvxpy"], ["clarabel", "qoco"], ["after"]) == [
        ("clarabel", "clarabel", "after"), ("cvxpy", "clarabel", "after"),
        ("clarabel", "qoco", "after"), ("cvxpy", "qoco", "after")]
    assert bench.configurations(["clarabel"], ["clarabel"], ["before", "after"]) == [
        ("clarabel", "clarabel", "before"), ("clarabel", "clarabel", "after")]
    assert bench.configurations(["clarabel"], ["qoco"], ["before", "after", "dual", "noref"]) \
        == [("clarabel", "qoco", "after"), ("clarabel", "qoco", "dual")]
    assert bench.configurations(["clarabel"], ["scs"], ["after"]) == [("clarabel", "scs", "after")]
    assert bench.configurations(["clarabel"], ["mosek"], ["after"]) == [("cvxpy", "mosek", "after")]
    # each run is one step solver (PFEMConfig.solver)
    assert [bench.step_solver(b, s, f) for b, s, f in (
        ("clarabel", "clarabel", "primal"), ("clarabel", "clarabel", "dual"),
        ("clarabel", "qoco", "dual"), ("cvxpy", "clarabel", "dual"), ("cvxpy", "qoco", "primal"),
        ("cvxpy", "scs", "primal"), ("clarabel", "mosek", "primal"))] == [
            "clarabel", "clarabel-dual", "qoco-dual", "cvxpy", "cvxpy-qoco", "cvxpy-scs", "mosek"]


def test_options_refused():
    with pytest.raises(SystemExit):
        bench.main(["--solver", "before"])                  # renamed --settings
    with pytest.raises(SystemExit):
        bench.main(["--backends", "cvxpy", "--settings", "dual"])


def test_tiny_run_by_solver(tmp_path, capsys):
    pytest.importorskip("qoco")
    out = tmp_path / "rows.json"
    bench.main(["--nx", "5", "--steps", "1", "--solvers", "clarabel", "qoco", "--json",
                str(out)])
    text = capsys.readouterr().out
    assert "qoco-clarabel / clarabel-clarabel: step CPU" in text
    import json
    rows = json.loads(out.read_text())
    assert [(r["solver"], r["backend"]) for r in rows] == [("clarabel", "clarabel"),
                                                           ("qoco", "clarabel")]
    assert [r["step_solver"] for r in rows] == ["clarabel", "qoco"]
    for r in rows:
        assert r["iterations"] > 0 and r["total_passes"] >= 1
        assert sum(r["statuses"].values()) == 1 and 0 <= r["inaccurate"] <= r["total_passes"]
