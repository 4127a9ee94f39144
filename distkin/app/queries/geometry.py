"""Scene query ``cayley_menger``: named Cayley-Menger determinants of a point set.

Scene fields::

    [[query]]
    type = "cayley_menger"
    determinants = ["D(1,2,3,4)", "D(5,4,1,2;5,4,1,6)"]
    method = "certified"            # fast | precise | certified
    dps = 30                        # precise tier only
    points = [[...], ...]           # optional; else the mechanism's points

For an ``octahedral`` mechanism the points are P1..P3 of the base and P4..P6 of the
platform in its own frame only if the query gives none, which is rarely meaningful; the
query is intended for ``kind = "points"``.

Units: a determinant of ``n`` labels is a polynomial of degree ``n - 1`` in the squared
distances (Rojas et al., eq. (1)), so its unit is the scene's length unit to the power
``2(n - 1)``; ``D(1) = -1`` is a pure number.  The values are in the scene's own length
unit, as written (exact rationals stay the scene's numbers); each JSON entry names its
``unit`` ("mm^6", or "none" for a pure number or a unitless scene), and the result's
``unit`` block names those of the area and volume interpretations.

A determinant of 3 or 4 equal labels also gives ``triangle_area_squared`` (-D/16) or
``tetrahedron_volume_squared`` (D/288): exact where the determinant is (an exact string,
``"2809/576"``, as the determinant's ``value``), else a float, with the float always in
``triangle_area_squared_float`` / ``tetrahedron_volume_squared_float``; null beyond
float64's range.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from fractions import Fraction

from ...argcheck import check_keys, dps_field, exact_matrix, method_field, string_list
from ...errors import InputError
from ...exact import float_ball, to_tier
from ..query import Outcome, register
from ..report import float_inputs, float_inputs_line
from ...geometry.cayley_menger import (FloatRangeWarning, cayley_menger, parse_label,
                                        squared_distances)
from ...geometry.cm_float import CancellationWarning

__all__ = ["CayleyMengerQuery"]


@dataclass(frozen=True)
class _Params:
    points: tuple
    determinants: tuple
    labels: tuple
    method: str
    dps: int


def _interpretation(rows, cols):
    if cols != rows:
        return None
    k = len(rows)
    if k == 3:
        return "triangle_area_squared", Fraction(-1, 16)
    if k == 4:
        return "tetrahedron_volume_squared", Fraction(1, 288)
    return None


@register("cayley_menger", mechanisms=("points",),
          summary="Cayley-Menger (bi)determinants of a labelled point set")
class CayleyMengerQuery:
    @staticmethod
    def parse(table, mechanism, units, field):
        check_keys(table, {"type", "determinants", "method", "dps", "points"}, field)
        if "points" in table:
            points = exact_matrix(table["points"], f"{field}.points")
        else:
            points = mechanism.points
        if "determinants" not in table:
            raise InputError("missing required field 'determinants'",
                             field=f"{field}.determinants")
        names = string_list(table["determinants"], f"{field}.determinants")
        if not names:
            raise InputError('expected at least one determinant label, such as '
                             '"D(1,2,3,4)" or "D(5,4,1,2;5,4,1,6)", got an empty list []',
                             field=f"{field}.determinants")
        labels = []
        for i, name in enumerate(names):
            try:
                rows, cols = parse_label(name)
            except InputError as exc:
                raise exc.with_field(f"{field}.determinants[{i}]")
            cols = rows if cols is None else cols
            if len(rows) != len(cols):
                raise InputError(f"expected as many row labels as column labels in {name!r}",
                                 field=f"{field}.determinants[{i}]")
            bad = [x for x in rows + cols if not 1 <= x <= len(points)]
            if bad:
                raise InputError(f"label {bad[0]} is out of range 1..{len(points)} in {name!r}",
                                 field=f"{field}.determinants[{i}]")
            labels.append((rows, cols))
        method = method_field(table, field)
        dps = dps_field(table, method, field)
        return _Params(points, names, tuple(labels), method, dps)

    @staticmethod
    def run(p, scene, ctx):
        if p.method == "precise":       # for this query only (mp.dps is global state)
            import mpmath
            with mpmath.workdps(p.dps):
                return _run_cm(p, scene)
        return _run_cm(p, scene)


def _run_cm(p, scene):
    """The cayley_menger query at the working precision its ``run`` set."""
    import numpy as np
    pts = np.array([[to_tier(x, p.method) for x in row] for row in p.points],
                   dtype=float if p.method == "fast" else object)
    sq = squared_distances(pts)
    length = scene.units.length
    values, lines = [], []
    for name, (rows, cols) in zip(p.determinants, p.labels):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", FloatRangeWarning)
            warnings.simplefilter("always", CancellationWarning)
            d = cayley_menger(sq, rows, cols)
        lost = [w.message for w in caught if issubclass(w.category, FloatRangeWarning)]
        entry = {"name": name, "rows": list(rows), "cols": list(cols)}
        entry.update(_value_fields(d, p.method))
        vouch = _vouch(sq, rows, cols, d, p.method,
                       [w.message for w in caught if issubclass(w.category, CancellationWarning)])
        entry.update(vouch)
        if lost:                               # fast: a non-zero value beyond float64
            side = "below" if d == 0 else "beyond"
            entry.update(value=None, decimal=lost[0].value, float64_range=side,
                         text=f"{lost[0].value} ({side} the float64 range: float64 gives "
                              f"{float(d)!r})")
        unit = length_power(length, 2 * (len(rows) - 1))
        entry["unit"] = unit                   # of value and radius
        text = f"{name} = {entry['text']}" + ("" if unit == "none" else f" {unit}")
        interp = _interpretation(rows, cols)
        if interp is not None:
            kind, factor = interp
            # exact where exact (QA 23 D5): an fmpq determinant gives the exact value,
            # a string in the JSON as the determinant's own, with its float beside it
            exact = (Fraction(int(d.p), int(d.q)) * factor
                     if type(d).__name__ == "fmpq" else None)
            try:
                val = (float(exact) if exact is not None else
                       float(d if p.method != "certified" else _mid(d)) * float(factor)) + 0.0
            except OverflowError:
                val = math.inf
            label = "area^2" if kind.startswith("triangle") else "volume^2"
            entry[kind] = entry[f"{kind}_float"] = None
            if val == 0 and (lost or not _is_zero(d)):   # QA J 4: underflow, not flat
                text += f"   ({label} below the float64 range, not 0)"
            elif math.isfinite(val):
                entry[kind] = val if exact is None else exact
                entry[f"{kind}_float"] = val
                u = _INTERPRETATION_UNITS[kind](length)
                shown = f"{exact} = " if exact is not None and exact.denominator != 1 else ""
                text += f"   ({label} = {shown}{val:.10g}{'' if u == 'none' else ' ' + u})"
            else:                              # the determinant is right, its float is not
                text += f"   ({label} beyond the float64 range)"
        if vouch.get("error_estimate") is not None and not lost:
            text += f"   (error estimate {vouch['error_estimate']:.2g}" + (
                "" if unit == "none" else f" {unit}") + ")"
        if vouch.get("cannot_vouch"):
            text += (f"\n    WARNING: {vouch['cannot_vouch']}")
        values.append(entry)
        lines.append(text)
    accuracy = {"fast": "float64 determinant (LU); error estimate k eps s_max^(k-1) for k "
                        "points (Higham, Ch. 9), an estimate, not a bound",
                "precise": f"mpmath at {p.dps} digits; error estimate k 2^-prec "
                           f"s_max^(k-1) for k points, an estimate, not a bound",
                "certified": "exact rational (fmpq) or certified arb ball"}[p.method]
    lines.append(f"accuracy: {accuracy}")
    named = [(f"mechanism.points[{i}][{j}]", v)
             for i, row in enumerate(p.points) for j, v in enumerate(row)]
    note = float_inputs_line(named)
    if note:
        lines.append(note)
    unit = {"determinants": "each entry's 'unit' (value and radius): the scene's length "
                            "unit to the power 2(n - 1) for n labels",
            **{k: f(length) for kind, f in _INTERPRETATION_UNITS.items()
               for k in (kind, f"{kind}_float")}}
    return Outcome({"method": p.method, "determinants": values, "accuracy": accuracy,
                    "inputs_from_float": float_inputs(named), "unit": unit},
                   "\n".join(lines))


def _vouch(sq, rows, cols, d, method, cancellation):
    r"""What the tier can say of the value ``d``: ``error_estimate`` (absolute, the
    value's unit; :mod:`distkin.geometry.cm_float`'s backward-error estimate
    :math:`k u s_{\max}^{k-1}` with the unit round-off ``u`` of the tier) and, where it
    cannot tell the value from 0 or keeps fewer than about 6 digits, ``cannot_vouch``
    (the fast tier's CancellationWarning, which the API emits; QA X3 D1: the query
    swallowed it, and the precise tier printed 20 digits of noise for an exact 0).
    Nothing for ``certified`` (its ball or exact value says it) or a single label."""
    import mpmath
    if method == "certified" or len(rows) < 2:
        return {}
    k = len(rows)
    with mpmath.workprec(64):
        smax = max(abs(mpmath.mpf(sq[r - 1][c - 1])) for r in rows for c in cols)
        u = mpmath.mpf(2) ** (-53 if method == "fast" else -mpmath.mp.prec)
        est = k * u * smax ** (k - 1)
        rel = est / abs(mpmath.mpf(d)) if d != 0 else mpmath.inf
    out = {"error_estimate": float(est) if mpmath.isfinite(float(est)) else mpmath.nstr(est, 3),
           "relative_error_estimate": float(rel) if rel != mpmath.inf else None}
    if cancellation:
        out["cannot_vouch"] = str(cancellation[0]).split("; use method")[0] + (
            '; use method = "precise" or "certified"')
    elif rel > 1e-6:
        out["cannot_vouch"] = (f"the {method} value "
                               + ("is 0 within its error estimate" if rel == mpmath.inf or rel >= 1
                                  else f"keeps about {max(0, int(-mpmath.log10(rel)))} digits")
                               + (": it may be 0 (e.g. a flat simplex); use method = "
                                  '"certified" to decide' if rel >= 1 else ""))
    return out


def length_power(length: str, power: int) -> str:
    """The unit of a length to ``power`` in a scene of length unit ``length``:
    ``("mm", 6) -> "mm^6"``, ``("m", 1) -> "m"``; "none" at power 0 (a pure number) and
    in a unitless scene (``length = "none"``)."""
    if power == 0 or length == "none":
        return "none"
    return length if power == 1 else f"{length}^{power}"


#: the interpretations' keys -> their units (a squared area, a squared volume)
_INTERPRETATION_UNITS = {
    "triangle_area_squared": lambda length: length_power(length, 4),
    "tetrahedron_volume_squared": lambda length: length_power(length, 6),
}


def _mid(d):
    return float(d.mid()) if type(d).__name__ == "arb" else float(d)


def _is_zero(d) -> bool:
    """An exact zero (fmpq, mpf, float) or an arb ball that is exactly 0."""
    if type(d).__name__ == "arb":
        return d.is_zero()
    return d == 0


def _value_fields(d, method):
    name = type(d).__name__
    if name == "fmpq":
        text = str(d)
        if len(text) > 40:                   # QA J 13: a decimal, the exact value in JSON
            import mpmath
            with mpmath.workdps(20):
                dec = mpmath.nstr(mpmath.mpf(int(d.p)) / int(d.q), 15)
            text = f"{dec} (exact rational of {len(text)} characters: JSON 'value')"
        return {"value": str(d), "exact": True, "radius": 0.0, "text": text}
    if name == "arb":
        value, radius = float_ball(d)     # the ball within radius of the float value
        return {"value": value, "exact": False, "radius": radius,
                "text": d.str(15, radius=True)}
    if name == "mpf":
        import mpmath
        x = float(d)                     # beyond float64: the value as its decimal text
        return {"value": x if math.isfinite(x) else mpmath.nstr(d, 20), "exact": False,
                "radius": None, "text": mpmath.nstr(d, 20)}
    return {"value": float(d), "exact": False, "radius": None, "text": f"{float(d):.15g}"}
