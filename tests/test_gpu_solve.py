"""benchmarks/gpu_solve.py (issue 40, item 6): the CPU half of the GPU path. A tiny step's
conic problem is captured, written, read back bit for bit and solved from the file."""
import importlib

import numpy as np
import pytest

gpu = importlib.import_module("benchmarks.gpu_solve")


@pytest.fixture(scope="module")
def captured(tmp_path_factory):
    out = tmp_path_factory.mktemp("gpu_cap")
    paths = gpu.capture(9, out, steps=2, passes=2, keep=1, log=lambda *a: None)
    return paths


def test_the_file_holds_the_captured_problem_bit_for_bit(captured):
    (path,) = captured
    assert path.name == "nx9_solve3.npz"
    prob = gpu.from_file(path)
    again, elements = gpu.capture_step(9, steps=2, passes=2)   # the run is deterministic
    last = again[-1]
    assert prob["elements"] == elements > 0 and prob["nx"] == 9
    for key, ref in (("P", last["P"]), ("A", last["A"])):
        M, R = prob[key], ref.tocsc()
        assert M.shape == R.shape and M.dtype == R.dtype
        for part in ("data", "indices", "indptr"):
            assert np.array_equal(getattr(M, part), getattr(R, part))
    assert np.array_equal(prob["q"], last["c"]) and np.array_equal(prob["b"], last["b"])
    kinds, dims = gpu.cone_arrays(last["cones"])
    assert np.array_equal(prob["cone_kinds"], kinds) and np.array_equal(prob["cone_dims"], dims)
    assert prob["n_free"] == last["n_free"] > 0
    assert np.array_equal(prob["du_ref"], prob["z_ref"][:prob["n_free"]])
    assert prob["ref_status"] == "Solved"
    # and a second write / read of the problem is the same, array for array
    again_path = path.with_name("copy.npz")
    gpu.to_file(again_path, prob)
    copy = gpu.from_file(again_path)
    assert set(copy) == set(prob)
    for key in ("q", "b", "x_ref", "z_ref", "s_ref", "du_ref", "cone_dims"):
        assert copy[key].dtype == prob[key].dtype and np.array_equal(copy[key], prob[key])
    again_path.unlink()


def test_clarabel_from_the_file_meets_the_reference(captured):
    (path,) = captured
    prob = gpu.from_file(path)
    x, z, status, _ = gpu._clarabel(prob, gpu.REF_TOL, equilibrate_enable=False, max_iter=500)
    assert status == "Solved"
    assert gpu.rel(x, prob["x_ref"]) < 1e-6 and gpu.rel(z, prob["z_ref"]) < 1e-6
    rows = {r["solver"]: r for r in gpu.solve_file(path, ["clarabel-noeq", "qoco",
                                                          "moreau-cuda"])}
    assert rows["clarabel-noeq"]["status"] == "Solved"
    assert rows["clarabel-noeq"]["du_err"] < 1e-6
    assert rows["qoco"]["status"].startswith("QOCO_SOLVED")      # its y has Clarabel's sign
    assert rows["qoco"]["du_err"] < 1e-5
    try:
        import moreau  # noqa: F401
    except ImportError:
        assert rows["moreau-cuda"]["status"] == "not installed"


def test_row_order_groups_zero_nonnegative_and_second_order_rows():
    kinds = np.array(["ZeroConeT", "NonnegativeConeT", "SecondOrderConeT",
                      "SecondOrderConeT", "NonnegativeConeT"])
    perm, n_zero, n_nonneg, soc = gpu.row_order(kinds, np.array([2, 1, 3, 3, 2]))
    assert n_zero == 2 and n_nonneg == 3 and soc == [3, 3]
    assert perm.tolist() == [0, 1, 2, 9, 10, 3, 4, 5, 6, 7, 8]
    with pytest.raises(NotImplementedError):
        gpu.row_order(np.array(["ExponentialConeT"]), np.array([3]))


def test_solve_prints_a_row_per_file_and_solver(captured, capsys):
    (path,) = captured
    assert gpu.main(["solve", str(path.parent), "--solvers", "clarabel", "qoco-cuda"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert len(out) == 3 and "clarabel" in out[1] and "Solved" in out[1]
    assert "qoco-cuda" in out[2]
    import qoco
    if not qoco.algebra_available("cuda"):
        assert "not installed" in out[2]
