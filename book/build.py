"""Build the book: offline MathJax, the pages that exist, executed, then checked.

Usage (from the repository root, in an environment with the ``book`` extras)::

    python book/build.py            # full build into book/_build/html
    python book/build.py --pages silo --figures warn   # one chapter; list figure problems
    python book/build.py --allow-warnings   # list Sphinx warnings without failing on them

Steps:

1. MathJax. ``book/_static/mathjax`` is filled from the npm package
   ``mathjax@3.2.2`` (``npm pack``, then its ``es5/`` folder), once; ``_config.yml``
   points ``mathjax_path`` at it, so the pages render maths with no network.
2. Table of contents. ``book/_toc.yml`` lists every planned page; the build uses
   a copy, ``book/_build/_toc.yml``, without the pages whose file does not exist
   yet, and says which it left out.
3. ``jupyter-book build`` with every page executed (``execute_notebooks: force``);
   an error in a cell fails the build, and so does any Sphinx warning (``-W
   --keep-going``: an ERROR in a docstring, ``|x|`` read as an RST substitution, shows
   as a red span in the page; ``--allow-warnings`` lists them without failing). A
   ``--pages`` build does not fail on the links to the pages it left out. The
   repository root is put first on
   ``PYTHONPATH`` so that the pages run this checkout's package. Every figure a
   page shows is checked as the scripts' figures are, at the page's width
   (``book/_ext/figure_check.py``, which the kernel runs first): a figure with
   a problem fails its cell, and the build names the page and the figure.
4. Checks on the HTML: every listed page was written (with its number of
   figures printed), the local MathJax is there and each page loads at most one
   MathJax script, and no page loads anything from another host or names a CDN.
   The execution time of each page and the Sphinx warnings are printed.
5. Every page opened in headless Chromium at 1280 x 900 px (``book/browser_check.py``;
   ``python book/browser_check.py`` runs this step alone on a built book): no MathJax
   error, no display equation wider than the content column, every image loaded, no
   raw ``$`` in the text, no bare object repr in an output, no code cell wider than
   its box, no docutils error rendered in the page (``.problematic``,
   ``.system-message``; step 4 counts these in the HTML too). Without Chromium (Debian
   package ``chromium``) this step is skipped with a warning (``--no-browser`` skips it).

``bash scripts/book.sh`` (its arguments passed on) makes ``.venv``, installs the
``book`` extras and runs this script; the book is ``book/_build/html/index.html``.

Exit code 0 only if all of this holds.
"""
import argparse
import json
import os
from pathlib import Path
import re
import shutil
import subprocess
import sys
import tarfile
import tempfile
import time

import yaml

BOOK = Path(__file__).resolve().parent
ROOT = BOOK.parent
MATHJAX = "mathjax@3.2.2"
MATHJAX_DIR = BOOK / "_static" / "mathjax"
BUILD = BOOK / "_build"
HTML = BUILD / "html"
PAGE_SUFFIXES = (".md", ".ipynb", ".rst")
FIGURE_CHECK = BOOK / "_ext" / "figure_check.py"
PAGE_WIDTH = 688   # CSS px: the content column in browser_check's 1280 px window (measured)

# a script, style sheet or font fetched from another host when a page is opened
REMOTE_LOAD = re.compile(
    r"""<(?:script|link|img|iframe)\b[^>]*?\b(?:src|href)\s*=\s*["']((?:https?:)?//[^"']+)""",
    re.IGNORECASE)
# links (<a href>) may point anywhere; what a page loads may not
CDN = re.compile(r"\b(?:cdn[\w.-]*\.[a-z]+|unpkg\.com|jsdelivr\.net|cdnjs\.cloudflare\.com"
                 r"|ajax\.googleapis\.com|fonts\.googleapis\.com|code\.jquery\.com)\b",
                 re.IGNORECASE)
EXECUTED = re.compile(r"(\S+): Executed notebook in ([\d.]+) seconds")
ANSI = re.compile(r"\x1b\[[0-9;]*m")
MATHJAX_SCRIPT = re.compile(r"<script\b[^>]*\bsrc=[\"'][^\"']*mathjax/", re.IGNORECASE)
# what docutils renders for markup it could not read (an undefined |substitution|, ...)
DOCUTILS_ERROR = re.compile(
    r"""<\w+\b[^>]*\bclass=["'](?:[^"']*\s)?(problematic|system-message)(?=["'\s])""")
XREF_MISSING = re.compile(r"Unknown source document '([^']+)' \[myst\.xref_missing\]")


def log(msg):
    print(f"[book] {msg}", flush=True)


def ensure_mathjax():
    """Put MathJax's es5 build in book/_static/mathjax (from npm) unless it is there."""
    if (MATHJAX_DIR / "tex-chtml.js").is_file():
        log(f"MathJax already in {MATHJAX_DIR.relative_to(ROOT)}")
        return
    npm = shutil.which("npm")
    if npm is None:
        raise SystemExit("[book] error: npm is needed once to fetch MathJax "
                         f"({MATHJAX}) for offline maths; install Node.js/npm")
    with tempfile.TemporaryDirectory() as tmp:
        log(f"npm pack {MATHJAX}")
        out = subprocess.run([npm, "pack", MATHJAX, "--silent"], cwd=tmp,
                             capture_output=True, text=True, stdin=subprocess.DEVNULL)
        if out.returncode != 0:
            raise SystemExit(f"[book] error: `npm pack {MATHJAX}` failed "
                             f"(exit code {out.returncode}):\n{out.stderr.strip()}")
        tarball = Path(tmp) / out.stdout.strip().splitlines()[-1]
        with tarfile.open(tarball) as tar:
            members = [m for m in tar.getmembers() if m.name.startswith("package/es5/")]
            # the safe "data" filter where this Python has it (3.11.4+)
            safe = {"filter": "data"} if hasattr(tarfile, "data_filter") else {}
            tar.extractall(tmp, members=members, **safe)
        staging = MATHJAX_DIR.with_name("mathjax.partial")
        shutil.rmtree(staging, ignore_errors=True)
        shutil.copytree(Path(tmp) / "package" / "es5", staging)
        shutil.rmtree(MATHJAX_DIR, ignore_errors=True)
        staging.rename(MATHJAX_DIR)   # complete or absent, never half copied
    log(f"MathJax copied to {MATHJAX_DIR.relative_to(ROOT)}")


def _page_exists(name):
    path = BOOK / name
    if path.suffix in PAGE_SUFFIXES:
        return path.is_file()
    return any(path.with_name(path.name + s).is_file() for s in PAGE_SUFFIXES)


def _filter_entries(entries, missing):
    kept = []
    for entry in entries:
        entry = dict(entry)
        if "file" in entry and not _page_exists(entry["file"]):
            missing.append(entry["file"])
            continue
        for key in ("sections", "chapters"):
            if key in entry:
                entry[key] = _filter_entries(entry[key], missing)
                if not entry[key]:
                    del entry[key]
        if "parts" in entry:
            entry["parts"] = [p for p in (_filter_part(p, missing) for p in entry["parts"]) if p]
        kept.append(entry)
    return kept


def _filter_part(part, missing):
    part = dict(part)
    part["chapters"] = _filter_entries(part.get("chapters", []), missing)
    return part if part["chapters"] else None


def write_toc(only=None):
    """Copy book/_toc.yml to book/_build/_toc.yml without the pages not written yet.

    ``only``: page names; the other chapters are left out as well (the root stays).
    """
    toc = yaml.safe_load((BOOK / "_toc.yml").read_text())
    if only:
        keep = {Path(p).stem for p in only}
        if "chapters" in toc:
            toc["chapters"] = [c for c in toc["chapters"] if Path(c["file"]).stem in keep]
        for part in toc.get("parts", []):          # the chapters of a toc in parts
            part["chapters"] = [c for c in part.get("chapters", [])
                                if Path(c["file"]).stem in keep]
        if "parts" in toc:
            toc["parts"] = [p for p in toc["parts"] if p["chapters"]]
            if not toc["parts"]:
                del toc["parts"]
    if not _page_exists(toc["root"]):
        raise SystemExit(f"[book] error: the root page {toc['root']!r} does not exist")
    missing = []
    for key in ("chapters", "sections"):
        if key in toc:
            toc[key] = _filter_entries(toc[key], missing)
            if not toc[key]:
                del toc[key]
    if "parts" in toc:
        toc["parts"] = [p for p in (_filter_part(p, missing) for p in toc["parts"]) if p]
        if not toc["parts"]:
            del toc["parts"]
    if missing:
        log("not written yet, left out of the toc: " + ", ".join(missing))
    BUILD.mkdir(parents=True, exist_ok=True)
    path = BUILD / "_toc.yml"
    path.write_text(yaml.safe_dump(toc, sort_keys=False))
    return path, toc


def _pages(toc):
    yield toc["root"]
    stack = [toc]
    while stack:
        node = stack.pop()
        for key in ("parts", "chapters", "sections"):
            for child in node.get(key, []):
                if "file" in child:
                    yield child["file"]
                stack.append(child)


def pin_kernel():
    """A ``python3`` kernel spec that runs this interpreter; returns its JUPYTER_PATH.

    Pages name the kernel ``python3``; a spec of that name in the user's Jupyter
    directory (``ipykernel install --user`` for another Python) would otherwise win.
    """
    spec_dir = BUILD / "jupyter" / "kernels" / "python3"
    spec_dir.mkdir(parents=True, exist_ok=True)
    # every figure a page shows is checked as it is shown (book/_ext/figure_check.py)
    spec = {"argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}",
                     f"--IPKernelApp.exec_files={FIGURE_CHECK}"],
            "display_name": "Python 3", "language": "python"}
    (spec_dir / "kernel.json").write_text(json.dumps(spec, indent=1))
    return str(BUILD / "jupyter")


def run_jupyter_book(toc_path, strict, incremental, figures="fail"):
    """Run jupyter-book build; return (exit code, warning lines).

    ``strict``: Sphinx's ``-W --keep-going`` (every warning reported, then the build fails).
    """
    cmd = [sys.executable, "-c",
           "import sys; from jupyter_book.cli.main import main; sys.exit(main())",
           "build", str(BOOK), "--toc", str(toc_path)]
    if not incremental:
        cmd.append("--all")
    if strict:
        cmd += ["-W", "--keep-going"]
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    env["JUPYTER_PATH"] = os.pathsep.join(filter(None, [pin_kernel(),
                                                        env.get("JUPYTER_PATH")]))
    # the kernel shows figures inline unless MPLBACKEND (e.g. Agg, set for the tests) says otherwise
    env.pop("MPLBACKEND", None)
    env["PYVISTA_OFF_SCREEN"] = "true"
    env["PFEM_BOOK_PAGE_WIDTH"] = str(PAGE_WIDTH)
    env["PFEM_BOOK_FIGURES"] = figures
    log("jupyter-book build (executing every page)")
    warnings, times = [], []
    with subprocess.Popen(cmd, env=env, cwd=ROOT, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                          text=True, bufsize=1) as proc:
        for line in proc.stdout:
            sys.stdout.write(line)
            plain = ANSI.sub("", line).rstrip()
            if re.search(r"\b(WARNING|ERROR|CRITICAL):", plain):   # Sphinx's format
                warnings.append(plain)
            if m := EXECUTED.search(plain):
                times.append((Path(m[1]).name, float(m[2])))
    for page, seconds in times:
        log(f"executed {page} in {seconds:.1f} s")
    return proc.returncode, warnings


def check_html(toc):
    """Problems with the built HTML: missing pages, no local MathJax, remote loads."""
    problems = []
    for page in _pages(toc):
        html = HTML / (str(Path(page).with_suffix("")) + ".html")
        if not html.is_file():
            problems.append(f"page {page} was not written ({html.relative_to(ROOT)})")
            continue
        n_images = len(re.findall(r"<img\b", html.read_text(errors="replace")))
        log(f"{html.relative_to(HTML)}: {n_images} figure(s)")
    if not (HTML / "_static" / "mathjax" / "tex-chtml.js").is_file():
        problems.append("_static/mathjax/tex-chtml.js is missing from the HTML")
    n_math = 0
    for html in sorted(HTML.rglob("*.html")):
        text = html.read_text(errors="replace")
        name = html.relative_to(HTML)
        n_scripts = len(MATHJAX_SCRIPT.findall(text))
        if n_scripts > 1:
            problems.append(f"{name} loads {n_scripts} MathJax scripts (one expected)")
        n_math += n_scripts == 1
        for url in REMOTE_LOAD.findall(text):
            problems.append(f"{name} loads {url}")
        for host in sorted(set(CDN.findall(text))):
            problems.append(f"{name} refers to the CDN {host}")
    log(f"{n_math} page(s) load the local MathJax")
    built = [HTML / (str(Path(page).with_suffix("")) + ".html") for page in _pages(toc)]
    problems += docutils_errors([html for html in built if html.is_file()])
    return problems


def docutils_errors(pages):
    """A line for each of the HTML ``pages`` that renders docutils errors (the red
    ``problematic`` spans and ``system-message`` boxes of markup docutils could not read,
    such as ``|x|`` taken for an undefined substitution)."""
    found = []
    for html in pages:
        kinds = DOCUTILS_ERROR.findall(Path(html).read_text(errors="replace"))
        if kinds:
            found.append(f"{Path(html).name} renders {len(kinds)} docutils error(s) "
                         f"({', '.join(sorted(set(kinds)))})")
    return found


def left_out_warnings(warnings, left_out):
    """The warnings without those of links to the pages a ``--pages`` build left out."""
    gone = {Path(p).stem for p in left_out}
    return [w for w in warnings
            if not ((m := XREF_MISSING.search(w)) and Path(m[1]).stem in gone)]


def figure_reports(toc):
    """(page, text) of each cell whose figures the kernel found hard to read (``warn``)."""
    found = []
    for page in _pages(toc):
        nb = BUILD / "jupyter_execute" / (str(Path(page).with_suffix("")) + ".ipynb")
        if not nb.is_file():
            continue
        for cell in json.loads(nb.read_text()).get("cells", []):
            for out in cell.get("outputs", []):
                text = out.get("text", "")
                text = "".join(text) if isinstance(text, list) else text
                if "[figure check]" in text:
                    found.append((nb.stem, text[text.index("[figure check]"):].strip()))
    return found


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--strict", action="store_true",
                   help="fail on any Sphinx warning (the default; -W --keep-going)")
    p.add_argument("--allow-warnings", action="store_true",
                   help="list the Sphinx warnings without failing on them")
    p.add_argument("--incremental", action="store_true",
                   help="rebuild only changed pages (default: all pages, all executed)")
    p.add_argument("--no-browser", action="store_true",
                   help="skip opening the pages in headless Chromium")
    p.add_argument("--pages", nargs="+", metavar="PAGE",
                   help="build only these chapters (and the root page): to iterate on a page")
    p.add_argument("--figures", choices=("fail", "warn"), default="fail",
                   help="a figure hard to read fails its page (default) or is printed "
                        "in its cell's output (warn: to survey the whole book)")
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    ensure_mathjax()
    toc_path, toc = write_toc(args.pages)
    strict = args.strict or not args.allow_warnings
    # a --pages build links to the pages it left out: those warnings are not counted
    code, warnings = run_jupyter_book(toc_path, strict and not args.pages, args.incremental,
                                      args.figures)
    if args.pages:
        every_page = set(_pages(yaml.safe_load((BOOK / "_toc.yml").read_text())))
        warnings = left_out_warnings(warnings, every_page - set(_pages(toc)))
    log(f"{len(warnings)} warning(s) from the build" + (":" if warnings else ""))
    for line in warnings:
        log(f"  {line}")
    if code != 0:
        log(f"error: jupyter-book build failed (exit code {code})")
        return code
    problems = check_html(toc)
    if strict and warnings:
        problems.append(f"{len(warnings)} Sphinx warning(s) (above; --allow-warnings lists "
                        "them without failing)")
    for page, text in figure_reports(toc):      # --figures warn: the cells did not fail
        log(f"figures of {page}: {text}")
        problems.append(f"{page}: figures hard to read (above)")
    for line in problems:
        log(f"error: {line}")
    if not args.no_browser:
        sys.path.insert(0, str(BOOK))
        from browser_check import check_pages
        failed = check_pages()
        if failed:
            problems.append(f"{failed} page(s) with problems in the browser (above)")
            log(f"error: {failed} page(s) with problems in the browser")
    log(f"built {HTML.relative_to(ROOT)}/intro.html in {time.perf_counter() - t0:.0f} s")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
