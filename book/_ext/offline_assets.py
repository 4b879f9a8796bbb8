"""Sphinx extension of this book: pages that load nothing from the network.

* MathJax is served from ``book/_static/mathjax`` (``mathjax_path`` in
  ``_config.yml``; ``book/build.py`` fetches it). Jupyter Book adds every ``.js``
  file under ``_static`` to every page, which would load MathJax's hundreds of
  component files in each page: they are taken out again, and Sphinx's mathjax
  extension loads ``mathjax_path`` alone, on the pages with maths.
* Thebe (live code through a Binder server) is off, but sphinx-thebe still puts
  the address of its script on a CDN in each page: its assets are dropped.
"""
from pathlib import Path

from sphinx.errors import ExtensionError


def _check_mathjax(app):
    path = Path(app.srcdir) / "_static" / app.config.mathjax_path
    if not path.is_file():
        raise ExtensionError(f"offline MathJax not found at {path}: build the book "
                             "with `python book/build.py`, which fetches it")


def _drop_mathjax_components(app, config):
    # Sphinx's mathjax extension adds mathjax_path itself, to pages with maths only
    def name(entry):
        return entry[0] if isinstance(entry, (tuple, list)) else entry
    config.html_js_files = [f for f in config.html_js_files
                            if not str(name(f)).startswith("mathjax/")]


def _is_thebe(js):
    name = str(js.filename or "").removeprefix("_static/")
    body = js.attributes.get("body", "") or ""
    return name == "sphinx-thebe.js" or "THEBE_JS_URL" in body


def _drop_thebe(app, pagename, templatename, context, doctree):
    scripts = context.get("script_files")
    if scripts is not None:
        # in place: this is the builder's list, restored before each page
        scripts[:] = [js for js in scripts if not _is_thebe(js)]


def setup(app):
    app.connect("config-inited", _drop_mathjax_components)
    app.connect("builder-inited", _check_mathjax)
    app.connect("html-page-context", _drop_thebe, priority=900)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
