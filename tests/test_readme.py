"""The README stays an entry point (issue 37): short, one table, every path real.

The measured results live in the book (each benchmark's page, its "At full size"
section; the appendices Performance and Long studies), not in the README.
"""
from pathlib import Path
import re

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"

MAX_LINES = 200
MAX_BYTES = 15 * 1024
MAX_RESULT = 100   # characters in a table's result cell
# what the commands of the README write, not files of the repository
OUTPUTS = ("results/", ".venv/", "column_run/", "book/_build/")
# a relative path: a folder (name/) or a folder and a name, no spaces, no scheme (https://)
PATH = re.compile(r"^\.?[\w-]+(?:/[\w.-]+)*/$|^\.?[\w-]+(?:/[\w.-]+)+$")


def _text():
    return README.read_text(encoding="utf-8")


def _table_rows(text):
    """The rows of the README's tables as lists of cells, without the header rule."""
    rows = []
    for line in text.splitlines():
        if line.startswith("|") and not re.match(r"^\|[\s|:-]+\|$", line):
            rows.append([c.strip() for c in line.strip().strip("|").split("|")])
    return rows


def _code_blocks(text):
    """(language, body) of each fenced code block."""
    blocks, lang, body = [], None, []
    for line in text.splitlines():
        if line.startswith("```"):
            if lang is None:
                lang, body = line[3:].strip(), []
            else:
                blocks.append((lang, "\n".join(body)))
                lang = None
        elif lang is not None:
            body.append(line)
    return blocks


def _named_paths(text):
    """The repository paths the README names: in backticks, in links, in commands, in its tree."""
    prose = re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)
    names = {word for code in re.findall(r"`([^`]+)`", prose) for word in code.split()}
    names |= set(re.findall(r"\]\(([^)\s]+)\)", prose))
    for lang, body in _code_blocks(text):
        if lang == "bash":      # the commands' arguments, comments left out
            for line in body.splitlines():
                names |= set(line.split("#")[0].split())
        elif lang == "":        # the layout: top-level entries and the package's modules
            names |= set(re.findall(r"^([\w.-]+/)\s", body, flags=re.M))
            for sub in re.findall(r"^  ([\w.-]+/)\s", body, flags=re.M):
                names.add("pfem_skfem/" + sub)
            for files in re.findall(r"^  ([\w.]+\.py(?:, [\w.]+\.py)*)\s", body, flags=re.M):
                names |= {"pfem_skfem/" + f for f in files.split(", ")}
    paths = set()
    for name in names:
        if "://" in name or name.startswith("#") or name.startswith(OUTPUTS):
            continue
        if PATH.match(name):
            paths.add(name)
    return paths


def test_readme_is_short():
    text = _text()
    n_lines = len(text.splitlines())
    n_bytes = len(text.encode("utf-8"))
    assert n_lines <= MAX_LINES, f"README.md has {n_lines} lines (at most {MAX_LINES}): measurements go to the book"
    assert n_bytes <= MAX_BYTES, f"README.md has {n_bytes} bytes (at most {MAX_BYTES}): measurements go to the book"


def test_readme_result_cells_are_headlines():
    rows = _table_rows(_text())
    assert rows, "README.md has no table"
    header = [c.lower() for c in rows[0]]
    col = next(i for i, c in enumerate(header) if c.startswith("result"))
    for row in rows[1:]:
        assert len(row) == len(header), f"a row with {len(row)} cells: {row}"
        assert len(row[col]) <= MAX_RESULT, (
            f"{row[0]}: a result of {len(row[col])} characters (at most {MAX_RESULT}); "
            f"the rest goes to the book page ({row[-1]})")


def test_readme_tables_one():
    text = _text()
    headers = [line for line in text.splitlines() if re.match(r"^\|[\s|:-]+\|$", line)]
    assert len(headers) == 1, f"{len(headers)} tables in README.md: one (What is verified)"


def test_readme_paths_exist():
    paths = _named_paths(_text())
    for sure in ("docs/pfem_skfem_results.png", "verification/strip_footing.py", "scripts/verify.sh",
                 "pfem_skfem/", "pfem_skfem/scene/", "pfem_skfem/cli.py", "docs/make_readme_figure.py"):
        assert sure in paths, f"{sure} not found among the README's paths: the parser missed it"
    missing = sorted(p for p in paths if not (ROOT / p.rstrip("/")).exists())
    assert not missing, f"README.md names paths that do not exist: {missing}"


def test_readme_names_every_verification_script():
    text = _text()
    scripts = sorted(p.name for p in (ROOT / "verification").glob("*.py") if p.name != "__init__.py")
    absent = [s for s in scripts if f"verification/{s}" not in text]
    assert not absent, f"scripts missing from README's table: {absent}"


def test_readme_states_the_quick_suite_s_time_from_the_measured_times():
    """The total of scripts/verify.sh is the cases' --quick CPU times (cli.QUICK_SECONDS,
    what `pfem-skfem list` shows) over two cores (issue 56 item 2)."""
    from pfem_skfem import cli
    text = " ".join(_text().split())
    total = sum(cli.QUICK_SECONDS.values())
    assert f"about {round(total / 2 / 60)} minutes on two cores" in text
    assert f"the {len(cli.QUICK_SECONDS)} quick cases' {total} s of CPU" in text
