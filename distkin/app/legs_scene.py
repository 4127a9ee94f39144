"""The ``kind = "legs"`` mechanism table of a scene: any parallel mechanism, leg by leg.

::

    [units]
    length = "mm"               # lengths below in mm (m, cm, km also)
    angle = "deg"               # angles below in deg (or rad)

    [mechanism]
    kind = "legs"
    name = "gough6"
    home = [0, 0, 400, 0, 0, 0] # x y z (length), rx ry rz (angle); R = Rz Ry Rx
    mass = 10                   # kg, always SI
    inertia = "0.2"             # kg m^2, always SI
    # scale = 150               # optional FK length scale (length; default: mean |p|)
    # legs_csv = "legs.csv"     # the legs from a CSV file (path relative to the scene)
    # route = "numpy"           # plain-numpy kernels, no derivation (default "generated")

    [[mechanism.leg]]           # one table per leg, in actuator order
    type = "UPS"                # RSS | RUS | RRRS (revolute) | SPS | UPS (prismatic)
    base = [300, 0, 0]          # crank pivot / base joint (length, base frame)
    platform = [150, 0, 0]      # platform joint (length, end-effector frame)
    range = [350, 550]          # joint range: length (prismatic) or angle (revolute)
    limit = 1000                # actuator effort, SI: N (prismatic) or N m (revolute);
                                #   a number (±) or [min, max]
    # revolute legs also: axis, crank0, crank90 (unit vectors, no unit), crank, distal
    # (length), offset (length, along the axis; RRRS), branch (+1 | -1; default: the IK
    # solution nearer q = 0 at home)

Meaning of every field: :mod:`distkin.mechanisms.legs`.  Exactly one of
``[[mechanism.leg]]``, ``legs_csv`` and ``octahedral`` (the prismatic platforms of Rojas
et al.: the octahedral manipulator, its Δ 6-6 platform and the Fig. 2 approximations,
:mod:`distkin.app.platform_scene`).

CSV (``legs_csv``): one header row, one row per leg, in the scene's units, columns
(:data:`CSV_COLUMNS`; an empty cell is a field not given; any order; unknown or repeated
columns are refused; a vector's three columns and a ``_min``/``_max`` pair are given
together or not at all; blank lines are skipped but counted in the line numbers)::

    type, base_x, base_y, base_z, platform_x, platform_y, platform_z,
    axis_x, axis_y, axis_z, crank0_x, crank0_y, crank0_z, crank90_x, crank90_y, crank90_z,
    crank, offset_x, offset_y, offset_z, distal, branch, range_min, range_max,
    limit_min, limit_max

Errors name the leg and the field (``mechanism.leg[3].axis``, or
``mechanism.legs_csv[3].axis`` with the file's line number and, for one cell, its
column), the expected and the received value.
"""

from __future__ import annotations

import csv
from fractions import Fraction
from pathlib import Path

from ..argcheck import as_table, check_keys, require
from ..errors import DistkinError, InputError
from ..exact import exact_to_float, parse_exact, parse_float
from ..mechanisms.kinematics import LegMechanism
from ..mechanisms.legs import LEG_FIELDS, PRISMATIC_TYPES
from .units import angle_factor, length_factor, si_length_hint, warn_radians

__all__ = ["parse_legs", "parse_home", "CSV_COLUMNS", "legs_csv_text", "legs_toml_text",
           "DEFAULT_LENGTH_UNIT"]

_VECTORS = ("base", "platform", "axis", "crank0", "crank90", "offset")
_LENGTH_VECTORS = ("base", "platform", "offset")
_LENGTHS = ("crank", "distal")

#: the CSV columns, in the order :func:`legs_csv_text` writes them
CSV_COLUMNS = (("type",) + tuple(f"{v}_{c}" for v in _VECTORS[:5] for c in "xyz")
               + ("crank", "offset_x", "offset_y", "offset_z", "distal", "branch",
                  "range_min", "range_max", "limit_min", "limit_max"))


def _length(value, units, fld):
    """A scene length in metres: an exact value times the exact unit, rounded once (the
    same float whichever unit a value is written in)."""
    length_factor(units, fld)                   # a physical unit, or the error
    return exact_to_float(parse_exact(value, fld), fld, units.length_factor)


def _number(value, fld):
    return parse_float(value, fld)


def _vector(value, fld, conv):
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise InputError(f"expected a list of 3 numbers, got {value!r}", field=fld)
    return tuple(conv(v, f"{fld}[{i}]") for i, v in enumerate(value))


def _leg(table, units, fld):
    """One leg table (scene units) -> keyword arguments of :class:`~.legs.Leg` (SI)."""
    table = as_table(table, fld)
    check_keys(table, set(LEG_FIELDS), fld)
    kind = require(table, "type", fld)
    prismatic = kind in PRISMATIC_TYPES
    length = lambda v, f: _length(v, units, f)  # noqa: E731
    out = {"type": kind}
    for k, v in table.items():
        f = f"{fld}.{k}"
        if k in _VECTORS:
            out[k] = _vector(v, f, length if k in _LENGTH_VECTORS else _number)
        elif k in _LENGTHS:
            out[k] = length(v, f)
            if not out[k] > 0:
                raise InputError(f"expected a positive length, got {v!r} ({units.length})",
                                 field=f)
        elif k == "branch":
            out[k] = v
        elif k == "range":
            if not isinstance(v, (list, tuple)) or len(v) != 2:
                raise InputError(f"expected [min, max], got {v!r}", field=f)
            af = angle_factor(units)
            out[k] = tuple(length(x, f"{f}[{i}]") if prismatic else _number(x, f"{f}[{i}]") * af
                           for i, x in enumerate(v))
        elif k == "limit":
            if isinstance(v, (list, tuple)):
                if len(v) != 2:
                    raise InputError(f"expected a number or [min, max], got {v!r}", field=f)
                out[k] = tuple(_number(x, f"{f}[{i}]") for i, x in enumerate(v))
            else:                              # a number: ±limit, so a magnitude
                out[k] = _number(v, f)
                if not out[k] > 0:
                    raise InputError(f"expected a positive effort limit (a number stands for "
                                     f"±limit; [min, max] for asymmetric limits), got {v!r} "
                                     f"{'N' if prismatic else 'N·m'}", field=f)
    return out


def _csv_legs(path: Path, fld):
    """The leg tables of a CSV file (:data:`CSV_COLUMNS`) and the file's line number of
    each (blank lines skipped, but counted)."""
    try:
        text = path.read_text(encoding="utf-8-sig")   # a byte-order mark (Excel) skipped
    except OSError as exc:
        raise InputError(f"expected a readable CSV file, got {str(path)!r} ({exc.strerror})",
                         field=fld) from None
    from .csv_rows import csv_rows
    rows = csv_rows(text, path.name, fld)
    if not rows:
        raise InputError(f"expected a header row and one row per leg, got an empty file "
                         f"{path.name!r}", field=fld)
    head_line, head = rows[0][0], [h.strip() for h in rows[0][1]]
    bad = [h for h in head if h not in CSV_COLUMNS]
    if bad:
        raise InputError(f"expected columns among {', '.join(CSV_COLUMNS)}, got {bad}",
                         field=fld, hint=f"line {head_line} of {path.name}")
    for h in head:
        if head.count(h) > 1:
            where = " and ".join(str(i + 1) for i, x in enumerate(head) if x == h)
            raise InputError(f"expected each column once in the header (line {head_line} "
                             f"of {path.name}), got {h!r} {head.count(h)} times (columns "
                             f"{where})", field=fld)
    legs, lines = [], []
    for n, (line, row) in enumerate(rows[1:]):
        f = f"{fld}[{n}]"
        at = f"line {line} of {path.name}"
        if len(row) != len(head):
            raise InputError(f"expected {len(head)} cells ({at}), got {len(row)}", field=f)
        cells = {h: c.strip() for h, c in zip(head, row) if c.strip() != ""}
        table = {}
        for name in LEG_FIELDS:
            if name in _VECTORS:
                cols = [f"{name}_{c}" for c in "xyz"]
            elif name in ("range", "limit"):
                cols = [f"{name}_min", f"{name}_max"]
            else:
                if name in cells:
                    table[name] = cells[name] if name != "branch" else _branch(cells[name], f)
                continue
            parts = [cells.get(c) for c in cols]
            if any(p is not None for p in parts):
                if any(p is None for p in parts):
                    raise InputError(_half_given(name, cols, cells, head, at),
                                     field=f"{f}.{name}")
                table[name] = parts
        legs.append(table)
        lines.append(line)
    return legs, lines


def _half_given(name, cols, cells, head, at):
    """The message of a vector or a [min, max] pair given in part (a CSV row)."""
    given = [f"{c} = {cells[c]}" for c in cols if c in cells]
    missing = [f"{c} ({'an empty cell' if c in head else 'no such column'})"
               for c in cols if c not in cells]
    return (f"expected {_and(cols)} together ({at}), got {_and(given)} but no "
            f"{_and(missing)}")


def _and(items):
    items = list(items)
    return items[0] if len(items) == 1 else f"{', '.join(items[:-1])} and {items[-1]}"


def _csv_column(rest: str) -> str | None:
    """The CSV column of a leg's field path (``"base[0]"`` -> ``"base_x"``, ``"range[1]"``
    -> ``"range_max"``, ``"crank"`` -> ``"crank"``), None when there is none."""
    name, _, index = rest.partition("[")
    if index:
        i = index.rstrip("]")
        if name in _VECTORS and i in ("0", "1", "2"):
            return f"{name}_{'xyz'[int(i)]}"
        if name in ("range", "limit") and i in ("0", "1"):
            return f"{name}_{('min', 'max')[int(i)]}"
        return None
    return name if name in CSV_COLUMNS else None


def _branch(text, fld):
    try:
        return int(text)
    except ValueError:
        raise InputError(f"expected branch +1 or -1, got {text!r}", field=f"{fld}.branch") from None


def parse_legs(table, units, field, scene_path=None):
    """Parse a ``legs`` mechanism table into a :class:`~.kinematics.LegMechanism` (SI).

    ``scene_path`` is the scene file (``legs_csv`` is relative to its folder)."""
    check_keys(table, {"kind", "name", "home", "mass", "inertia", "scale", "leg", "legs_csv",
                       "route"}, field)
    if ("leg" in table) == ("legs_csv" in table):
        raise InputError("expected exactly one of [[mechanism.leg]] tables, legs_csv and "
                         "octahedral, got "
                         f"{'both' if 'leg' in table else 'neither'}", field=field)
    if "leg" in table:
        raw = table["leg"]
        if not isinstance(raw, list):
            raise InputError(f"expected [[{field}.leg]] tables, got {type(raw).__name__}",
                             field=f"{field}.leg")
        prefix = f"{field}.leg"
    else:
        csv_name = table["legs_csv"]
        if not isinstance(csv_name, str):
            raise InputError(f"expected a file name, got {csv_name!r}", field=f"{field}.legs_csv")
        base = Path(scene_path).parent if scene_path else Path.cwd()
        raw, lines = _csv_legs(base / csv_name, f"{field}.legs_csv")
        prefix = f"{field}.legs_csv"

        def where(i, fld=""):            # the row (and the column) of leg i's field
            rest = fld.partition(f"{prefix}[{i}].")[2]
            column = _csv_column(rest) if rest else None
            return f"line {lines[i]} of {csv_name}" + (f", column {column}" if column else "")
    if "leg" in table:
        where = None
    legs = []
    for i, t in enumerate(raw):
        try:
            legs.append(_leg(t, units, f"{prefix}[{i}]"))
        except DistkinError as exc:
            if where is not None:       # the row and column first, then any hint
                exc.hint = "; ".join(filter(None, (where(i, exc.field or ""), exc.hint)))
                exc.args = (exc.one_line(),)
            raise
    home = parse_home(require(table, "home", field), units, f"{field}.home")
    kw = {k: _number(table[k], f"{field}.{k}") for k in ("mass", "inertia") if k in table}
    if "scale" in table:
        kw["scale"] = _length(table["scale"], units, f"{field}.scale")
    if "route" in table:
        from ..argcheck import choice
        from ..mechanisms.kinematics import ROUTES
        kw["route"] = choice(table["route"], f"{field}.route", ROUTES)
    name = table.get("name", "legs")
    if not isinstance(name, str):
        raise InputError(f"expected a name (text), got {name!r}", field=f"{field}.name")
    try:
        return _built(name, tuple(legs), home, kw, units, field, prefix)
    except DistkinError as exc:
        fld = exc.field or ""
        if fld.startswith("leg["):
            i = int(fld[4:fld.index("]")])
            fld = prefix + fld[3:]
            if where is not None:
                exc.hint = "; ".join(filter(None, (where(i, fld), exc.hint)))
        elif fld == "leg":                 # the table as a whole: [[leg]] or the CSV
            fld = prefix
        else:
            fld = f"{field}.{fld}" if fld else field
        si = si_length_hint(exc, units)    # the description's message is in SI
        if si:
            exc.hint = "; ".join(filter(None, (exc.hint, si)))
        exc.field = None
        raise exc.with_field(fld) from None


def _built(name, legs, home, kw, units, field, prefix):
    """The :class:`~distkin.mechanisms.kinematics.LegMechanism`, its load warnings
    (:class:`~distkin.errors.GeometryWarning`: a home some leg does not reach, lines
    that do not span 6 DOF) said with the scene's field (``mechanism.home``, the leg
    table's ``prefix``) and, when they state lengths (SI), the scene's length unit, as
    an RSS scene's are (QA: they read ``home: ...`` in m without a word of the scene's
    mm)."""
    import warnings

    from ..errors import GeometryWarning, warn
    from .units import has_si_length
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", GeometryWarning)
        mech = LegMechanism(name, legs, home, **kw)
    for w in caught:
        if not issubclass(w.category, GeometryWarning):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
            continue
        text = str(w.message)
        head, _, rest = text.partition(": ")
        if head in ("home", "leg"):
            text = f"{prefix if head == 'leg' else field + '.home'}: {rest}"
        if units.length not in ("m", "none") and has_si_length(text):
            text += f" (lengths in this message in m (SI), the scene's in {units.length})"
        warn(text, GeometryWarning)
    return mech


def parse_home(home, units, fld):
    """A scene's ``home`` pose [x, y, z, rx, ry, rz] (scene units) in m and rad."""
    if not isinstance(home, list) or len(home) != 6:
        raise InputError(f"expected [x, y, z, rx, ry, rz], got {home!r}", field=fld)
    af = angle_factor(units)
    angles = [_number(v, f"{fld}[{i + 3}]") for i, v in enumerate(home[3:])]
    warn_radians(angles, units, fld)
    return tuple([_length(v, units, f"{fld}[{i}]") for i, v in enumerate(home[:3])]
                 + [a * af for a in angles])


#: the length unit :func:`legs_csv_text` and :func:`legs_toml_text` write by default (the
#: same for both: a scene and its CSV written with the defaults agree)
DEFAULT_LENGTH_UNIT = "mm"


def legs_csv_text(mech, *, length_unit: str = DEFAULT_LENGTH_UNIT) -> str:
    """A leg table as CSV text (:data:`CSV_COLUMNS`), lengths in ``length_unit`` ("m",
    "mm" (the default, as :func:`legs_toml_text`), "cm"), angles in rad, limits in SI,
    each the shortest decimal that a scene in that unit (and ``angle = "rad"``) reads
    back to the same float.  The CSV has no unit of its own: the scene's ``[units]`` are
    its unit, so the scene (:func:`legs_toml_text` with ``csv_name``) must be written in
    the same ``length_unit``."""
    import io
    from .units import parse_units
    desc = mech.leg_description()

    def num(x, unit=1):
        return _shortest(x, unit)

    lu = parse_units({"length": length_unit, "angle": "rad"}).length_factor
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(CSV_COLUMNS)
    for leg in desc.leg_table:
        d = leg.as_dict()
        row = []
        for col in CSV_COLUMNS:
            name, _, part = col.rpartition("_") if "_" in col else (col, "", "")
            if col == "type":
                row.append(leg.type)
            elif name in _VECTORS and part in "xyz":
                v = d.get(name)
                row.append("" if v is None else
                           num(v["xyz".index(part)], lu if name in _LENGTH_VECTORS else 1))
            elif col in _LENGTHS:
                row.append("" if d.get(col) is None else num(d[col], lu))
            elif col == "branch":
                row.append("" if leg.branch is None else str(leg.branch))
            else:
                v = d.get(name)
                k = 0 if part == "min" else 1
                unit = lu if (name == "range" and leg.prismatic) else 1
                row.append("" if v is None else num(v[k], unit))
        w.writerow(row)
    return buf.getvalue()


def _toml_string(text: str) -> str:
    """``text`` as a TOML basic string (JSON's escapes are TOML's: quotes, backslashes
    and control characters escaped; other characters kept as they are)."""
    import json
    return json.dumps(str(text), ensure_ascii=False)


def legs_toml_text(mech, *, length_unit: str = DEFAULT_LENGTH_UNIT,
                   csv_name: str | None = None) -> str:
    """A ``[mechanism]`` table (``kind = "legs"``, with ``[units]``) of any mechanism
    description, every length written exactly in ``length_unit`` ("m", "mm", "cm"),
    angles in rad: the scene reads it back to the same floats (the same kernels and
    numbers; tests/mechanisms/test_legs_scene.py).  With ``csv_name`` the legs are left to
    that CSV file, which the scene reads in its ``[units]``: write it with
    :func:`legs_csv_text` in the same ``length_unit`` (both default to
    :data:`DEFAULT_LENGTH_UNIT`); the scene says so in a comment."""
    from .units import parse_units
    lu = parse_units({"length": length_unit, "angle": "rad"}).length_factor
    desc = mech.leg_description()

    def num(x, unit=1):
        return '"' + _shortest(x, unit) + '"'

    def vec(v, unit=1):
        return "[" + ", ".join(num(x, unit) for x in v) + "]"

    out = [f'[units]\nlength = "{length_unit}"\nangle = "rad"\n', "[mechanism]",
           'kind = "legs"', f"name = {_toml_string(desc.name)}",
           f"home = [{', '.join([num(x, lu) for x in desc.home_pose[:3]] + [num(x) for x in desc.home_pose[3:]])}]",
           f"mass = {num(desc.mass)}", f"inertia = {num(desc.inertia)}"]
    if desc.scale is not None:
        out.append(f"scale = {num(desc.scale, lu)}")
    if csv_name is not None:
        out.append(f"# the legs in {csv_name}, lengths in {length_unit} (this scene's "
                   f"[units]: legs_csv_text(mech, length_unit=\"{length_unit}\"))"
                   .replace("\n", " "))
        out.append(f"legs_csv = {_toml_string(csv_name)}")
        return "\n".join(out) + "\n"
    for leg in desc.leg_table:
        out.append("\n[[mechanism.leg]]")
        for k, v in leg.as_dict().items():
            if k == "type":
                out.append(f'type = "{v}"')
            elif k in _LENGTH_VECTORS:
                out.append(f"{k} = {vec(v, lu)}")
            elif k in _VECTORS:
                out.append(f"{k} = {vec(v)}")
            elif k in _LENGTHS:
                out.append(f"{k} = {num(v, lu)}")
            elif k == "branch":
                out.append(f"branch = {v}")
            else:
                out.append(f"{k} = {vec(v, lu if (k == 'range' and leg.prismatic) else 1)}")
    return "\n".join(out) + "\n"


def _shortest(x: float, unit=1) -> str:
    """The shortest decimal text d with float(d * unit) == x exactly (what a scene in
    that unit reads back as x), else the exact value of x / unit."""
    unit = Fraction(unit)
    y = Fraction(x) / unit
    for digits in range(1, 18):
        d = f"{float(y):.{digits}g}"
        if float(Fraction(d) * unit) == x:
            return d if "e" not in d else _exact_decimal(Fraction(d))
    return _exact_decimal(y)


def _exact_decimal(fr: Fraction) -> str:
    """The exact value of a dyadic fraction times a power of ten, as text (a decimal when
    it terminates, else ``p/q``); parse_exact reads it back exactly."""
    if fr.denominator == 1:
        return str(fr.numerator)
    d = fr.denominator
    twos = fives = 0
    while d % 2 == 0:
        d //= 2
        twos += 1
    while d % 5 == 0:
        d //= 5
        fives += 1
    if d != 1:
        return f"{fr.numerator}/{fr.denominator}"
    k = max(twos, fives)
    digits = abs(fr.numerator) * 10 ** k // fr.denominator
    s = str(digits).rjust(k + 1, "0")
    s = f"{s[:-k]}.{s[-k:]}".rstrip("0").rstrip(".")
    return ("-" if fr < 0 else "") + s
