"""Scene files: one mechanism and a list of queries, loaded into frozen objects.

The format is docs/design.md §4::

    [units]                     # optional; the engine works in SI
    length = "mm"               # m (default) | mm | cm | km | none (unitless)
    angle = "deg"               # rad (default) | deg

    [mechanism]
    kind = "octahedral"
    base = [[0,0,0], [6,"sqrt(108)",0], [12,0,0]]
    platform = [[0,0,0], [6,0,0], [3,"sqrt(27)",0]]

    [[query]]
    type = "forward_kinematics"
    legs = ["19.8", "18", "18", "17", "14.9", "17.8"]

Mechanism kinds and query types are registered by the modules that implement them
(:data:`MECHANISM_PARSERS` and :mod:`distkin.app.registry`); modules are imported only when
a scene names them ("model only what a scene requires").  Every query is parsed and
validated at load time, so a bad field is reported before any work starts.
"""

from __future__ import annotations

import os
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

from ..argcheck import as_table, check_keys, exact_matrix, require
from ..errors import DistkinError, InputError
from ..exact import exact_to_float
from ..toml_syntax import toml_syntax_error
from .units import SCENE_UNIT_KINDS, Units, name_scene_units, parse_units

__all__ = [
    "Units",
    "PointSet",
    "Octahedral",
    "Query",
    "Scene",
    "MECHANISM_PARSERS",
    "ANCHORS",
    "load_scene",
    "loads_scene",
    "input_files",
    "toml_syntax_error",
    "toml_text",
    "broken_link_error",
]

@dataclass(frozen=True)
class PointSet:
    """``kind = "points"``: a labelled point set (label i = row i - 1)."""

    points: tuple

    kind = "points"


@dataclass(frozen=True)
class Octahedral:
    """``kind = "octahedral"``: base P1 P2 P3 and platform P4 P5 P6 (Rojas et al., Fig. 4).

    ``base`` holds P1, P2, P3 in base coordinates; ``platform`` holds P4, P5, P6 in the
    platform frame.  Entries are :class:`~distkin.exact.Exact`.
    """

    base: tuple
    platform: tuple

    kind = "octahedral"


def _parse_points(table, units, fld):
    check_keys(table, {"kind", "points"}, fld)
    pts = exact_matrix(require(table, "points", fld), f"{fld}.points", cols=None)
    if len(pts) < 1:
        raise InputError("expected at least one point", field=f"{fld}.points")
    dims = {len(p) for p in pts}
    if len(dims) != 1:
        raise InputError(f"expected points of one dimension, got dimensions {sorted(dims)}",
                         field=f"{fld}.points")
    return PointSet(pts)


def _parse_octahedral(table, units, fld):
    check_keys(table, {"kind", "base", "platform"}, fld)
    base = exact_matrix(require(table, "base", fld), f"{fld}.base", rows=3, cols=3)
    plat = exact_matrix(require(table, "platform", fld), f"{fld}.platform", rows=3, cols=3)
    for name, rows in (("base", base), ("platform", plat)):
        for i, row in enumerate(rows):            # every tier rounds them once to float64
            for j, v in enumerate(row):
                exact_to_float(v, f"{fld}.{name}[{i}][{j}]")
    return Octahedral(base, plat)


def _parse_rss(table, units, field):
    from .mechanism_scene import parse_rss
    return parse_rss(table, units, field)


def _parse_legs(table, units, field, path=None):
    if isinstance(table, dict) and "octahedral" in table:
        from .platform_scene import parse_platform_legs
        return parse_platform_legs(table, units, field)
    from .legs_scene import parse_legs
    return parse_legs(table, units, field, path)


def _parse_platform66(table, units, field):
    from .queries.delta import parse_platform66
    return parse_platform66(table, units, field)


#: mechanism kind -> the function parsing its table (the rss and 6-6 parsers import
#: their modules on first use)
MECHANISM_PARSERS = {
    "points": _parse_points,
    "octahedral": _parse_octahedral,
    "rss": _parse_rss,
    "legs": _parse_legs,
    "platform66": _parse_platform66,
}

#: kinds whose tables may name files relative to the scene (the parser gets its path)
_WITH_PATH = ("legs",)

#: the roots of a scene's field names; an error whose field starts with none of them
#: came from inside a query and is re-anchored there ("dps" -> "query[0].dps")
ANCHORS = ("query", "mechanism", "units")


@dataclass(frozen=True)
class Query:
    """One ``[[query]]`` table: its type, its validated parameters and its position."""

    index: int
    type: str
    params: Any
    table: MappingProxyType = field(repr=False)

    @property
    def field(self) -> str:
        return f"query[{self.index}]"


@dataclass(frozen=True)
class Scene:
    """A loaded scene: units, mechanism and validated queries (immutable)."""

    path: str
    units: Units
    mechanism: Any
    mechanism_table: MappingProxyType
    queries: tuple


def loads_scene(text: str, path: str = "<string>") -> Scene:
    """Load a scene from TOML text; see :func:`load_scene`."""
    from . import registry
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise toml_syntax_error(text, exc, path) from None
    if not data:                   # "mechanism: missing required field 'mechanism'" before
        raise InputError("expected a [mechanism] table and [[query]] tables, got an empty "
                         "scene (no table, no key)", field="scene")
    if "mechanism" not in data and ("device" in data or "pd" in data):
        raise InputError("expected a run scene ([mechanism], [[query]]), got a controller "
                         "scene ([device], [pd], ...)", field="scene",
                         hint="run it with 'distkin control --sim --scene FILE' (or --port)")
    check_keys(data, {"units", "mechanism", "query", "title", "description"}, "scene")
    units = parse_units(data.get("units"))
    mtable = as_table(require(data, "mechanism", ""), "mechanism")
    kind = require(mtable, "kind", "mechanism")
    if not isinstance(kind, str) or kind not in MECHANISM_PARSERS:   # a list: unhashable
        raise InputError(f"expected one of {', '.join(map(repr, MECHANISM_PARSERS))}, "
                         f"got {kind!r}", field="mechanism.kind")
    try:
        mechanism = MECHANISM_PARSERS[kind](mtable, units, "mechanism",
                                            *((path,) if kind in _WITH_PATH else ()))
    except DistkinError as exc:         # the geometry is read in the scene's unit
        raise name_scene_units(exc, units)
    qlist = data.get("query", [])
    if isinstance(qlist, dict):                    # [query] written for [[query]]
        raise InputError("expected [[query]] tables (an array, double brackets), got one "
                         "[query] table", field="query", hint="write [[query]]")
    if not isinstance(qlist, list) or not qlist:
        raise InputError("expected at least one [[query]] table", field="query")
    parsed = []
    for i, q in enumerate(qlist):
        fld = f"query[{i}]"
        q = as_table(q, fld)
        qtype = require(q, "type", fld)
        spec = registry.get(qtype, kind, field=f"{fld}.type")
        try:
            params = spec.parse(q, mechanism, units, fld)
        except DistkinError as exc:
            if exc.field is None or not exc.field.startswith(ANCHORS):
                exc.with_field(fld)              # "dps" -> "query[0].dps"
            if kind in SCENE_UNIT_KINDS:
                name_scene_units(exc, units)
            raise
        parsed.append(Query(i, qtype, params, MappingProxyType(dict(q))))
    return Scene(str(path), units, mechanism, MappingProxyType(dict(mtable)), tuple(parsed))


def load_scene(path) -> Scene:
    """Load and validate a TOML scene file.

    Raises
    ------
    InputError
        Missing file, invalid TOML, unknown mechanism kind or query type, missing
        fields, wrong shapes, malformed numbers.  The error's ``field`` names the place
        (``mechanism.base[1][2]``, ``query[0].legs``, ...).
    """
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise (broken_link_error(p, "scene", "a scene") or InputError(
            f"expected a scene file, got a path that does not exist: {str(p)!r}",
            field="scene")) from None
    except (IsADirectoryError, PermissionError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read scene file {str(p)!r}: {exc}", field="scene") from None
    return loads_scene(text, str(p))


def toml_text(path, field: str, what: str) -> str:
    """The text of the TOML file ``path`` (a ``what``, given by the option ``field``),
    checked as TOML: a file that is not UTF-8 or cannot be read is an
    :class:`~distkin.errors.InputError` naming ``field``, and a syntax error names its
    line (:func:`toml_syntax_error`).  ``distkin control`` and ``sim`` read their
    ``--scene`` with it (QA: a non-UTF-8 controller scene was an internal failure, exit
    1, and an unclosed array named no line)."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"expected a UTF-8 text {what} file, got {str(path)!r} (byte "
                         f"{exc.start} is not UTF-8)", field=field) from None
    except OSError as exc:
        broken = broken_link_error(Path(path), field, f"a {what}")
        raise (broken or InputError(f"expected a readable {what} file, got {str(path)!r} "
                                    f"({exc.strerror or type(exc).__name__})",
                                    field=field)) from None
    try:
        tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise toml_syntax_error(text, exc, path) from None
    return text


def broken_link_error(p: Path, field: str, what: str) -> InputError | None:
    """The error of ``p`` a symbolic link whose target does not exist, or None (QA pkg
    9: five examples are links into distkin/scenes, and ``cp -a examples copy`` copied
    the links, which then said "a path that does not exist")."""
    try:
        if not p.is_symlink() or p.exists():
            return None
        target = os.readlink(p)
    except OSError:
        return None
    return InputError(f"expected {what} file, got {str(p)!r}, a broken symbolic link to "
                      f"{target!r} ({str(p.parent / target)!r} does not exist)", field=field,
                      hint="copy the files the links point to (cp -L), or run the original")


def input_files(scene: Scene) -> tuple:
    """The files a loaded scene was read from: the scene file and the ``legs_csv`` it
    names (relative to its folder).  An output option must name none of them
    (:func:`.output_paths.check_output_path`)."""
    files = [Path(scene.path)]
    csv_name = scene.mechanism_table.get("legs_csv")
    if isinstance(csv_name, str):
        files.append(Path(scene.path).parent / csv_name)
    return tuple(files)
