"""A TOML syntax error as one line that names where it is.

``tomllib`` names the line and column of most syntax errors itself, but not those of an
array, inline table or string left open: it reports them "at end of document".  Scene
files of both layers (run scenes, :mod:`distkin.app.scene`; controller scenes,
:mod:`distkin.control.config`) raise this module's error, so a file loaded through the
Python API names the place as the command line does.
"""

from __future__ import annotations

import re

from .errors import InputError

__all__ = ["toml_syntax_error"]


def toml_syntax_error(text: str, exc, path) -> InputError:
    """The one-line error of a TOML syntax error in the file ``path``, naming its line
    (also where an array or string left open at the end of the document was opened)."""
    return InputError(f"expected valid TOML, got a syntax error: {exc}"
                      f"{_unclosed_at(text, exc)}", field=str(path))


def _unclosed_at(text: str, exc) -> str:
    """Where the array or string that ``tomllib`` found unclosed was opened: ``"; the
    '[' opened at line 7, column 8 is never closed"``.  At the end of the document
    tomllib names no line; before it ("Unclosed array (at line 4, column 1)") it names
    the line after the array's, where the next key begins (QA 2026-11-29), so the line
    where the array (or inline table) still open there began is named too, if nothing
    after it closes it either: tomllib says "Unclosed array" for a missing comma too
    ("a = [1 2]", review 2026-11-29).  ``""`` for any other error (those name their line
    themselves)."""
    msg = str(exc)
    at = re.search(r"\(at line (\d+), column (\d+)\)$", msg)
    if msg.endswith("(at end of document)"):
        stack, string = _scan(text, len(text))
        if string is not None:
            quote = text[string] * 3 if text.startswith(text[string] * 3, string) else \
                text[string]
            return f"; the string {quote} opened at {_where(text, string)} is never closed"
        return _note(text, stack[0]) if stack else ""
    if not (msg.startswith(("Unclosed array", "Unclosed inline table")) and at):
        return ""
    stack, _ = _scan(text, _offset(text, int(at.group(1)), int(at.group(2))))
    if not stack or stack[-1] not in _scan(text, len(text))[0]:
        return ""
    return _note(text, stack[-1])


def _scan(text: str, n: int):
    """The brackets ``[`` ``{`` still open at index ``n`` of ``text`` (their indices,
    outermost first), outside strings and comments, and the index of a string still open
    there (None: none)."""
    stack, i = [], 0
    while i < n:
        c = text[i]
        if c == "#":                                     # a comment, to the line's end
            end = text.find("\n", i)
            i = n if end < 0 else end
        elif c in "\"'":
            quote = c * 3 if text.startswith(c * 3, i) else c
            j = i + len(quote)
            while j < n and not text.startswith(quote, j):
                if len(quote) == 1 and text[j] == "\n":
                    break                                # tomllib names that line itself
                j += 2 if text[j] == "\\" and c == '"' else 1
            if j >= n:
                return stack, i
            i = j + len(quote)
            continue
        elif c in "[{":
            stack.append(i)
        elif c in "]}" and stack and text[stack[-1]] == "[{"["]}".index(c)]:
            stack.pop()                                  # (a ']' closes no '{')
        i += 1
    return stack, None


def _where(text: str, k: int) -> str:
    return f"line {text.count(chr(10), 0, k) + 1}, column {k - text.rfind(chr(10), 0, k)}"


def _note(text: str, k: int) -> str:
    return f"; the {text[k]!r} opened at {_where(text, k)} is never closed"


def _offset(text: str, line: int, column: int) -> int:
    """The index in ``text`` of ``line``, ``column`` (both from 1, as tomllib counts)."""
    start = 0
    for _ in range(line - 1):
        start = text.find("\n", start) + 1
        if start == 0:
            return len(text)
    return min(start + column - 1, len(text))
