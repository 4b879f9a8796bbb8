"""book/build.py without building the book: its count of the docutils errors a page renders,
the table of contents of a ``--pages`` build, and the warnings such a build does not count."""
from pathlib import Path

import pytest
import yaml

from tests.test_book_browser import DEFECTS, PAGE

BOOK = Path(__file__).resolve().parents[1] / "book"


@pytest.fixture
def build(tmp_path, monkeypatch):
    """book/build.py as a module, writing its table of contents under tmp_path."""
    from book import build as module
    monkeypatch.setattr(module, "BUILD", tmp_path / "_build")
    return module


def test_rendered_docutils_errors_are_counted_page_by_page(build, tmp_path):
    """The red span of ``|q_j|`` taken for a substitution, and a system-message box (its
    title, class system-message-title, not counted again); a clean page has none."""
    clean, bad = tmp_path / "clean.html", tmp_path / "api.html"
    clean.write_text(PAGE.format(mathjax="", defects=""))
    bad.write_text(PAGE.format(mathjax="", defects=DEFECTS["a docutils error rendered "
                                                            "(problematic)"] * 2
                               + DEFECTS["a docutils error rendered (system-message)"]))
    assert build.docutils_errors([clean]) == []
    assert build.docutils_errors([clean, bad]) == [
        "api.html renders 3 docutils error(s) (problematic, system-message)"]


def test_a_pages_build_keeps_the_root_and_the_chapters_named(build):
    """``--pages api``: the root and the one chapter, its part's caption kept, no other part."""
    _, toc = build.write_toc(["api"])
    assert toc["root"] == "intro"
    assert toc["parts"] == [{"caption": "Appendices", "chapters": [{"file": "api"}]}]
    assert list(build._pages(toc)) == ["intro", "api"]
    _, whole = build.write_toc(None)
    full = yaml.safe_load((BOOK / "_toc.yml").read_text())
    assert len(whole["parts"]) == len(full["parts"])


def test_a_pages_build_does_not_count_links_to_the_pages_it_left_out(build):
    warnings = [
        "/b/intro.md:59: WARNING: Unknown source document 'silo' [myst.xref_missing]",
        "/b/intro.md:60: WARNING: Unknown source document 'no_such_page' [myst.xref_missing]",
        "/p/contact.py:docstring of CoulombCones:1: ERROR: Undefined substitution "
        "referenced: \"slip\".",
    ]
    assert build.left_out_warnings(warnings, {"silo", "statics"}) == warnings[1:]
