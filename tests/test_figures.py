"""The figure checks (:func:`pfem_skfem.report.figure_problems`) find what a reader misses.

The quick suite (``tests/test_verification.py``) applies them to every figure the
verification scripts write; here each check meets a figure that breaks it, so that a
check that cannot fail fails here.
"""
import pytest

from pfem_skfem.report import figure_problems, pyplot


def readable():
    fig, ax = pyplot().subplots(figsize=(6, 4))
    line, = ax.plot([0, 1], [0, 1], label="ours")
    ax.axhline(0.5, ls="--", label="reference")
    ax.set(xlabel="settlement [m]", ylabel="Nc", title="the footing")
    ax.legend()
    return fig, ax


def test_a_readable_figure_has_no_problems():
    fig, _ = readable()
    assert figure_problems(fig) == []
    pyplot().close(fig)


@pytest.mark.parametrize("spoil, problem", [
    (lambda fig, ax: ax.set_xlabel(""), "no x label"),
    (lambda fig, ax: ax.set_ylabel(""), "no y label"),
    (lambda fig, ax: ax.set_title(""), "no title"),
    (lambda fig, ax: ax.tick_params(labelsize=5), "tick labels of 5 pt"),
    (lambda fig, ax: fig.set_size_inches(14, 2.3), "size 1680 x 276 px"),
    (lambda fig, ax: fig.set_size_inches(2, 2), "size 240 x 240 px"),
    (lambda fig, ax: fig.colorbar(ax.scatter([0], [0], c=[1])), "colour bar without a label"),
])
def test_each_check_finds_its_problem(spoil, problem):
    fig, ax = readable()
    spoil(fig, ax)
    fig.canvas.draw()                       # tick labels exist once drawn
    found = figure_problems(fig)
    pyplot().close(fig)
    assert any(problem in p for p in found), found


def test_a_suptitle_is_a_title_and_an_axis_off_panel_needs_no_labels():
    fig, (a, b) = pyplot().subplots(1, 2, figsize=(8, 4))
    a.plot([0, 1], [1, 0])
    a.set(xlabel="x [m]", ylabel="y [m]")
    b.imshow([[0, 1], [1, 0]])
    b.axis("off")
    fig.suptitle("two panels")
    assert figure_problems(fig) == []
    pyplot().close(fig)
