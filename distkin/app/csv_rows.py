"""The rows of a scene's CSV file (``legs_csv``), read as a spreadsheet writes them.

Two slips of a spreadsheet's export are named or read as meant (QA):

- a row that ends in an empty field (a trailing comma, ``...,1000,``) has one cell more
  than the header; the empty cells beyond the header's last column hold nothing, so
  they are dropped (a header's own trailing empty cells too: a column with no name and
  no values), and a row with a value beyond the header is refused naming its line;
- a file of semicolon-separated values (a spreadsheet in a locale whose decimal mark is
  ",") is refused as such: distkin reads comma-separated values.
"""

from __future__ import annotations

import csv

from ..errors import InputError

__all__ = ["csv_rows", "SEPARATOR_HINT"]

#: the hint of a refused separator
SEPARATOR_HINT = ("export the table as comma-separated values (a spreadsheet's "
                  "\"CSV (comma delimited)\"), with '.' as the decimal mark")


def _semicolons(line: int, row, name: str, fld: str) -> None:
    """Refuse a row written with ';' between its values (no cell of a leg table holds
    a ';': numbers, a leg type, a branch)."""
    if any(";" in c for c in row):
        raise InputError(f"expected comma-separated values, got semicolon-separated values "
                         f"(line {line} of {name}): distkin reads comma-separated", field=fld,
                         hint=SEPARATOR_HINT)


def csv_rows(text: str, name: str, fld: str) -> list[tuple[int, list[str]]]:
    """The non-blank rows of the CSV ``text`` (file ``name``, for the messages; ``fld``
    the scene field naming it) as ``(line, cells)``, the header first, blank lines
    skipped but counted (the line numbers an editor shows).  The header's trailing
    empty cells are dropped, and so are a row's empty cells beyond the header's width
    (a trailing comma).

    Raises
    ------
    InputError
        semicolon-separated values; a header with an empty cell between named ones
        (its column); a row with a value beyond the header's last column (its line).
    """
    reader = csv.reader(text.splitlines())
    rows = [(reader.line_num, row) for row in reader if any(c.strip() for c in row)]
    for line, row in rows:
        _semicolons(line, row, name, fld)
    if not rows:
        return rows
    head_line, head = rows[0]
    head = list(head)
    while head and not head[-1].strip():            # a trailing comma in the header
        head.pop()
    empty = [i + 1 for i, h in enumerate(head) if not h.strip()]
    if empty:
        raise InputError(f"expected a column name in every header cell (line {head_line} "
                         f"of {name}), got an empty cell (column {empty[0]})", field=fld)
    out = [(head_line, head)]
    for n, (line, row) in enumerate(rows[1:]):
        extra = row[len(head):]
        if extra and any(c.strip() for c in extra):
            k = len(head) + next(i for i, c in enumerate(extra) if c.strip()) + 1
            raise InputError(f"expected {len(head)} cells (line {line} of {name}), got "
                             f"{len(row)}: a value in cell {k}, beyond the header's last "
                             f"column {head[-1].strip()!r}", field=f"{fld}[{n}]")
        out.append((line, row[:len(head)]))
    return out
