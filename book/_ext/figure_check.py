"""The figure checks of the test suite on every figure a page of the book shows.

``book/build.py`` starts each page's kernel with this file (``IPKernelApp.exec_files``
in the kernel spec it writes). It registers two IPython hooks:

* ``post_execute``, registered before matplotlib's inline backend registers its own
  (which shows and closes the figures open at the end of a cell), and a wrapper
  of ``pyplot.show`` (which shows and closes them mid-cell): each figure is
  checked by :func:`pfem_skfem.harness.figures.figure_problems` at the page's width
  (``PFEM_BOOK_PAGE_WIDTH`` CSS pixels) as it is about to be shown;
* ``post_run_cell``: a cell that showed a figure with problems fails
  (``FigureProblems``, naming each figure by its title), so the page's execution
  fails and with it the build, which names the page. With ``PFEM_BOOK_FIGURES=warn``
  the problems are printed in the cell's output instead (to survey a whole book).

Hooks rather than an edit of every page: a page cannot forget them, and a figure
is checked as drawn, after every call the cell made on it.
"""


def _register(shell):
    import os

    from pfem_skfem.harness.figures import figure_problems

    page_width = float(os.environ.get("PFEM_BOOK_PAGE_WIDTH", "688"))
    warn = os.environ.get("PFEM_BOOK_FIGURES") == "warn"
    found = []

    class FigureProblems(AssertionError):
        """A figure of this cell that a reader of the page would find hard to read."""

    def check_open_figures():
        if "matplotlib.pyplot" not in __import__("sys").modules:
            return
        from matplotlib._pylab_helpers import Gcf
        for manager in Gcf.get_all_fig_managers():
            fig = manager.canvas.figure
            if getattr(fig, "_book_checked", False):
                continue
            fig._book_checked = True
            title = fig._suptitle.get_text() if fig._suptitle else ""
            title = title or next((ax.get_title() for ax in fig.axes if ax.get_title()),
                                  "untitled")
            problems = figure_problems(fig, dpi=fig.dpi, page_width=page_width)
            if problems:
                found.append(f"figure '{title}':\n  " + "\n  ".join(problems))

    def fail_cell(result):
        if not found:
            return
        text = f"{len(found)} figure(s) hard to read at {page_width:g} px:\n" + "\n".join(found)
        found.clear()
        if warn:
            print("[figure check] " + text, file=__import__("sys").stderr)
            return
        try:
            raise FigureProblems(text)
        except FigureProblems as error:
            shell.showtraceback()
            if result is not None and result.error_in_exec is None:
                result.error_in_exec = error    # the cell fails: the kernel replies 'error'

    shell.events.register("post_execute", check_open_figures)   # before the inline flush
    shell.events.register("post_run_cell", fail_cell)

    import matplotlib.pyplot as plt
    show = plt.show

    def checked_show(*args, **kwargs):
        check_open_figures()
        return show(*args, **kwargs)

    plt.show = checked_show


_register(get_ipython())  # noqa: F821 (run by IPython, which defines get_ipython)
del _register
