"""Scene units, the one place where a scene's numbers become SI.

The engine works in SI (m, rad); a scene may declare ``[units] length = "mm"`` (or
``cm``, ``km``, ``none`` for unitless geometry) and ``angle = "deg"``
(docs/design.md, "Conventions").  Length factors are exact (:class:`~fractions.Fraction`).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from fractions import Fraction

from ..argcheck import as_table, check_keys
from ..errors import InputError
from ..exact import parse_float

__all__ = ["Units", "parse_units", "length_factor", "display_length", "angle_factor", "length_value",
           "angle_value", "DEG", "SCENE_UNIT_KINDS", "name_scene_units", "scaling_text",
           "SCALING_ORIGIN", "has_si_length", "si_length_hint",
           "degrees_hint", "radians_hint", "warn_radians"]

#: radians per degree
DEG = math.pi / 180.0

_LENGTH = {"m": Fraction(1), "mm": Fraction(1, 1000), "cm": Fraction(1, 100),
           "km": Fraction(1000), "none": None}
_ANGLE = {"rad": None, "deg": "deg"}


@dataclass(frozen=True)
class Units:
    """Units a scene is written in; values are converted to SI when parsed.

    ``length_factor`` is the exact factor to metres (``None`` for unitless scenes).
    """

    length: str = "m"
    angle: str = "rad"

    @property
    def length_factor(self) -> Fraction | None:
        return _LENGTH[self.length]


def parse_units(raw) -> Units:
    """The ``[units]`` table of a scene (``None``: SI)."""
    if raw is None:
        return Units()
    t = as_table(raw, "units")
    check_keys(t, {"length", "angle"}, "units")
    length = t.get("length", "m")
    angle = t.get("angle", "rad")
    if not isinstance(length, str) or length not in _LENGTH:   # a list is unhashable
        raise InputError(f"expected one of {', '.join(map(repr, _LENGTH))}, got {length!r}",
                         field="units.length")
    if not isinstance(angle, str) or angle not in _ANGLE:
        raise InputError(f"expected 'rad' or 'deg', got {angle!r}", field="units.angle")
    return Units(length, angle)


def length_factor(units, field) -> float:
    """Metres per scene length unit; rss and legs scenes need a physical unit."""
    f = units.length_factor
    if f is None:
        raise InputError("expected a physical length unit (m, mm, cm, km) for an rss or legs "
                         "mechanism, got 'none'", field="units.length")
    return float(f)


def display_length(unit, default: str = "m") -> tuple:
    """``(factor, name)``: a length in m times ``factor`` is in the scene's length
    ``unit`` (from :data:`_LENGTH`, the factors the scene was parsed with), for reports
    and plots; ``default`` for None, a unitless scene ("none") or an unknown name, since
    the engine's lengths are SI.

    >>> display_length("cm"), display_length("none"), display_length(None, "mm")
    ((100.0, 'cm'), (1.0, 'm'), (1000.0, 'mm'))
    """
    f = _LENGTH.get(unit) if isinstance(unit, str) else None
    if f is None:
        unit, f = default, _LENGTH[default]
    return float(1 / f), unit


def angle_factor(units) -> float:
    """Radians per scene angle unit."""
    return DEG if units.angle == "deg" else 1.0


def length_value(value, units, field) -> float:
    """A scene length (exact text or number) in metres (float)."""
    f = units.length_factor
    if f is None:
        raise InputError("expected a physical length unit for an rss or legs scene, got 'none'",
                         field="units.length")
    return parse_float(value, field) * float(f)


def angle_value(value, units, field) -> float:
    """A scene angle (exact text or number) in radians (float)."""
    return parse_float(value, field) * angle_factor(units)


#: mechanism kinds whose engine works in the scene's own length unit, as written (the
#: geometry is solved exactly, not converted to SI); an error of theirs that says
#: "length units" means that unit.  (The ``rss``/``legs`` queries work in SI; their
#: mechanism tables are parsed in scene units, so their load-time errors are renamed too.)
SCENE_UNIT_KINDS = ("octahedral", "platform66", "points")


def name_scene_units(exc, units):
    """Rename the library's generic "length units" in the error ``exc`` to the scene's
    length unit (``"squared length units"`` -> ``mm^2``, ``"(length units)"`` and
    ``"length units"`` -> ``mm``), in place; ``exc`` is returned.  The library has no
    unit; a scene has one (its ``[units] length``, "m" when not written), which its
    report prints elsewhere.  A unitless scene (``length = "none"``) keeps "length
    units"."""
    if units.length == "none":
        return exc
    u = units.length

    def rename(text):
        if not text:
            return text
        return (text.replace("squared length units", f"{u}^2")
                .replace("(length units)", u).replace("length units", u))
    message, hint = rename(exc.message), rename(exc.hint)
    if (message, hint) != (exc.message, exc.hint):
        exc.message, exc.hint = message, hint
        exc.args = (exc.one_line(),)
    return exc


#: where the default scaling matrix ST of the isotropy indices comes from
#: (:data:`distkin.indices.isotropy.ST_DEFAULT`): Kühne et al., Sec. III-B-2, the GII
#: optimisation of the 6-RSS kinematics; the paper never calls it the Octopod's (QA 23)
SCALING_ORIGIN = ("the paper's ST (Kühne et al. Sec. III-B-2, the GII optimisation of the "
                  "6-RSS kinematics: the originally intended output capabilities of Ergin's "
                  "device)")


def scaling_text(ST) -> str:
    """The scaling matrix ST of the isotropy indices with its units, the diagonal
    (6,) as (N x3, N·m x3): ``"diag(15 N, 15 N, 15 N, 1 N·m, 1 N·m, 1 N·m)"`` (Kühne et
    al. Sec. III-B-2; the numbers as given, only the units added)."""
    units = ("N",) * 3 + ("N·m",) * 3
    return "diag(" + ", ".join(f"{float(v):g} {u}" for v, u in zip(ST, units)) + ")"


#: a number (or a closing bracket of numbers) followed by m, m^2, m^3 as a word: a
#: length in an SI message ("0.6353 m", "(0.29, -0.05, 0) m", "margin -0.01 m^2"),
#: not "mm", "m/s", "N·m" or "rad/m"
_SI_LENGTH = re.compile(r"[0-9)\]]\s?m(?:\^[23]|²|³)?(?![A-Za-z0-9_/·])")


def has_si_length(text) -> bool:
    """Whether ``text`` (an error message or hint) states a length in m (SI)."""
    return bool(text) and _SI_LENGTH.search(text) is not None


def si_length_hint(exc, units) -> str | None:
    """The hint "lengths in this message in m (SI), the scene's in mm" for an error
    ``exc`` of the engine (its message in SI) raised while a scene in ``units`` was
    read, or None: when the scene is in m, or when neither the message nor the hint
    states a length (QA: "expected at least 6 legs, got 5" got it)."""
    if units.length in ("m", "none") or not (has_si_length(exc.message)
                                              or has_si_length(exc.hint)):
        return None
    return f"lengths in this message in m (SI), the scene's in {units.length}"


def degrees_hint(value_rad: float, units, allowed) -> str | None:
    """The hint of an angle refused in a scene whose ``[units] angle`` is ``"rad"``
    when the number as written would have been allowed in degrees (``rotation = 30``
    meant as ±30°), or None.  ``value_rad`` is the value as read (rad, the number
    written), ``allowed`` a predicate on an angle in rad (QA: an angle unit slip)."""
    if units.angle != "rad" or not math.isfinite(value_rad) or not allowed(value_rad * DEG):
        return None
    return (f"an angle in degrees? the scene's [units] angle is \"rad\" ({value_rad:g} "
            f"deg would be {value_rad * DEG:.4g} rad; angle = \"deg\" reads degrees)")


#: the magnitudes (as written, deg) of the largest angle of a pose or range of a deg scene
#: that could be radians: [0.01, π/2) (below 0.01 both readings are under 0.6°: a tiny
#: test value, 0.001 in a grid, said nothing worth a warning)
RADIANS_BELOW = math.pi / 2
RADIANS_FROM = 0.01


def _round_degrees(v: float) -> bool:
    """Whether ``v`` (deg, as written) is a round number of degrees: a multiple of 0.1
    or of 0.25 (0.5, 1.5, 0.25, 0.1), what a step or a small tilt in degrees looks like;
    a radian value such as 0.35 or 0.26 is not."""
    return any(abs(v * k - round(v * k)) <= 1e-9 * max(1.0, abs(v * k)) for k in (10, 4))


def radians_hint(angles, units) -> str | None:
    """The words of a likely unit slip for the angles of one pose or range of a scene
    whose ``[units] angle`` is ``"deg"``, ``angles`` as written (deg), or None: when
    every nonzero one is below π/2 in magnitude (:data:`RADIANS_BELOW`), the largest at
    least :data:`RADIANS_FROM`, and none is a round number of degrees
    (:func:`_round_degrees`), they read as radians
    (``rotation = 0.35`` meant as 0.35 rad, 20°).  The reverse of :func:`degrees_hint`;
    conservative: one round or large angle, or none nonzero, and it says nothing."""
    if units.angle != "deg":
        return None
    nonzero = [abs(float(v)) for v in angles if math.isfinite(float(v)) and float(v) != 0.0]
    if (not nonzero or not RADIANS_FROM <= max(nonzero) < RADIANS_BELOW
            or any(map(_round_degrees, nonzero))):
        return None
    shown = ", ".join(f"{v:g}" for v in angles)
    big = max(nonzero)
    what = (f"the angles {shown} deg are all below π/2 = 1.571 in magnitude and none"
            if len(angles) > 1 else
            f"the angle {shown} deg is below π/2 = 1.571 in magnitude and not")
    return (f"{what} a round number of degrees: radians? the scene's [units] angle is \"deg\" "
            f"({big:g} deg is {big * DEG:.4g} rad; {big:g} rad would be {big / DEG:.4g} deg)")


def warn_radians(angles, units, field) -> None:
    """A :class:`~distkin.errors.GeometryWarning` naming ``field`` when
    :func:`radians_hint` finds the ``angles`` (as written) of a deg scene to be radians."""
    hint = radians_hint(angles, units)
    if hint:
        from ..errors import GeometryWarning, warn
        warn(f"{field}: {hint}", GeometryWarning)
