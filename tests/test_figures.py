"""The figure checks (:func:`pfem_skfem.harness.figures.figure_problems`) find what a reader misses.

The quick suite (``tests/test_verification.py``) applies them to every figure the
verification scripts write; here each check meets a figure that breaks it, so that a
check that cannot fail fails here.
"""
import pytest

from pfem_skfem.harness.figures import figure_problems, pyplot


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
    b.imshow([[[0, 0, 0], [1, 1, 1]], [[1, 1, 1], [0, 0, 0]]])   # a picture (RGB)
    b.axis("off")
    fig.suptitle("two panels")
    assert figure_problems(fig) == []
    pyplot().close(fig)


def test_empty_panels_and_unexplained_colour_are_found():
    fig, (a, b, c) = pyplot().subplots(1, 3, figsize=(12, 4))
    a.scatter([0, 1, 2], [0, 1, 0], c=[0.0, 1.0, 2.0])       # colour means speed: no bar
    a.set(xlabel="x [m]", ylabel="y [m]", title="coloured by speed")
    b.plot([0, 1], [0, 1])
    b.set(xlabel="t [s]", ylabel="V [m2]")
    found = figure_problems(fig)                               # c: nothing drawn
    scripts = figure_problems(fig, content=False)              # without the content checks
    pyplot().close(fig)
    assert not any("empty" in p or "colour" in p for p in scripts), scripts
    assert any("axes 3 (untitled): empty" in p for p in found), found
    assert any("axes 1" in p and "without a colour bar" in p for p in found), found
    assert any("a title speaks of colour" in p for p in found), found


def test_a_colour_bar_or_a_legend_explains_colour():
    fig, (a, b) = pyplot().subplots(1, 2, figsize=(10, 4))
    dots = a.scatter([0, 1, 2], [0, 1, 0], c=[0.0, 1.0, 2.0])
    fig.colorbar(dots, ax=a, label="speed [m/s]")
    b.scatter([0, 1], [1, 0], c=[0.0, 1.0], label="two kinds")
    b.legend()
    for ax in (a, b):
        ax.set(xlabel="x [m]", ylabel="y [m]", title="coloured by speed")
    assert figure_problems(fig) == []
    pyplot().close(fig)


def test_panels_too_narrow_at_the_page_width_are_found():
    # seven panels across 13 in: at a 688 px page each is shrunk to ~60 px
    fig, axes = pyplot().subplots(1, 7, figsize=(13, 3), layout="constrained")
    for ax in axes:
        ax.plot([0, 1], [0, 1])
        ax.set(xlabel="x [m]", ylabel="y [m]", title="a panel")
    assert figure_problems(fig, dpi=100) == []                 # fine as a saved file
    found = figure_problems(fig, dpi=100, page_width=688)
    pyplot().close(fig)
    assert any("axes 1 (a panel)" in p and "at the page's 688 px" in p for p in found), found
    assert any("labels of" in p for p in found), found


def test_a_readable_figure_is_readable_at_the_page_width():
    fig, _ = readable()
    assert figure_problems(fig, dpi=100, page_width=688) == []
    pyplot().close(fig)


def test_a_grid_labels_its_outer_panels_only():
    fig, axes = pyplot().subplots(2, 2, figsize=(7, 6), sharex=True, sharey=True)
    for ax in axes.flat:
        ax.plot([0, 1], [0, 1])
        ax.set_title("a panel")
    for ax in axes[-1]:
        ax.set_xlabel("x [m]")
    for ax in axes[:, 0]:
        ax.set_ylabel("y [m]")
    assert figure_problems(fig, dpi=100, page_width=688) == []
    pyplot().close(fig)


@pytest.mark.parametrize("show", ["", "plt.show()"])
def test_the_book_kernel_fails_a_cell_that_shows_a_bad_figure(tmp_path, monkeypatch, show):
    """``book/_ext/figure_check.py`` as the build starts it: the cell fails, naming it."""
    import json
    from pathlib import Path
    import sys

    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    root = Path(__file__).resolve().parents[1]
    spec = tmp_path / "kernels" / "figcheck"
    spec.mkdir(parents=True)
    (spec / "kernel.json").write_text(json.dumps({
        "argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}",
                 f"--IPKernelApp.exec_files={root / 'book' / '_ext' / 'figure_check.py'}"],
        "display_name": "figcheck", "language": "python"}))
    monkeypatch.setenv("JUPYTER_PATH", str(tmp_path))
    monkeypatch.setenv("PYTHONPATH", str(root))
    monkeypatch.delenv("MPLBACKEND", raising=False)
    monkeypatch.delenv("PFEM_BOOK_FIGURES", raising=False)
    good = ("import matplotlib.pyplot as plt\nfig, ax = plt.subplots(figsize=(6, 4))\n"
            "ax.plot([0, 1]); ax.set(xlabel='t [s]', ylabel='x [m]', title='fine')\n")
    bad = ("fig, axes = plt.subplots(1, 3, figsize=(9, 3))\naxes[0].plot([0, 1])\n"
           "axes[0].set(xlabel='t [s]', ylabel='x [m]', title='two of three')\n" + show)
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(good),
                                         nbformat.v4.new_code_cell(bad)])
    client = nbclient.NotebookClient(nb, kernel_name="figcheck", timeout=120)
    with pytest.raises(nbclient.exceptions.CellExecutionError) as error:
        client.execute()
    text = str(error.value)
    assert "figure 'two of three'" in text and "axes 2 (untitled): empty" in text, text
    assert nb.cells[0].outputs and not any(o.output_type == "error"
                                           for o in nb.cells[0].outputs)


def test_a_picture_without_ticks_needs_no_axis_labels():
    fig, ax = pyplot().subplots(figsize=(6, 4))
    ax.plot([0, 1, 1, 0], [0, 0, 1, 1], "k.")
    ax.set_xticks([]), ax.set_yticks([])
    ax.set_title("a cloud of particles")
    assert figure_problems(fig) == []
    pyplot().close(fig)
