"""Figures of the verification scripts and the book: the pyplot backend, the output
folder, saving, and the checks of what a reader cannot read (:func:`figure_problems`,
:func:`inspect_figures`).
"""
from pathlib import Path
import sys

import numpy as np

def pyplot():
    """matplotlib.pyplot, on the Agg backend unless pyplot is already in use (a notebook)."""
    import matplotlib
    if "matplotlib.pyplot" not in sys.modules:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def figure_dir(args, name):
    """``args.outdir / name``, created (``OUTDIR/quick/name`` for a ``--quick`` run: the
    parser, :class:`.options.ScriptParser`, puts its ``outdir`` apart)."""
    out = Path(args.outdir) / name
    out.mkdir(parents=True, exist_ok=True)
    return out


FIGURE_PIXELS = ((400, 2600), (250, 2000))
"""The (min, max) width and height of a saved figure in pixels."""
SMALLEST_FONT = 7.0
"""Tick labels and axis labels at least this many points (at the saved dpi: readable)."""
LEGIBLE_AXES_PX = (160, 100)
"""The least width and height of a panel with data, in CSS pixels as a page shows it."""
LEGIBLE_TEXT_PX = 8.0
"""The least size of a tick or axis label, in CSS pixels as a page shows it."""
COLOUR_WORDS = r"\bcolou?r(?:ed|s)?\b"
"""A title matching this (case aside) says that colour means something."""


def _is_colorbar(ax):
    return hasattr(ax, "_colorbar") or ax.get_label() == "<colorbar>"


def _has_content(ax):
    return bool(ax.lines or ax.collections or ax.images or ax.patches or ax.texts
                or ax.tables or ax.artists or ax.get_legend())


def _labelled_sibling(ax, axis):
    """A panel sharing ``ax``'s ``axis`` has the label (a grid labels its outer panels)."""
    shared = ax.get_shared_x_axes() if axis == "x" else ax.get_shared_y_axes()
    return any(getattr(other, f"get_{axis}label")().strip()
               for other in shared.get_siblings(ax) if other is not ax)


def _colour_mapped(ax):
    """The artists of ``ax`` whose colour encodes a quantity (a varying array, colormap)."""
    found = []
    for artist in [*ax.collections, *ax.images]:
        data = artist.get_array() if hasattr(artist, "get_array") else None
        if data is None or np.ndim(data) != 1 and not (np.ndim(data) == 2
                                                        and artist in ax.images):
            continue                         # no colour mapping, or an RGB(A) picture
        values = np.ma.compressed(np.ma.masked_invalid(np.asarray(data, dtype=float)))
        if values.size and np.ptp(values) > 0:
            found.append(artist)
    return found


def _colour_explained(fig, ax, artist, colorbars):
    """A colour bar of the same colormap and range, a legend, or contour labels."""
    if ax.get_legend() is not None or getattr(artist, "labelTexts", None):
        return True
    for cb in colorbars:
        m = cb.mappable
        if m is artist or (m.get_cmap().name == artist.get_cmap().name
                           and m.get_clim() == artist.get_clim()):
            return True
    return False


def _page_problems(fig, axes, page_width):
    """Panels and labels too small once ``fig`` is shown at ``page_width`` CSS pixels."""
    fig.canvas.draw()                        # aspect-fixed axes take their final size
    renderer = fig.canvas.get_renderer()
    width = fig.get_tightbbox(renderer).width * fig.dpi    # as shown inline: cropped
    scale = min(1.0, page_width / width)    # a PNG pixel is a CSS pixel, shrunk to fit
    (w_min, h_min), problems = LEGIBLE_AXES_PX, []
    for i, ax in axes:
        name = f"axes {i + 1} ({ax.get_title() or 'untitled'})"
        box = ax.get_window_extent(renderer)
        w, h = box.width * scale, box.height * scale
        if w < w_min or h < h_min:
            problems.append(f"{name}: {w:.0f} x {h:.0f} px at the page's {page_width} px "
                            f"(want at least {w_min} x {h_min}: fewer or larger panels)")
        texts = [ax.xaxis.label, ax.yaxis.label, *ax.get_xticklabels(), *ax.get_yticklabels()]
        sizes = [t.get_fontsize() * fig.dpi / 72 * scale for t in texts
                 if t.get_visible() and t.get_text()]
        if sizes and min(sizes) < LEGIBLE_TEXT_PX:
            problems.append(f"{name}: labels of {min(sizes):.1f} px at the page's "
                            f"{page_width} px (want {LEGIBLE_TEXT_PX:g}: a narrower figure)")
    return problems


def figure_problems(fig, dpi=120, page_width=None, content=True):
    """What makes ``fig`` hard to read, before it is saved; an empty list when nothing.

    Every figure has a title (an axes title or ``suptitle``) and a saved size within
    :data:`FIGURE_PIXELS`, no wider than 4.5 times its height; every visible axes
    has something drawn in it; every axes with data has x and y labels (a colour bar:
    its label; an axis without ticks, a picture's, or sharing a labelled one: none),
    and its tick labels are at least :data:`SMALLEST_FONT` points; colour
    that encodes a quantity (a scatter's ``c``, an image, a ``tripcolor``) has a colour
    bar (or a legend), and a title that speaks of colour has one too. Given
    ``page_width``, the figure is judged as a page shows it (scaled down to that many
    CSS pixels when wider): each panel with data at least :data:`LEGIBLE_AXES_PX`,
    its labels at least :data:`LEGIBLE_TEXT_PX`.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    dpi : float
        The resolution it will be saved at.
    page_width : float, optional
        The width of the page's content column in CSS pixels (the book's).
    content : bool
        Check for empty panels and for colour without a colour bar (default).

    Returns
    -------
    list of str
    """
    import re
    problems = []
    w, h = fig.get_size_inches() * dpi
    (w0, w1), (h0, h1) = FIGURE_PIXELS
    if not (w0 <= w <= w1 and h0 <= h <= h1) or w > 4.5 * h:
        problems.append(f"size {w:.0f} x {h:.0f} px (want {w0}-{w1} x {h0}-{h1}, "
                        "at most 4.5:1)")
    suptitle = fig._suptitle.get_text() if getattr(fig, "_suptitle", None) else ""
    axes = [ax for ax in fig.get_axes() if ax.get_visible()]
    if not suptitle and not any(ax.get_title() or ax.get_title("left") for ax in axes):
        problems.append("no title: say what the figure shows (set_title or suptitle)")
    colorbars = [ax._colorbar for ax in axes if getattr(ax, "_colorbar", None)]
    titles = [suptitle] + [ax.get_title() for ax in axes]
    speaks_of_colour = any(re.search(COLOUR_WORDS, t, re.I) for t in titles)
    legends = any(ax.get_legend() for ax in axes)
    if content and speaks_of_colour and not colorbars and not legends:
        problems.append("a title speaks of colour but there is no colour bar (or legend)")
    with_data = []
    for i, ax in enumerate(axes):
        name = f"axes {i + 1} ({ax.get_title() or 'untitled'})"
        if _is_colorbar(ax):
            if ax.axison and not (ax.get_ylabel() or ax.get_xlabel()):
                problems.append(f"{name}: a colour bar without a label")
            continue
        if not _has_content(ax):
            if content:
                problems.append(f"{name}: empty (nothing drawn: remove it)")
            continue
        for artist in _colour_mapped(ax) if content else ():
            if not _colour_explained(fig, ax, artist, colorbars):
                problems.append(f"{name}: colour encodes a quantity "
                                f"({type(artist).__name__}) without a colour bar")
                break
        with_data.append((i, ax))
        if not ax.axison:
            continue
        for axis, label in (("x", ax.get_xlabel()), ("y", ax.get_ylabel())):
            ticked = len(getattr(ax, f"get_{axis}ticks")()) > 0   # no ticks: a picture
            if ticked and not label.strip() and not _labelled_sibling(ax, axis):
                problems.append(f"{name}: no {axis} label")
        for tick in ax.get_xticklabels() + ax.get_yticklabels():
            if tick.get_visible() and tick.get_fontsize() < SMALLEST_FONT:
                problems.append(f"{name}: tick labels of {tick.get_fontsize():g} pt")
                break
    if page_width is not None and with_data:
        problems += _page_problems(fig, with_data, page_width)
    return problems


def inspect_figures(script, argv, outdir):
    """Draw ``script``'s figures at ``argv`` (a quick run) and report what is hard to read.

    Runs the case in-process, then its ``figures`` with every :func:`save_figure`
    checked by :func:`figure_problems` before it saves; the other pictures it writes
    (pyvista PNGs) are checked for their size.

    Returns
    -------
    (Report, dict)
        The report, and for each file written, the list of its problems.
    """
    import matplotlib.image as mpimg

    args = script.build_parser().parse_args(["--quiet", *argv, "--outdir", str(outdir)])
    report = script.run(args)
    found = {}
    original = getattr(script, "save_figure", None)

    def checked(fig, path, dpi=120):
        found[str(path)] = figure_problems(fig, dpi)
        save_figure(fig, path, dpi)

    script.save_figure = checked
    try:
        script.figures(args, **report.data)
    finally:
        if original is not None:
            script.save_figure = original
    (w0, w1), (h0, h1) = FIGURE_PIXELS
    for png in sorted(Path(outdir).rglob("*.png")):
        if str(png) in found:
            continue
        h, w = mpimg.imread(png).shape[:2]
        found[str(png)] = ([] if w0 <= w <= w1 and h0 <= h <= h1 else
                           [f"picture of {w} x {h} px"])
    return report, found


def labelled(ax, xlabel, ylabel, title=None, *, legend=7, title_size=None):
    """Label a panel as :func:`figure_problems` wants it: its x and y labels, its title (of
    ``title_size`` points, matplotlib's default if None) and, unless ``legend`` is None or
    nothing drawn has a label, a legend of ``legend`` points. Returns ``ax``."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if title is not None:
        ax.set_title(title, fontsize=title_size)
    if legend is not None and ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=legend)
    return ax


def write_summary(folder, data, name="summary.json"):
    """Write ``data`` beside the figures as ``folder / name``, indented JSON (arrays and
    numpy numbers as lists and numbers, any other object as its string); returns the path."""
    import json

    path = Path(folder) / name
    path.write_text(json.dumps(data, indent=1, default=lambda o: o.tolist()
                               if hasattr(o, "tolist") else str(o)))
    return path


def save_figure(fig, path, dpi=120):
    """Lay out ``fig`` (unless it has a layout engine), write it to ``path`` and close it."""
    engine = getattr(fig, "get_layout_engine", lambda: None)()
    if engine is None or type(engine).__name__ == "PlaceHolderLayoutEngine":
        fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    pyplot().close(fig)
