"""A TOML syntax error as one line that names where it is.

``tomllib`` names the line and column of most syntax errors itself, but not those of an
array, inline table or string left open: it reports them "at end of document".  Scene
files of both layers (run scenes, :mod:`distkin.app.scene`; controller scenes,
:mod:`distkin.control.config`) raise this module's error, so a file loaded through the
Python API names the place as the command line does.
"""

from __future__ import annotations

from .errors import InputError

__all__ = ["toml_syntax_error"]


def toml_syntax_error(text: str, exc, path) -> InputError:
    """The one-line error of a TOML syntax error in the file ``path``, naming its line
    (also where an array or string left open at the end of the document was opened)."""
    return InputError(f"expected valid TOML, got a syntax error: {exc}"
                      f"{_unclosed_at(text, exc)}", field=str(path))


def _unclosed_at(text: str, exc) -> str:
    """Where the array or string that ``tomllib`` found unclosed "at end of document"
    was opened (tomllib names no line then): ``"; the '[' opened at line 7, column 8 is
    never closed"``; ``""`` for any other error (those name their line themselves)."""
    if not str(exc).endswith("(at end of document)"):
        return ""
    stack, i, n = [], 0, len(text)

    def where(k):
        return f"line {text.count(chr(10), 0, k) + 1}, column {k - text.rfind(chr(10), 0, k)}"

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
                return f"; the string {quote} opened at {where(i)} is never closed"
            i = j + len(quote)
            continue
        elif c in "[{":
            stack.append(i)
        elif c in "]}" and stack:
            stack.pop()
        i += 1
    if not stack:
        return ""
    return f"; the {text[stack[0]]!r} opened at {where(stack[0])} is never closed"
