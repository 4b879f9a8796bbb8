"""The book in a real browser (headless Chromium): the checks of ``book/browser_check.py``.

``test_the_checker_finds_every_kind_of_defect`` opens a small page with one defect of
each kind (a MathJax error, an equation wider than the column, a missing image, a raw
``$``, a bare object repr, a code cell wider than its box, a docutils error rendered as a
red ``.problematic`` span or a ``.system-message`` box) and a clean page, so that a
check that cannot fail fails here (tests/test_book_build.py: ``book/build.py``'s count of
the same spans in the HTML, without a browser). ``test_every_page_of_the_built_book_reads_well`` opens every page of
``book/_build/html`` (``python book/build.py`` writes it, and runs the same check).
Both skip, saying why, where there is no Chromium (Debian: ``apt-get install chromium``)
or no MathJax copy / no built book.
"""
from pathlib import Path

import pytest

from book import browser_check

ROOT = Path(__file__).resolve().parents[1]
BOOK = ROOT / "book"

MATHJAX = BOOK / "_static" / "mathjax" / "tex-chtml.js"
needs_chromium = pytest.mark.skipif(
    browser_check.find_chromium() is None,
    reason="no Chromium to open the book in (Debian: apt-get install chromium)")
needs_mathjax = pytest.mark.skipif(
    not MATHJAX.is_file(), reason="no book/_static/mathjax (python book/build.py fetches it)")

PAGE = """<!DOCTYPE html><html><head><meta charset="utf-8">
<script defer src="{mathjax}"></script></head>
<body><article class="bd-article" style="width: 600px; padding: 0 20px">
<section><h1>A page</h1>
<p>Inline maths \\(a + b\\) and a display equation:</p>
<div class="math">\\[ E = m c^2 \\]</div>
<div class="highlight"><pre>print("a code cell that fits")</pre></div>
{defects}
</section></article></body></html>"""

DEFECTS = {
    "MathJax error": '<div class="math">\\[\\begin{split} a &= b \\tag{3.45} \\end{split}\\]</div>',
    "wider than the column": '<div class="math">\\[ ' + " + ".join(f"x_{{{i}}}^2" for i in range(60))
                             + " \\]</div>",
    "image not loaded": '<img src="no_such_figure.png" alt="missing">',
    "raw maths": "<ul><li>+ \\Delta\\lambda \\nabla F$. In</li></ul>",
    "bare object repr": '<div class="cell_output"><pre>&lt;matplotlib.legend.Legend at '
                        '0x7f3a2c1d9e50&gt;</pre></div>',
    "a code cell wider than its box": ('<div class="highlight"><pre>total = '
                                       + " + ".join(f"term_{i}" for i in range(40))
                                       + "</pre></div>"),
    # what Sphinx renders for ``|q_j| <= mu p`` in a docstring (an undefined substitution)
    "a docutils error rendered (problematic)": '<p>the cone <a class="problematic" '
                                               'href="#id1" id="id2">|q_j|</a> &lt;= mu p</p>',
    "a docutils error rendered (system-message)": '<div class="system-message"><p class='
                                                  '"system-message-title">System Message: '
                                                  'ERROR/3</p></div>',
}


def page(tmp_path, defects=""):
    path = tmp_path / "page.html"
    path.write_text(PAGE.format(mathjax=MATHJAX.as_uri(), defects=defects))
    return path


@needs_chromium
@needs_mathjax
def test_a_clean_page_has_no_problems(tmp_path):
    problems, counts = browser_check.check_page(page(tmp_path))
    assert problems == []
    assert counts["equations"] == 2                     # MathJax ran: two formulas typeset


@needs_chromium
@needs_mathjax
def test_the_checker_finds_every_kind_of_defect(tmp_path):
    problems, _ = browser_check.check_page(page(tmp_path, "\n".join(DEFECTS.values())))
    for kind in DEFECTS:
        assert any(kind in line for line in problems), f"{kind!r} not found in {problems}"
    assert any("\\tag not allowed in split environment" in line for line in problems)


@needs_chromium
def test_every_page_of_the_built_book_reads_well():
    html = BOOK / "_build" / "html"
    pages = browser_check.book_pages(html) if html.is_dir() else []
    if not pages:
        pytest.skip("the book is not built (python book/build.py)")
    stale = [p.name for p in pages if (BOOK / p.with_suffix(".md").name).is_file()
             and (BOOK / p.with_suffix(".md").name).stat().st_mtime > p.stat().st_mtime]
    if stale:
        pytest.skip(f"the built {', '.join(stale)} older than the pages (python book/build.py)")
    found = {p.name: browser_check.check_page(p)[0] for p in pages}
    assert {name: lines for name, lines in found.items() if lines} == {}
