"""The ``kind = "rss"`` mechanism table of a scene file.

::

    [units]
    length = "mm"
    angle = "deg"

    [mechanism]
    kind = "rss"
    preset = "octopod"          # hexa | hunt | ergin | octopod | octo
    l0 = 160                    # any parameter may be overridden, in the scene's units:
    gamma = 10                  #   legs, l0 l1 l2 l3 lp ld z0 (length), beta gamma (angle),
    mass = "0.2"                #   mass (kg) and inertia (kg m^2) always in SI
    layout = "tangential"       # the reading of Fig. 2: tangential (default) | radial

Unless ``l3`` is given it follows the reading's rule (:mod:`.presets`).
"""

from __future__ import annotations

import math
import sys
import warnings
from fractions import Fraction

from ..argcheck import check_keys, choice, require
from ..errors import InputError
from ..exact import exact_to_float, parse_exact
from ..mechanisms.legs import GeometryWarning
from ..mechanisms.presets import PRESETS, SLIP_RATIO, slip_ratio, slip_ratios
from ..mechanisms.rss import preset
from .units import angle_factor, degrees_hint, length_factor

__all__ = ["parse_rss", "unit_slips", "length_slips", "warn_slips", "LENGTHS", "ANGLES",
           "SLIP_RATIO"]

LENGTHS = ("l0", "l1", "l2", "l3", "lp", "ld", "z0")
ANGLES = ("beta", "gamma")
_SI = ("mass", "inertia")
#: the preset overrides whose keys start a slip warning of preset() (said here instead)
_SLIP_MESSAGE = r"(%s): " % "|".join(LENGTHS + _SI)


def parse_rss(table, units, field):
    """Parse an ``rss`` mechanism table into an :class:`~.rss.RSSMechanism` (SI)."""
    check_keys(table, {"kind", "preset", "legs", "layout", *LENGTHS, *ANGLES, *_SI}, field)
    name = choice(require(table, "preset", field), f"{field}.preset", tuple(PRESETS))
    length_factor(units, field)                 # a physical unit, or the error
    af = angle_factor(units)
    over = {}
    if "layout" in table:
        from ..mechanisms.rss import LAYOUTS
        over["layout"] = choice(table["layout"], f"{field}.layout", LAYOUTS)
    if "legs" in table:
        legs = table["legs"]
        if legs not in (6, 8) or isinstance(legs, bool):
            raise InputError(f"expected legs = 6 or 8, got {legs!r}", field=f"{field}.legs")
        over["legs"] = legs
    for k in LENGTHS + ANGLES + _SI:
        if k in table:
            ex = parse_exact(table[k], f"{field}.{k}")
            # a length: the exact value times the exact unit factor, rounded once (the
            # same SI number whichever unit the scene is written in)
            over[k] = exact_to_float(ex, f"{field}.{k}", Fraction(units.length_factor)
                                     if k in LENGTHS else af if k in ANGLES else 1)
            if k in ANGLES and not 0 <= over[k] < math.pi / 2:   # this field, both units
                raise InputError(f"expected {k} in [0°, 90°), got {over[k]:.6g} rad (the "
                                 f"scene's {k} = {table[k]!r} {units.angle})",
                                 field=f"{field}.{k}",
                                 hint=degrees_hint(over[k], units,
                                                   lambda a: 0 <= a < math.pi / 2))
    _warn_unit_slips(name, over, table, units, field)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", GeometryWarning)
            # the slips were said above in the scene's units; preset() says them in SI
            warnings.filterwarnings("ignore", message=_SLIP_MESSAGE, category=GeometryWarning)
            mech = preset(name, **over)
        for w in caught:        # e.g. a home pose some leg does not reach: one line each
            if not issubclass(w.category, GeometryWarning):
                warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
                continue
            si = "" if units.length == "m" else f"; the scene's [units] length is \"{units.length}\""
            print(f"distkin: warning: {field}.{w.message}{si}", file=sys.stderr, flush=True)
        return mech
    except InputError as exc:
        fld = exc.field if exc.field and exc.field != "preset" else None
        msg = exc.message
        unit = (units.length if fld in LENGTHS else units.angle if fld in ANGLES else None)
        if fld in table and unit not in (None, "m", "rad"):
            msg += f" (the scene's {fld} = {table[fld]!r} {unit})"     # SI above, scene units here
        raise InputError(msg, field=f"{field}.{fld}" if fld else field) from None


def unit_slips(name, over, table, units, field) -> list[str]:
    """:func:`~distkin.mechanisms.presets.slip_ratios` worded in the scene's units: one
    line per override more than :data:`SLIP_RATIO` times off the preset's value (0.152
    for l0 = 152 mm in a mm scene).  ``over`` holds the overrides in SI, ``table`` as
    written."""
    lines = []
    for k, _v, b, ratio, unit in slip_ratios(name, over):
        if k in LENGTHS:
            lines.append(_length_line(f"{field}.{k}", table[k], ratio, b, "the preset's",
                                      units))
        else:
            lines.append(f"{field}.{k}: {table[k]} {unit} is {ratio:.3g} x the preset's "
                         f"{b:.6g} {unit} ({k} is in {unit} (SI) whatever the scene's units)")
    return lines


def length_slips(checks, units) -> list[str]:
    """The same test and words for the other lengths of a scene: one line per
    ``(field, written, value, reference, what)`` whose SI ``value`` is more than
    :data:`SLIP_RATIO` times off the SI ``reference`` (``what`` names it, e.g. "the
    device's length scale"; :func:`~distkin.mechanisms.presets.slip_ratio`), worded in
    the scene's units with the value as ``written``: a study grid's half and step
    (0.025 for 25 mm in a mm scene), a design sweep's ranges."""
    lines = []
    for fld, written, value, reference, what in checks:
        ratio = slip_ratio(value, reference)
        if ratio is not None:
            lines.append(_length_line(fld, written, ratio, reference, what, units))
    return lines


def _length_line(fld, written, ratio, reference, what, units):
    lf = 1.0 / float(units.length_factor)
    return (f"{fld}: {written} {units.length} is {ratio:.3g} x {what} {reference * lf:.6g} "
            f"{units.length} (a length in another unit? the scene's [units] length is "
            f"\"{units.length}\")")


def warn_slips(lines):
    """Lines of :func:`unit_slips` or :func:`length_slips` as warnings on stderr, one
    line each (a line said once: devices of one size share their grid's)."""
    for line in dict.fromkeys(lines):
        print(f"distkin: warning: {line}", file=sys.stderr, flush=True)


def _warn_unit_slips(name, over, table, units, field):
    """:func:`unit_slips` as warnings, one line each on stderr."""
    warn_slips(unit_slips(name, over, table, units, field))
