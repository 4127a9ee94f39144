"""Result documents: the JSON contract and the readable text report.

JSON (docs/design.md §4)::

    {"distkin": VERSION, "scene": PATH,
     "queries": [{"type", "status": "ok"|"error", "error": {"kind", "message"}?,
                  "result": {...}, "seconds"}]}

Exact numbers travel as strings (``"99/5"``), floats as JSON numbers, balls as
``{"mid", "rad"}`` (the ball within ``rad`` of the float ``mid``:
:func:`~distkin.exact.float_ball`); NaN and infinities, which JSON lacks, become strings.
"""

from __future__ import annotations

import json
import math
from fractions import Fraction

import numpy as np

__all__ = ["jsonable", "document", "dumps", "fmt", "render_text", "float_inputs",
           "float_inputs_line", "as_written"]


def jsonable(x):
    """Convert results to JSON-able values (exact values as strings)."""
    if x is None or isinstance(x, (bool, str)):
        return x
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        x = float(x)
        if math.isfinite(x):
            return x
        return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")
    if isinstance(x, Fraction):
        return str(x.numerator) if x.denominator == 1 else f"{x.numerator}/{x.denominator}"
    if isinstance(x, dict):
        return {str(k): jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return jsonable(x.tolist())
    name = type(x).__name__
    if name in ("fmpq", "fmpz"):
        return str(x)
    if name == "arb":                 # the float mid and a radius about it (float_ball)
        from ..exact import float_ball
        mid, rad = float_ball(x)
        return {"mid": jsonable(mid), "rad": jsonable(rad)}
    if name == "mpf":
        return float(x)
    if hasattr(x, "free_symbols"):  # sympy
        return str(x)
    from ..exact import Exact
    if isinstance(x, Exact):
        return str(x)
    raise TypeError(f"cannot put {name} {x!r} into JSON")


def document(scene_path: str, records: list, version: str) -> dict:
    return {"distkin": version, "scene": scene_path, "queries": jsonable(records)}


def dumps(doc: dict) -> str:
    return json.dumps(doc, indent=2, allow_nan=False)


def fmt(value, unit: str = "", digits: int = 6) -> str:
    """A number with its unit, ``fmt(0.0123, "m") -> '0.0123 m'``."""
    if isinstance(value, Fraction):
        s = str(value)
    elif isinstance(value, (int, np.integer)):
        s = str(int(value))
    else:
        try:
            s = f"{float(value):.{digits}g}"
        except (TypeError, ValueError):
            s = str(value)
    return f"{s} {unit}".rstrip()


def float_inputs(named) -> list:
    """The names of the scene values, among ``named`` ((name, Exact) pairs), that were
    bare floats and so are taken as their exact binary values (docs/design.md §3)."""
    return [name for name, v in named if getattr(v, "from_float", False)]


def as_written(values) -> list:
    """Scene values (:class:`~distkin.exact.Exact`) for the JSON as they were used: a
    bare float as a JSON number (its binary value, which the computation used), an exact
    text as its string (``"17.4"`` is 87/5; docs/design.md §3), so that a string in the
    JSON always means an exact value (QA 23 D7: ``m_legs`` gave ``"17.4"`` for 17.4)."""
    return [float(v) if getattr(v, "from_float", False) else v.text for v in values]


def float_inputs_line(named) -> str:
    """The report's line saying which inputs were bare floats ("" when none), with the
    exact value of the first (``19.8`` is 19.800000000000000710542735760100...)."""
    from decimal import Decimal
    floats = [(name, v) for name, v in named if getattr(v, "from_float", False)]
    if not floats:
        return ""
    name, v = next(((n, x) for n, x in floats if str(Decimal(float(x.value))) != x.text),
                   floats[0])
    exact = str(Decimal(float(v.value)))
    return (f"inputs given as bare floats, taken as their exact binary values: "
            f"{', '.join(n for n, _ in floats)} (e.g. {v.text} is {exact}; write "
            f"\"{v.text}\" for the decimal)")


def render_text(scene_path: str, records: list, texts: list) -> str:
    """The readable report: one section per query, with its status and time."""
    lines = [f"distkin report for {scene_path}", ""]
    for i, (rec, text) in enumerate(zip(records, texts)):
        head = f"[{i}] {rec['type']}: {rec['status']} ({rec['seconds'] * 1e3:.1f} ms)"
        lines.append(head)
        lines.append("-" * len(head))
        if rec["status"] == "error":
            lines.append(f"  error ({rec['error']['kind']}): {rec['error']['message']}")
        elif text:
            lines.extend("  " + t if t else "" for t in text.rstrip().splitlines())
        lines.append("")
    return "\n".join(lines)
