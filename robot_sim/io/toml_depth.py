"""A pre-scan of TOML text that bounds how deeply its keys nest, before ``tomllib`` runs.

``tomllib`` builds one dictionary per level of a dotted key (``a.a.a... = 1``) and
recurses through nested arrays and inline tables; fifty thousand levels fit in a 100 KB
file and take gigabytes.  :func:`nesting_too_deep` walks the text once, outside strings
and comments, and finds the first line where a key path (table header or dotted key,
plus the inline tables and arrays around it) goes more than ``limit`` levels deep.
"""
from __future__ import annotations

#: Most levels a key may nest in any TOML file the program reads (robot, world, task):
#: the deepest real file needs four.
MAX_TOML_DEPTH = 32


def nesting_too_deep(text: str, limit: int = MAX_TOML_DEPTH) -> int | None:
    """The 1-based line of ``text`` where nesting first exceeds ``limit`` levels, or None.

    Levels count the parts of a table header (``[a.b]``: 2), the parts of a dotted key
    under the current header, and each array or inline table a value opens.  Strings
    (basic, literal, multi-line) and comments are skipped, so their dots and brackets do
    not count.  Linear in the length of ``text``.
    """
    line, i, n = 1, 0, len(text)
    header = 0  # levels of the current [table] header
    open_: list[tuple[bool, int]] = []  # open arrays / inline tables: (is a table, its level)
    key_dots, in_key, value_level = 0, True, 0
    at_line_start = True
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            if not open_:
                in_key, key_dots = True, 0
            at_line_start = True
            i += 1
            continue
        if c in " \t\r":
            i += 1
            continue
        if c == "#":
            end = text.find("\n", i)
            i = n if end < 0 else end
            continue
        if c in "\"'":
            i = _skip_string(text, i)
            continue
        if at_line_start and not open_ and c == "[":  # a [table] or [[array]] header
            end = text.find("\n", i)
            end = n if end < 0 else end
            header = _header_levels(text[i:end])
            if header > limit:
                return line
            i, at_line_start = end, False
            continue
        at_line_start = False
        level = open_[-1][1] if open_ else header  # the level keys here start from
        if in_key and c == ".":
            key_dots += 1
            if level + key_dots + 1 > limit:
                return line
        elif in_key and c == "=":
            in_key, value_level = False, level + key_dots + 1
        elif c in "[{":
            inner = value_level if not open_ or open_[-1][0] else open_[-1][1] + 1
            if inner > limit:
                return line
            open_.append((c == "{", inner))
            in_key, key_dots = c == "{", 0
        elif c in "]}":
            if open_:
                open_.pop()
        elif c == "," and open_ and open_[-1][0]:
            in_key, key_dots = True, 0
        i += 1
    return None


def _skip_string(text: str, i: int) -> int:
    """The index just past the string starting at ``text[i]`` (any of TOML's four kinds)."""
    quote = text[i]
    if text.startswith(quote * 3, i):
        end = text.find(quote * 3, i + 3)
        while quote == '"' and end > 0 and _escaped(text, end):
            end = text.find(quote * 3, end + 1)
        return len(text) if end < 0 else end + 3
    j = i + 1
    while j < len(text) and text[j] not in (quote, "\n"):
        j += 2 if quote == '"' and text[j] == "\\" else 1
    return j + 1


def _escaped(text: str, i: int) -> bool:
    """Whether the character at ``i`` follows an odd number of backslashes."""
    k = i
    while k > 0 and text[k - 1] == "\\":
        k -= 1
    return (i - k) % 2 == 1


def _header_levels(header: str) -> int:
    """Parts of a ``[a.b."c.d"]`` header (dots outside quotes, plus one)."""
    levels, quote = 1, ""
    for c in header:
        if quote:
            quote = "" if c == quote else quote
        elif c in "\"'":
            quote = c
        elif c == ".":
            levels += 1
        elif c == "#":
            break
    return levels
