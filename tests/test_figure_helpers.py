"""The shared figure and study helpers of the verification scripts: a grid of snapshots on
one colour scale, or of bare particles (:func:`pfem_skfem.viz.snapshot_grid`), bounds against elements
(:func:`pfem_skfem.viz.plot_rounds`), a labelled panel
(:func:`pfem_skfem.harness.figures.labelled`), counted warnings
(:class:`pfem_skfem.harness.report.counted_warnings`); each figure passes the checks of
:func:`~pfem_skfem.harness.figures.figure_problems`."""
from types import SimpleNamespace
import warnings

import numpy as np
import pytest

from pfem_skfem.harness.figures import figure_problems, labelled, pyplot
from pfem_skfem.harness.report import counted_warnings
from pfem_skfem.viz import plot_rounds, snapshot_grid


def test_a_snapshot_grid_has_one_colour_scale_and_one_colour_bar():
    rng = np.random.default_rng(0)
    panels = {f"t = {t:g} s": (rng.random((20, 2)), t * rng.random(20)) for t in (1, 2, 3)}
    fig, axes = snapshot_grid(panels, label="speed [m/s]", title="particles coloured by speed",
                              ncols=2, scale=2.0, limits=((0, 0.5), None))
    assert axes.shape == (2, 2) and not axes[1, 1].get_visible()      # the spare panel is off
    scales = {ax.collections[0].get_clim() for ax in axes.flat[:3]}
    top = max(float(p[1].max()) for p in panels.values())
    assert scales == {(0.0, top)}
    assert axes[0, 0].get_xlim() == (0, 0.5)
    assert np.allclose(axes[0, 0].collections[0].get_offsets(), panels["t = 1 s"][0] / 2)
    assert len([ax for ax in fig.axes if hasattr(ax, "_colorbar")]) == 1
    assert figure_problems(fig) == []
    pyplot().close(fig)


def test_a_snapshot_grid_colours_the_cells_of_a_mesh_and_calls_draw_first():
    points = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    cells = np.array([[0, 1, 2], [0, 2, 3]])
    drawn = []
    fig, axes = snapshot_grid({"s = 1 cm": (points, [0.1, 0.2], cells)},
                              label="strain [-]", title="a mesh",
                              colours=dict(cmap="jet", vmax=1.0), draw=drawn.append)
    assert drawn == [axes[0, 0]]
    art = axes[0, 0].collections[0]
    assert art.get_clim() == (0.0, 1.0) and art.get_cmap().name == "jet"
    assert figure_problems(fig) == []
    pyplot().close(fig)


def test_a_snapshot_grid_of_points_without_values_draws_dots_and_no_colour_bar():
    rng = np.random.default_rng(1)
    panels = {f"run {k}": (rng.random((30, 2)), None) for k in (1, 2)}
    fig, axes = snapshot_grid(panels, label=None, title="final deposits", dots="C3")
    dots = axes[0, 0].get_lines()[0]
    assert dots.get_marker() == "." and dots.get_color() == "C3"
    assert np.allclose(dots.get_xydata(), panels["run 1"][0])
    assert not axes[1, 0].collections and not any(hasattr(ax, "_colorbar") for ax in fig.axes)
    assert figure_problems(fig) == []
    pyplot().close(fig)


def test_histories_draw_a_labelled_line_per_run_scaled_and_floored():
    from pfem_skfem.viz import plot_histories

    runs = [dict(t=[0, 1, 2], ke=[1.0, 0.0, 0.5], mu=m) for m in (0.2, 0.3)]
    fig, (a, b) = pyplot().subplots(1, 2, figsize=(10, 4))
    plot_histories(a, runs, "t", "ke", "mu = {mu:g}", scale=100, style=":")
    plot_histories(b, runs, "t", "ke", lambda r: f"run {r['mu']}", floor=1e-3, log=True)
    labelled(a, "t [s]", "ke [%]", "scaled")
    labelled(b, "t [s]", "ke", "floored")
    assert [line.get_label() for line in a.get_lines()] == ["mu = 0.2", "mu = 0.3"]
    assert list(a.get_lines()[0].get_ydata()) == [100.0, 0.0, 50.0]
    assert a.get_lines()[0].get_linestyle() == ":" and a.get_yscale() == "linear"
    assert list(b.get_lines()[1].get_ydata()) == [1.0, 1e-3, 0.5]
    assert b.get_lines()[1].get_label() == "run 0.3" and b.get_yscale() == "log"
    assert figure_problems(fig) == []
    pyplot().close(fig)


def test_a_ground_profile_under_the_particles_frames_its_surface_at_one_scale():
    from pfem_skfem.viz import plot_ground

    x, slip = np.array([0.0, 50, 100, 200]), np.array([60.0, 30, 10, 10])
    fig, (a, b) = pyplot().subplots(2, 1, figsize=(8, 6))
    plot_ground(a, x, slip, slip + [0, 15, 0, 0], xlim=(0, 150))
    plot_ground(b, x, slip)
    assert a.get_xlim() == (0, 150) and a.get_ylim() == (2.0, 68.0)
    assert b.get_xlim() == (0, 200) and a.get_aspect() == 1.0
    assert [line.get_linestyle() for line in a.get_lines()] == ["-", "--"]
    assert len(b.get_lines()) == 1 and len(a.collections) == 1       # the grey ground
    assert a.get_xlabel() == "horizontal distance x [m]" and a.get_legend() is None
    b.set_title("bare")
    a.set_title("before and after")
    assert figure_problems(fig) == []
    pyplot().close(fig)


def test_bounds_against_elements_on_a_log_axis_with_a_second_hollow_series():
    fig, ax = pyplot().subplots(figsize=(6, 4))
    rounds = [SimpleNamespace(elements=n, lower=1 - 1 / n, upper=1 + 1 / n) for n in (100, 400)]
    plot_rounds(ax, rounds, 2.0)
    plot_rounds(ax, [SimpleNamespace(elements=1600, lower=0.99, upper=1.01)], 2.0,
                hollow=True, what=", uniform")
    labelled(ax, "elements", "Nc", "bounds")
    lines = ax.get_lines()
    assert [line.get_label() for line in lines] == [
        "lower bound", "upper bound", "lower bound, uniform", "upper bound, uniform"]
    assert np.allclose(lines[1].get_ydata(), [2.02, 2.005])
    assert ax.get_xscale() == "log" and ax.get_xlim()[1] >= 1600
    assert lines[2].get_linestyle() == "--" and lines[2].get_markerfacecolor() == "none"
    assert figure_problems(fig) == []
    pyplot().close(fig)


def test_labelled_sets_the_labels_and_a_legend_only_for_labelled_artists():
    fig, (a, b) = pyplot().subplots(1, 2, figsize=(8, 3))
    a.plot([0, 1], [0, 1], label="ours")
    b.plot([0, 1], [1, 0])
    assert labelled(a, "x [m]", "y [m]", "one", title_size=9) is a
    labelled(b, "t [s]", "h [m]")
    assert (a.get_xlabel(), a.get_ylabel(), a.get_title()) == ("x [m]", "y [m]", "one")
    assert a.title.get_fontsize() == 9
    assert a.get_legend().get_texts()[0].get_fontsize() == 7
    assert b.get_legend() is None and b.get_title() == ""
    pyplot().close(fig)


class Accepted(UserWarning):
    pass


def test_counted_warnings_counts_one_kind_and_shows_the_others():
    with pytest.warns(RuntimeWarning, match="shown"):
        with counted_warnings(Accepted) as counted:
            for _ in range(3):
                warnings.warn("accepted", Accepted)
            warnings.warn("shown", RuntimeWarning)
    assert counted.count == 3
    with warnings.catch_warnings(record=True) as after:
        warnings.simplefilter("always")
        warnings.warn("again", Accepted)       # outside the block: shown again
    assert len(after) == 1


def test_a_summary_beside_the_figures_holds_arrays_as_lists(tmp_path):
    import json

    from pfem_skfem.harness.figures import write_summary

    path = write_summary(tmp_path, {"x": np.arange(3), "v": np.float64(0.5), "p": tmp_path})
    assert path == tmp_path / "summary.json"
    assert json.loads(path.read_text()) == {"x": [0, 1, 2], "v": 0.5, "p": str(tmp_path)}


def test_the_value_the_rounds_bracket_is_a_line_or_a_band():
    fig, ax = pyplot().subplots(1, 2, figsize=(10, 4))
    rounds = [SimpleNamespace(elements=n, lower=1 - 1 / n, upper=1 + 1 / n) for n in (100, 400)]
    plot_rounds(ax[0], rounds, reference=1.0, label="exact")
    plot_rounds(ax[1], rounds, reference=(0.99, 1.01), label="published bounds")
    for a in ax:
        labelled(a, "elements", "load", "bounds")
    assert ax[0].get_lines()[-1].get_label() == "exact"
    assert list(ax[0].get_lines()[-1].get_ydata()) == [1.0, 1.0]
    assert [p.get_label() for p in ax[1].patches] == ["published bounds"]
    assert len(ax[1].get_lines()) == 2                       # no line for a band
    assert figure_problems(fig) == []
    pyplot().close(fig)


def test_a_convergence_study_with_the_slope_expected():
    from pfem_skfem.viz import plot_order

    fig, ax = pyplot().subplots(figsize=(6, 4))
    plot_order(ax, [4, 8, 16], [1e-2, 2.6e-3, 6e-4], "ours, order 2.03", slope=-2.0)
    labelled(ax, "elements", "error", "convergence")
    ours, expected = ax.get_lines()
    assert (ours.get_label(), expected.get_label()) == ("ours, order 2.03", "slope 2")
    assert np.allclose(expected.get_ydata(), [1e-2, 2.5e-3, 6.25e-4])
    assert ax.get_xscale() == ax.get_yscale() == "log"
    assert figure_problems(fig) == []
    pyplot().close(fig)


def test_groups_of_cases_beside_their_fits_one_quantity_a_panel(tmp_path):
    from pfem_skfem.viz import groups_figure, plot_groups

    fig, ax = pyplot().subplots(1, 2, figsize=(10, 4))
    a = np.array([0.5, 1.0, 2.0])
    rows = [dict(a=2.0, r=3.0, h=1.1), dict(a=0.5, r=0.6, h=0.5)]     # drawn in increasing a
    plot_groups(ax, [("PFEM", rows, "o"), ("none", [], "s")], "a", ("r", "h"), log=True,
                curves=[(0, a, 1.2 * a, "k-", "fit")],
                labels=("a", ("run-out", "height"), "columns"))
    fit, ours = ax[0].get_lines()
    assert fit.get_label() == "fit" and ours.get_label() == "PFEM"
    assert list(ours.get_xdata()) == [0.5, 2.0] and list(ours.get_ydata()) == [0.6, 3.0]
    assert list(ax[1].get_lines()[0].get_ydata()) == [0.5, 1.1]
    assert "none" not in [line.get_label() for a_ in ax for line in a_.get_lines()]
    assert ax[0].get_xscale() == "log" and ax[1].get_title() == "columns"
    assert ax[1].get_ylabel() == "height" and ax[0].get_legend() is not None
    assert figure_problems(fig) == []
    pyplot().close(fig)
    path = groups_figure(tmp_path / "study.png", "a study", [("a = 1", rows, "o-")], "a",
                         ("r", "h"), labels=("a", ("run-out", "height")))
    assert path.is_file()


def test_deposits_compared_by_their_particles_and_their_mass_within_a_radius():
    from pfem_skfem.viz import plot_mass_profiles

    fig, ax = pyplot().subplots(2, 1, figsize=(5, 6))
    points = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 1.0]])
    plot_mass_profiles(ax, [("rough", points, np.ones(3)), ("smooth", 2 * points, np.ones(3))],
                       scale=2.0, title="a = 1")
    rough = ax[0].get_lines()[0]
    assert list(rough.get_xdata()) == [0.0, 0.5, 1.0] and list(rough.get_ydata()) == [0, 0, 0.5]
    share = ax[1].get_lines()[1].get_ydata()
    assert share[-1] == pytest.approx(1.0) and np.all(np.diff(share) >= 0)
    assert ax[0].get_title() == "a = 1" and ax[0].get_aspect() == 1.0
    assert figure_problems(fig) == []
    pyplot().close(fig)


def test_a_study_of_deposits_a_column_of_particles_and_masses_per_group(tmp_path):
    from pfem_skfem.viz import mass_profiles_figure

    points = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 1.0]])
    deposits = [("rough", points, np.ones(3)), ("smooth", 2 * points, np.ones(3))]
    path = mass_profiles_figure(tmp_path / "profiles.png", "deposits at rest",
                                [("a = 0.5", 1.0, deposits), ("a = 4", 2.0, deposits[:1])])
    assert path == tmp_path / "profiles.png" and path.is_file()
    assert mass_profiles_figure(tmp_path / "none.png", "no study", []) is None   # no figure
    assert not (tmp_path / "none.png").exists()


def test_one_panel_of_curves_with_its_labels_and_legend(tmp_path, monkeypatch):
    from pfem_skfem import viz
    from pfem_skfem.harness import figures

    drawn = {}
    monkeypatch.setattr(figures, "save_figure", lambda fig, path: drawn.update(fig=fig))
    t = np.linspace(0.0, 1.0, 5)
    path = viz.lines_figure(tmp_path / "history.png", [(t, t ** 2, "--", "h"), (t, t, None, "r")],
                            ("t [s]", "h, r [m]", "a history"), size=(5, 3), title_size=9)
    ax, = drawn["fig"].axes
    dashed, plain = ax.get_lines()
    assert path == tmp_path / "history.png"
    assert dashed.get_linestyle() == "--" and plain.get_linestyle() == "-"
    assert list(plain.get_ydata()) == list(t) and plain.get_label() == "r"
    assert ax.get_title() == "a history" and ax.title.get_fontsize() == 9
    assert ax.get_xlabel() == "t [s]" and ax.get_legend() is not None
    assert tuple(drawn["fig"].get_size_inches()) == (5, 3)
    assert figure_problems(drawn["fig"]) == []
    pyplot().close(drawn["fig"])


def test_a_study_figure_without_cases_is_not_drawn(tmp_path):
    from pfem_skfem.viz import groups_figure

    a = np.array([0.5, 1.0])
    assert groups_figure(tmp_path / "none.png", "no study", [("a = 1", [], "o-")], "a",
                         ("r", "h"), curves=[(0, a, a, "k-", "fit")]) is None
    assert not (tmp_path / "none.png").exists()
