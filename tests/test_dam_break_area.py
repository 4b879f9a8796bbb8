"""scripts/dam_break_area.py: where a dam break's domain gains and loses area. Its places
are the meshes clipped at vertical lines, and they add up to what the records say each
remeshing changed."""
import importlib.util
from pathlib import Path

import numpy as np
import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "dam_break_area.py"


@pytest.fixture(scope="module")
def tool():
    spec = importlib.util.spec_from_file_location("dam_break_area", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_a_triangle_clipped_at_a_vertical_line_keeps_its_part_and_its_sign(tool):
    """The right triangle (0, 0), (2, 0), (0, 2): left of x = 1 lies 2 - 1/2 = 1.5 of its 2;
    all of it left of x = 5, none left of x = -1; clockwise, the same part negative."""
    t = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    assert tool.area_left_of(t, 1.0) == pytest.approx(1.5, rel=1e-15)
    assert tool.area_left_of(t, 5.0) == pytest.approx(2.0, rel=1e-15)
    assert tool.area_left_of(t, -1.0) == 0.0
    assert tool.area_left_of(t[::-1], 1.0) == pytest.approx(-1.5, rel=1e-15)


def test_the_places_add_up_to_the_remeshings_of_the_records(tool):
    """A small square column (6 across, 30 steps to T = 3): the wall, the layer and the tip
    together are what the records say the remeshings changed (each mesh less the one the
    step before moved), to round-off; with the steps' motions, the domain's change."""
    from verification.dam_break import DamBreak
    params = DamBreak(a=0.05715, n2=1.0, nx=6, steps=30, T_end=3.0, rho=1000.0, mu=1e-3,
                      g=9.81)
    out = tool.study(params, 0.0)
    places = sum(out["remeshing"].values())
    assert places == pytest.approx(out["remeshing_recorded"], abs=1e-12)
    assert out["motion"] + places == pytest.approx(out["area_change_final"], abs=1e-12)
    assert out["spray_took"] >= 0 and out["spray_volume"] >= 0
