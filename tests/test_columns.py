"""The column on a floor against a wall (pfem_skfem.scene.column_scene) and the measured run
(pfem_skfem.drivers.resumable.ResumableRun without a checkpoint) that four benchmarks share."""
import numpy as np
import pytest

from pfem_skfem.drivers.resumable import Bar, Frames, ResumableRun
from pfem_skfem.materials import NewtonianFluid
from pfem_skfem.scene import Geostatic, column_scene


def water_column(**options):
    return column_scene(NewtonianFluid(1e-3), 0.05, 0.1, 0.01, rho=1000.0, g=9.81, dt=0.005,
                        **options)


def test_column_on_floor_against_wall():
    state, scene = water_column(floor_friction=0.3, passes=1)
    (column,) = scene.regions
    assert column.polygon == ((0.0, 0.0), (0.05, 0.0), (0.05, 0.1), (0.0, 0.1))
    assert column.stress is None and column.name == "column"
    assert [b.name for b in scene.bodies] == ["floor", "wall"]
    floor, wall = (b.shape for b in scene.bodies)
    assert floor.mu == 0.3 and wall.mu == 0.0
    assert np.allclose(wall.points, [(0.0, 5.0), (0.0, -0.01)])        # 50 column sizes up
    assert scene.length == 0.1 and scene.gravity == (0.0, -9.81) and scene.alpha == 1.6
    assert scene.config.dt == 0.005 and scene.config.passes == 1
    assert state.x.min() >= 0.0 and state.x[:, 0].max() <= 0.05 and state.x[:, 1].max() <= 0.1


@pytest.mark.parametrize("removed_at", [0.0, np.inf])
def test_gate_and_names(removed_at):
    _, scene = water_column(gate_removed_at=removed_at, wall_friction=0.2, far=1.0,
                            body_names=("base", "left", "right"), stress=Geostatic(),
                            name="water")
    assert [b.name for b in scene.bodies] == ["base", "left", "right"]
    gate = scene.bodies[2]
    assert gate.removed_at == removed_at and gate.shape.mu == 0.2
    assert np.allclose(gate.shape.points, [(0.05, -0.01), (0.05, 1.0)])
    assert scene.regions[0].name == "water" and scene.regions[0].stress == Geostatic()


def test_a_measured_run(tmp_path):
    state, scene = water_column(passes=1)
    seen = []
    run = ResumableRun.open(scene, state, on_step=lambda s, record, result: seen.append(s.step),
                            bar=Bar(total=2))
    run.advance(lambda run: run.state.step >= 2)
    assert seen == [1, 2] and run.state.step == 2 and run.series is None
    assert run.checkpoint is None and run.record["step"] == 2
    run = ResumableRun.open(scene, state, frames=Frames(directory=tmp_path, name="w", every=1))
    run.advance(lambda run: run.state.step >= 2)
    assert run.series.pvd_path == tmp_path / "w.pvd" and run.series.pvd_path.is_file()
    assert len(run.series.entries) == 3                  # t = 0 and the two steps
