"""The built book as a reader sees it: every page opened in headless Chromium.

Usage (after ``python book/build.py``; ``build.py`` runs it as its last step)::

    python book/browser_check.py                 # every page of book/_build/html
    python book/browser_check.py PAGE.html ...   # some pages

Each page is opened at 1280 x 900 px (a laptop window) with MathJax 3 typesetting it
offline; a script added to a copy of the page waits for MathJax and then reports, and
``chromium --dump-dom`` hands the report back. A page fails on

* a MathJax error element (``mjx-merror``: a TeX command MathJax refused),
* a display equation wider than the content column (clipped or scrolled), or whose
  equation number overlaps it,
* an image that did not load,
* a raw ``$`` or ``\\(`` left in the text (maths that MyST or MathJax did not take),
* a cell output that is a bare object repr (``<matplotlib.legend.Legend at 0x...>``),
* a code cell wider than its box (its longest line cut or scrolled; ``_static/code.css``
  wraps long lines, so this finds a cell that escapes it),
* a docutils error rendered in the page: a red ``.problematic`` span (markup docutils
  could not read, e.g. ``|x|`` in a docstring taken for an undefined substitution) or a
  ``.system-message`` box.

The browser is the Debian package ``chromium`` (``apt-get install chromium``);
:func:`find_chromium` returns None where there is none.
"""
import argparse
import json
import os
from pathlib import Path
import re
import shutil
import subprocess
import sys
import tempfile

BOOK = Path(__file__).resolve().parent
HTML = BOOK / "_build" / "html"
WINDOW = (1280, 900)
ATTEMPTS = 3                # Chromium runs per page before 'no report' is a problem
MARK = "pfem-book-check"

# runs in the page: waits for MathJax, then writes its findings as JSON into <pre id=MARK>
CHECK_JS = r"""
(function () {
  var MARK = "%(mark)s";
  function text(el) { return (el.textContent || "").replace(/\s+/g, " ").trim(); }
  function where(el) {
    var math = el.closest ? el.closest("div.math, .cell_output, section") : null;
    var eqno = math && math.querySelector ? math.querySelector(".eqno") : null;
    if (eqno) return "equation " + text(eqno).replace("#", "");
    var sec = el.closest ? el.closest("section") : null;
    var h = sec && sec.querySelector("h1, h2, h3");
    return h ? "section '" + text(h).replace("#", "") + "'" : "the page";
  }
  function rectOf(el) { return el.getBoundingClientRect(); }
  function overlap(a, b) {
    return a.left < b.right - 1 && b.left < a.right - 1 && a.top < b.bottom - 1 && b.top < a.bottom - 1;
  }
  function check() {
    var problems = [], mjx = window.MathJax, items = [];
    var column = document.querySelector("article.bd-article") || document.querySelector("main") || document.body;
    var col = rectOf(column);
    var style = getComputedStyle(column);
    var right = col.right - parseFloat(style.paddingRight || "0");
    var left = col.left + parseFloat(style.paddingLeft || "0");
    try { items = Array.from(mjx.startup.document.math); } catch (e) { items = []; }
    var tex = new Map();
    items.forEach(function (m) { if (m.typesetRoot) tex.set(m.typesetRoot, m.math); });
    document.querySelectorAll("mjx-merror").forEach(function (e) {
      var root = e.closest("mjx-container");
      problems.push("MathJax error '" + (e.getAttribute("data-mjx-error") || text(e)) + "' in " +
                    where(root || e) + ": " + String(tex.get(root) || "").slice(0, 120));
    });
    document.querySelectorAll("mjx-container[display='true']").forEach(function (root) {
      var box = root.querySelector("mjx-math"), r = rectOf(box);
      var src = String(tex.get(root) || "").slice(0, 80);
      var frame = root.parentElement ? rectOf(root.parentElement) : rectOf(root);
      var limit = Math.min(right, frame.right);
      if (r.right > limit + 1 || r.left < Math.max(left, frame.left) - 1 ||
          root.scrollWidth > root.clientWidth + 1) {
        problems.push("display equation wider than the column (" + Math.round(r.width) + " px of " +
                      Math.round(limit - Math.max(left, frame.left)) + ") in " + where(root) + ": " + src);
      }
      var labels = [root.querySelector("mjx-labels")];
      var div = root.closest("div.math");
      if (div) labels.push(div.querySelector(".eqno"));
      labels.forEach(function (lab) {
        if (!lab) return;
        var body = root.querySelector("mjx-itable, mjx-mtable") || box;
        var cells = lab.tagName.toLowerCase() === "mjx-labels" ? lab.querySelectorAll("mjx-mtd") : [lab];
        var parts = body.querySelectorAll("mjx-mtd, mjx-mrow");
        cells.forEach(function (cell) {
          var c = rectOf(cell);
          if (c.width === 0) return;
          if (c.right > right + 1) {
            problems.push("equation number " + text(cell) + " runs out of the column: " + src);
            return;
          }
          if (lab.tagName.toLowerCase() !== "mjx-labels") { if (overlap(c, r)) problems.push(
            "equation number " + text(cell) + " overlaps its equation: " + src); return; }
          for (var i = 0; i < parts.length; i++) {
            if (parts[i].closest("mjx-labels")) continue;
            var p = rectOf(parts[i]);
            if (p.width > 0 && overlap(c, p) && !parts[i].contains(cell)) {
              problems.push("equation number " + text(cell) + " overlaps its equation: " + src);
              break;
            }
          }
        });
      });
    });
    column.querySelectorAll("img").forEach(function (img) {
      if (!img.complete || img.naturalWidth === 0)
        problems.push("image not loaded: " + (img.getAttribute("src") || "").slice(0, 100) + " in " + where(img));
    });
    var walker = document.createTreeWalker(column, NodeFilter.SHOW_TEXT, null);
    var skip = "PRE, CODE, SCRIPT, STYLE, TEXTAREA, MJX-CONTAINER, .highlight, #" + MARK;
    for (var node = walker.nextNode(); node; node = walker.nextNode()) {
      var el = node.parentElement;
      if (!el || el.closest(skip)) continue;
      var t = node.nodeValue;
      if (/\$/.test(t) || /\\[(\[]/.test(t))
        problems.push("raw maths in the text of " + where(el) + ": '" + t.trim().slice(0, 100) + "'");
    }
    column.querySelectorAll(".cell_output, .output").forEach(function (out) {
      var m = text(out).match(/<[\w.]+(?: object)? at 0x[0-9a-fA-F]+>/g);
      if (m) m.forEach(function (s) { problems.push("a bare object repr in an output: " + s + " in " + where(out)); });
    });
    // a code cell cut (or scrolled) where its longest line is wider than its box; outputs
    // are left to scroll (a printed table keeps its columns)
    var n_code = 0;
    column.querySelectorAll("div.highlight pre").forEach(function (code) {
      if (code.id === MARK || code.closest(".cell_output, .output")) return;
      n_code += 1;
      if (code.scrollWidth > code.clientWidth + 1) {
        var longest = "";
        (code.textContent || "").split("\n").forEach(function (l) {
          if (l.length > longest.length) longest = l;
        });
        problems.push("a code cell wider than its box (" + code.scrollWidth + " px of " +
                      code.clientWidth + ") in " + where(code) + ": '" + longest.trim().slice(0, 80) + "'");
      }
    });
    // what docutils renders for markup it could not read: a red span, a message box
    column.querySelectorAll(".problematic, .system-message").forEach(function (el) {
      problems.push("a docutils error rendered (" + (el.classList.contains("problematic") ?
                    "problematic" : "system-message") + "): '" + text(el).slice(0, 80) +
                    "' in " + where(el));
    });
    var pre = document.createElement("pre");
    pre.id = MARK;
    pre.textContent = JSON.stringify({problems: problems, equations: items.length,
                                      images: column.querySelectorAll("img").length,
                                      code: n_code, column: Math.round(right - left)});
    document.body.appendChild(pre);
  }
  function start() {
    if (window.MathJax && MathJax.startup && MathJax.startup.promise) {
      MathJax.startup.promise.then(function () { setTimeout(check, 200); });
    } else if (document.querySelector("script[src*='mathjax']") && (start.tries = (start.tries || 0) + 1) < 100) {
      setTimeout(start, 100);
    } else {
      check();
    }
  }
  if (document.readyState === "complete") start(); else window.addEventListener("load", start);
})();
"""


def find_chromium():
    """The path of a Chromium (or Chrome) executable, or None."""
    for name in ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable"):
        path = shutil.which(name)
        if path:
            return path
    return None


def check_page(html, chromium=None, timeout=120):
    """Open ``html`` in headless Chromium; return (problems, counts).

    Parameters
    ----------
    html : path
        A page of the built book (its ``_static`` relative to it).
    chromium : str, optional
        The browser (default :func:`find_chromium`).

    Returns
    -------
    problems : list of str
    counts : dict
        ``equations`` typeset and ``images`` in the content column.
    """
    chromium = chromium or find_chromium()
    html = Path(html).resolve()
    text = html.read_text(errors="replace")
    script = "<script>" + CHECK_JS % {"mark": MARK} + "</script>"
    page = html.with_name(f".{html.stem}.{MARK}.html")   # next to it: relative links work
    page.write_text(text.replace("</body>", script + "</body>") if "</body>" in text
                    else text + script)
    try:
        with tempfile.TemporaryDirectory() as profile:
            cmd = [chromium, "--headless", "--no-sandbox", "--disable-gpu",
                   "--disable-dev-shm-usage", "--allow-file-access-from-files",
                   "--hide-scrollbars", f"--window-size={WINDOW[0]},{WINDOW[1]}",
                   f"--user-data-dir={profile}", "--virtual-time-budget=60000",
                   "--run-all-compositor-stages-before-draw", "--dump-dom", page.as_uri()]
            for _ in range(ATTEMPTS):    # a Chromium that exits without the page's report
                proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout,
                                      env={**os.environ, "HOME": profile})
                # (the theme may add attributes, e.g. tabindex, to a <pre> of a page without maths)
                m = re.search(rf'<pre id="{MARK}"[^>]*>(.*?)</pre>', proc.stdout, re.S)
                if m:                     # failed itself (seen once in ~30 runs): try again
                    break
    finally:
        page.unlink(missing_ok=True)
    if not m:
        return [f"no report from Chromium (exit code {proc.returncode}): "
                f"{proc.stderr.strip()[-300:]}"], {}
    import html as html_lib
    data = json.loads(html_lib.unescape(m[1]))
    problems = data.pop("problems")
    return problems, data


def book_pages(root=HTML):
    """The content pages of the built book (no search, index or hidden pages)."""
    skip = {"search.html", "genindex.html", "py-modindex.html"}
    return sorted(p for p in Path(root).glob("*.html")
                  if p.name not in skip and not p.name.startswith(".")
                  and 'http-equiv="refresh"' not in p.read_text(errors="replace")[:2000].lower())


def check_pages(pages=None):
    """Check ``pages`` (default: every page of the built book), printing what is found.

    Returns
    -------
    int or None
        The number of pages with problems; None where there is no Chromium.
    """
    chromium = find_chromium()
    if chromium is None:
        print("[browser] warning: no Chromium (Debian: apt-get install chromium): "
              "the pages were not opened in a browser", flush=True)
        return None
    pages = [Path(x) for x in pages] if pages else book_pages()
    failed = 0
    for page in pages:
        problems, counts = check_page(page, chromium)
        print(f"[browser] {page.name}: {counts.get('equations', '?')} equation(s), "
              f"{counts.get('images', '?')} image(s), {counts.get('code', '?')} code block(s) "
              f"in a column of {counts.get('column', '?')} px, {len(problems)} problem(s)",
              flush=True)
        for line in problems:
            print(f"[browser]   {line}")
        failed += bool(problems)
    print(f"[browser] {len(pages) - failed}/{len(pages)} page(s) without problems at "
          f"{WINDOW[0]} x {WINDOW[1]} px", flush=True)
    return failed


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("pages", nargs="*", help="pages (default: every page of book/_build/html)")
    args = p.parse_args(argv)
    return 1 if check_pages(args.pages) else 0


if __name__ == "__main__":
    sys.exit(main())
