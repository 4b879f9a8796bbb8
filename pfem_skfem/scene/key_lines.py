"""Where the keys of a scene file are: a scan of its text (the line of each key, so that a
bad value is refused naming its line; :mod:`pfem_skfem.scene.files` uses it).

:func:`key_lines` follows the table headers, the arrays of tables and the values that
span lines, without a TOML parser of its own: ``tomllib`` reads the values and gives no
positions.
"""
import json
import re

_BARE = re.compile(r"[A-Za-z0-9_-]+")


def _read_key(s, i):
    """Dotted key starting at s[i]: (parts, index after it)."""
    parts = []
    while True:
        while i < len(s) and s[i] in " \t":
            i += 1
        if i < len(s) and s[i] in "\"'":
            q = s[i]
            j = i + 1
            while s[j] != q:
                j += 2 if (q == '"' and s[j] == "\\") else 1
            raw = s[i:j + 1]
            parts.append(json.loads(raw) if q == '"' else raw[1:-1])
            i = j + 1
        else:
            m = _BARE.match(s, i)
            parts.append(m.group(0))
            i = m.end()
        while i < len(s) and s[i] in " \t":
            i += 1
        if i < len(s) and s[i] == ".":
            i += 1
            continue
        return parts, i


def _scan_value(s, depth, string):
    """Bracket depth and open multi-line string (its quotes, or None) after reading s."""
    i = 0
    while i < len(s):
        if string:
            if s.startswith(string, i):
                i += 3
                string = None
                continue
            i += 2 if (string == '"""' and s[i] == "\\") else 1
            continue
        c = s[i]
        if c == "#":
            break
        if s.startswith('"""', i) or s.startswith("'''", i):
            string = s[i:i + 3]
            i += 3
        elif c in "\"'":
            j = i + 1
            while j < len(s) and s[j] != c:
                j += 2 if (c == '"' and s[j] == "\\") else 1
            i = j + 1
        else:
            depth += c in "[{"
            depth -= c in "]}"
            i += 1
    return depth, string


def key_lines(text):
    """{key path tuple: line number} of a valid TOML text: each table header, each element
    of an array of tables (``('regions', 1)``), each ``key = value`` (its first line)."""
    lines = {}
    table = ()
    counts = {}                                      # array of tables -> elements so far

    def resolve(names):
        path = ()
        for name in names:
            path += (name,)
            if path in counts:                       # [regions.material]: the last region's
                path += (counts[path] - 1,)
        return path

    depth, string = 0, None
    for n, raw in enumerate(text.splitlines(), 1):
        if depth or string:                          # inside a value over several lines
            depth, string = _scan_value(raw, depth, string)
            continue
        s = raw.strip()
        if not s or s.startswith("#"):
            continue
        if s.startswith("[["):
            names, _ = _read_key(s, 2)
            base = resolve(names[:-1]) + (names[-1],)
            counts[base] = counts.get(base, 0) + 1
            table = base + (counts[base] - 1,)
            lines.setdefault(base, n)
            lines[table] = n
        elif s.startswith("["):
            names, _ = _read_key(s, 1)
            table = resolve(names)
            lines[table] = n
        else:
            names, i = _read_key(s, 0)
            lines[table + tuple(names)] = n
            depth, string = _scan_value(s[i + 1:], 0, None)
    return lines
