"""Scene query ``delta_transform``: the Δ-transform of an octahedral mechanism.

Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited*, Sec. V-VI, eqs. (7)-(9).

Scene fields::

    [[query]]
    type = "delta_transform"
    offsets = ["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]   # delta1..delta6, eq. (9) rows;
                                             # numbers or symbol names ("Delta1")
    m_legs = ["6/25*sqrt(6170)", ...]        # optional: lengths of the 6-6 platform's legs
    solve = true                             # optional (default: true when m_legs and the
                                             # offsets are numeric): 6-6 forward kinematics
    method = "fast"                          # tier of the octahedral solver (or "auto")
    dps = 30                                 # precise (and auto's escalations) only

The JSON result has ``A`` (rows of strings), ``b``, ``det``, ``det_factors`` (the
irreducible factors, sympy syntax), ``det_constant``; with ``m_legs`` also
``mapped_squared_legs`` and ``mapped_legs`` (the l-legs, exact strings; their floats in
``*_float``; ``m_legs`` as written, a bare float a JSON number); with ``solve``
the 6-6 poses, each checked on the 6-6 platform's own joints (``max_leg_error``, null
with no pose; ``points`` P4 P5 P6 of the equivalent octahedron, ``platform_joints`` the
six joints), the equivalent octahedron's ``real_roots`` and ``octic`` (docs/design.md §4;
null when eq. (8) proves no pose), and the octahedral solver's word on them, as the
octahedral query gives it: ``certified``, ``conditioning`` (the fast tier's proof of its count, or why there is
none; the text then warns that the count may be wrong), ``reason`` (why there is no
pose) and ``notes`` (its warnings, said here rather than on stderr).

Numeric offsets outside 0 < delta_i < d_i (the joint leaves its edge, Fig. 6)
are refused at load time, as for ``kind = "platform66"``: ``InputError``, or
``DegenerateGeometryError`` at an end of the edge; a symbol is a parameter and is not
checked.  Offsets that make A singular raise ``DegenerateGeometryError`` at load time,
naming the vanishing factor; negative mapped squared lengths are an answer in ``delta_transform``
(``mapped_legs`` null, the ``reason``; with ``solve`` a ``forward_kinematics`` of 0 poses,
proved) as in the ``platform66`` forward kinematics: no pose (status ok, ``count`` 0, ``poses: []`` and the
``reason``; docs/design.md §4: a proved empty answer is an answer).

Mechanism kind ``platform66`` (Fig. 6): the 6-6 platform given by its octahedral parent
and the offsets; its ``forward_kinematics`` query takes the m-legs::

    [mechanism]
    kind = "platform66"
    base = [[0,0,0], [6,"sqrt(108)",0], [12,0,0]]        # P1 P2 P3 of the octahedral parent
    platform = [[0,0,0], [6,0,0], [3,"sqrt(27)",0]]      # P4 P5 P6, platform frame
    offsets = ["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]

    [[query]]
    type = "forward_kinematics"
    legs = ["6/25*sqrt(6170)", ...]                      # m1..m6
    method = "fast"

``delta_transform`` and ``singularity`` serve ``platform66`` too (offsets default to
the mechanism's).  Lengths are in the scene's length unit throughout.
"""

from __future__ import annotations

from dataclasses import dataclass

from ...argcheck import check_keys, dps_field, exact_matrix, method_field, require
from ...errors import DistkinError, InfeasibleError, InputError
from ...exact import METHODS_AUTO, exact_to_float, parse_vector
from ..query import Outcome, register
from ..report import as_written, float_inputs, float_inputs_line
from .octahedral import (check_leg_length, count_verdict, floats_segment_error, octic_fields,
                         pose_points, roots_lines)
from .octahedral import result_units as octahedral_units

__all__ = ["DeltaTransformQuery", "Platform66Forward", "Platform66Mechanism",
           "parse_platform66", "plot_det_family"]


@dataclass(frozen=True)
class Platform66Mechanism:
    """``kind = "platform66"``: the 6-6 platform of Rojas et al., Fig. 6, given by its
    octahedral parent (``base`` P1..P3, ``platform`` P4..P6 in the platform frame) and
    the offsets delta1..delta6 (eq. (9) rows).  Entries are
    :class:`~distkin.exact.Exact`."""

    base: tuple
    platform: tuple
    offsets: tuple

    kind = "platform66"


def parse_platform66(table, units, fld):
    """Scene parser of ``kind = "platform66"`` (registered in ``MECHANISM_PARSERS``).

    Raises
    ------
    InputError, DegenerateGeometryError
        Malformed points or offsets; offsets with det(A) = 0 or merging two joints.
    """
    from ...delta import equivalent_platform
    check_keys(table, {"kind", "base", "platform", "offsets"}, fld)
    base = exact_matrix(require(table, "base", fld), f"{fld}.base", rows=3, cols=3)
    plat = exact_matrix(require(table, "platform", fld), f"{fld}.platform", rows=3, cols=3)
    for name, rows in (("base", base), ("platform", plat)):
        for i, row in enumerate(rows):     # as kind = "octahedral": "1e400" is refused
            for j, v in enumerate(row):
                exact_to_float(v, f"{fld}.{name}[{i}][{j}]")
    offs = parse_vector(require(table, "offsets", fld), f"{fld}.offsets", length=6)
    try:
        equivalent_platform((base, plat), offs)
    except DistkinError as exc:
        raise exc.with_field(fld) if exc.field and not exc.field.startswith(fld) else exc
    return Platform66Mechanism(base, plat, offs)


@dataclass(frozen=True)
class _Params:
    offsets: tuple
    m_legs: tuple | None
    solve: bool
    method: str
    dps: int | None
    transform: object
    mechanism: object
    field: str = "query"         # "query[2]": the names in ``inputs_from_float``


def _fmt_matrix(M):
    return [[str(M[i, j]) for j in range(M.cols)] for i in range(M.rows)]


@register("delta_transform", mechanisms=("octahedral", "platform66"),
          summary="Δ-transform: A, b, det(A) factorised, mapped legs, equivalent 6-6 FK")
class DeltaTransformQuery:
    @staticmethod
    def parse(table, mechanism, units, field):
        from ...delta import check_offsets, delta_transform
        check_keys(table, {"type", "offsets", "m_legs", "solve", "method", "dps"}, field)
        if "offsets" in table:
            offs = parse_vector(table["offsets"], f"{field}.offsets", length=6,
                                allow_symbols=True)
        elif getattr(mechanism, "kind", None) == "platform66":
            offs = mechanism.offsets
        else:
            raise InputError("missing required field 'offsets' (delta1..delta6)",
                             field=f"{field}.offsets")
        tr = delta_transform(mechanism, offs, field=f"{field}.offsets")
        # 0 < delta_i < d_i for every numeric offset, as kind = "platform66" and the
        # singularity query check them (QA V 3); a symbol is a parameter
        check_offsets(tr, field=f"{field}.offsets")
        tr.check_regular(field=f"{field}.offsets")
        m_legs = None
        if "m_legs" in table:
            m_legs = parse_vector(table["m_legs"], f"{field}.m_legs", length=6)
            for i, m in enumerate(m_legs):
                check_leg_length(m, f"{field}.m_legs[{i}]")
        solve = table.get("solve", m_legs is not None and not tr.free_symbols)
        if not isinstance(solve, bool):
            raise InputError(f"expected true or false, got {solve!r}", field=f"{field}.solve")
        if solve and m_legs is None:
            raise InputError("expected m_legs when solve = true", field=f"{field}.solve")
        if solve and tr.free_symbols:
            raise InputError("expected numeric offsets when solve = true, got symbols "
                             f"{', '.join(map(str, tr.free_symbols))}", field=f"{field}.solve")
        method = method_field(table, field, allowed=METHODS_AUTO)
        # (None when not written: the library's default, 30 precise, 50 for auto's fallback)
        dps = dps_field(table, method, field, uses=("precise", "auto")) \
            if "dps" in table else None
        return _Params(offs, m_legs, solve, method, dps, tr, mechanism, field)

    @staticmethod
    def run(p, scene, ctx):
        import sympy as sp

        from ...delta import SIDE_NAMES, derive_eq7
        tr = p.transform
        unit = "" if scene.units.length == "none" else f" {scene.units.length}"
        const, factors = tr.det_factors()
        eq7 = derive_eq7()
        result = {
            "offsets": [str(o) for o in tr.offsets],
            "sides": {n: str(d) for n, d in zip(SIDE_NAMES, tr.sides)},
            "eq7": f"{sp.sstr(eq7.relation)} = 0",
            "sign_convention": "m^2 = A l^2 - b (eq. (8))",
            "A": _fmt_matrix(tr.A),
            "b": [str(x) for x in tr.b],
            "det": sp.sstr(tr.det),
            "det_constant": str(const),
            "det_factors": [sp.sstr(f) for f, _ in factors],
            "det_multiplicities": [int(k) for _, k in factors],
        }
        lines = ["eq. (7) from D(1,2,3,4) = -2 L^2:  " + result["eq7"],
                 "sides: " + ", ".join(f"{n} = {d}{unit}" for n, d in result["sides"].items()),
                 "offsets: " + ", ".join(f"delta{i + 1} = {o}{unit}"
                                         for i, o in enumerate(result["offsets"])),
                 "A (eq. (9), dimensionless), m^2 = A l^2 - b:"]
        lines += ["  [" + ", ".join(row) + "]" for row in result["A"]]
        lines.append("b = [" + ", ".join(result["b"]) + f"]{unit}^2" if unit else
                     "b = [" + ", ".join(result["b"]) + "]")
        lines.append(f"det(A) = {result['det']}")
        numeric_regular = not tr.free_symbols and tr.det != 0
        if numeric_regular:   # a non-zero number: its "factors" say nothing (QA J 3)
            lines.append(f"det(A) = {float(tr.det):.10g} != 0: the equivalent 6-6 platform "
                         "is not architecturally singular")
        elif factors:
            fac = " * ".join(f"({f})" + (f"^{k}" if k > 1 else "")
                             for f, k in zip(result["det_factors"], result["det_multiplicities"]))
            lines.append(f"det(A) = {const} * {fac}")
            lines.append("architecturally singular where a factor vanishes")
        else:
            lines.append("det(A) != 0: the equivalent 6-6 platform is not architecturally singular")
        no_map = None
        if p.m_legs is not None:
            result["m_legs"] = as_written(p.m_legs)
            try:
                l_sq, l = tr.map_legs(p.m_legs, field="m_legs")
            except InfeasibleError as exc:    # proved: no real l-leg, so no pose
                if not (exc.margin is not None and exc.margin < 0):
                    raise
                no_map = _no_map_reason(exc, scene.units.length)
        if no_map is not None:
            result["mapped_legs"] = None
            result["reason"] = no_map
            lines.append(f"m-legs -> l-legs: none real; {no_map}")
            if p.solve:
                # the fields of a solved answer (QA W 13), the tier the exact map's
                result["forward_kinematics"] = {
                    "method": p.method, "tier": "exact", "count": 0, "certified": True,
                    "poses": [], "reason": no_map, "max_leg_error": None, **_NO_OCTIC,
                    "conditioning": None, "notes": [],
                    "tier_reason": "the exact inverse map of eq. (8) proves that no pose "
                                   "exists; no octahedral solve ran"}
                lines.append(f"6-6 forward kinematics ({p.method}): 0 poses (proved)")
        elif p.m_legs is not None:
            result["mapped_squared_legs"] = [sp.sstr(x) for x in l_sq]
            # exact forms, as they are (nsimplify would pass off a nearby "simple"
            # number as the value); the text shows a long one by its value only
            result["mapped_legs"] = [sp.sstr(x) for x in l]
            if not tr.free_symbols:          # the floats beside the long exact forms
                result["mapped_legs_float"] = [float(x) for x in l]
                result["mapped_squared_legs_float"] = [float(x) for x in l_sq]
            lines.append("m-legs -> l-legs (exact, l^2 = A^-1 (m^2 + b)):")
            for i, (m, x) in enumerate(zip(result["m_legs"], result["mapped_legs"])):
                shown = _shown(x, None if tr.free_symbols else l[i], unit)
                lines.append(f"  m{i + 1} = {m}{unit}  ->  l{i + 1} = {shown}")
        if p.solve and no_map is None:
            lines += _solve(p, result, unit, ctx)
        if _family_ok(tr):
            lines += _family_finding(tr, result)
        result["unit"] = result_units(scene.units)
        _flag_floats(p.m_legs or (), "m_legs", p, result, lines)
        plot = (lambda stem: plot_det_family(tr, stem)) if _family_ok(tr) else None
        return Outcome(result, "\n".join(lines), plot)


def _shown(text: str, value, unit: str) -> str:
    """A mapped leg in the text report: its exact form and value, or, when the exact
    form is long (float data make nested radicals of hundreds of digits), the value
    only (the exact form stays in the JSON).  ``value`` None: symbolic."""
    if value is None:
        return f"{text}{unit}"
    approx = f"{float(value):.10g}{unit}"
    if len(text) <= 60:
        return f"{text}{unit}  (= {approx})"
    return f"{approx} (exact form: {len(text)} characters, in the JSON)"


def result_units(units) -> dict:
    """The ``unit`` block of a delta_transform result: lengths in the scene's own length
    unit (the geometry is used as written, exactly, not converted to SI), "none" for a
    unitless scene; A and det(A) are dimensionless, b and the squared legs squared
    lengths."""
    L = "none" if units.length == "none" else units.length
    L2 = "none" if L == "none" else f"{L}^2"
    octa_units = octahedral_units(units)
    return {"length": L, "offsets": L, "sides": L, "A": "none", "det": "none",
            "b": L2, "m_legs": L, "mapped_legs": L, "mapped_squared_legs": L2,
            "mapped_legs_float": L, "mapped_squared_legs_float": L2,
            "forward_kinematics": {
                "s15": L2, "translation": L, "platform_joints": L, "base_joints": L,
                "points": octa_units["points"], "real_roots": octa_units["real_roots"],
                "octic": octa_units["octic"],
                "platform_joints_local": L, "rotation": "none (rotation matrix)",
                "max_leg_error": L, "max_leg_error_solver": L,
                "det_J66": f"{L}^3 (normalised Plücker rows, moments in {L})"
                           if L != "none" else "none"}}


def _flag_floats(legs, name, p, result, lines):
    """Say which exact inputs were bare floats (docs/design.md §3), in the JSON and text,
    by their full paths (``query[2].m_legs[0]``, ``mechanism.offsets[1]``), as errors
    name them."""
    where = ("mechanism.offsets" if p.offsets is getattr(p.mechanism, "offsets", None)
             else f"{p.field}.offsets")
    named = ([(f"{p.field}.{name}[{i}]", v) for i, v in enumerate(legs)]
             + [(f"{where}[{i}]", v) for i, v in enumerate(p.offsets)]
             + [(f"mechanism.{k}[{i}][{j}]", v)
                for k in ("base", "platform")
                for i, row in enumerate(getattr(p.mechanism, k, ()))
                for j, v in enumerate(row)])
    result["inputs_from_float"] = float_inputs(named)
    note = float_inputs_line(named)
    if note:
        lines.append(note)


def _solve(p, result, unit, ctx):
    """Run the 6-6 forward kinematics, add it to ``result``; return text lines.  The
    octahedral solver's verdict on its count (``certified``, the fast tier's proof
    ``conditioning``) and, with no pose, its ``reason`` are said as the octahedral query
    says them (QA V 1, 2); its warnings go into the result (``notes``), not to stderr."""
    import warnings

    import numpy as np

    from ...delta import forward_kinematics66
    from ...errors import ConditioningWarning
    from ...singularity import jacobian_det
    if p.method in ("fast", "auto"):
        from ...octahedral.warmup import compile_fast_tier
        compile_fast_tier(notice=ctx.notice)  # first solve here: 2 processes
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ConditioningWarning)
        fk = forward_kinematics66(p.mechanism, p.offsets, p.m_legs, method=p.method,
                                  dps=p.dps)
    flt = lambda a: np.vectorize(float, otypes=[float])(np.asarray(a, dtype=object))  # noqa: E731
    bj = flt(fk.platform.base_joints)
    sq = f"{unit}^2" if unit else ""
    octa = fk.octahedral
    tier = getattr(octa, "tier", "") or p.method
    bound = " (rigorous arb bound)" if tier == "certified" else ""
    cond = getattr(octa, "conditioning", None)
    proof = cond if tier == "fast" else None     # (auto: the fast attempt's, if escalated)
    n = len(fk.poses)
    poses = []
    lines = [f"6-6 forward kinematics ({p.method}): {n} pose{'s' if n != 1 else ''}; "
             + ("each checked on the 6-6 platform's own joints" if n else octa.reason)]
    if p.method == "auto":
        lines.append(f"  answered by the {tier} tier: {octa.tier_reason}")
    if proof is not None and not proof.trusted:
        lines.append(f"  WARNING: {proof.reason}; the count may be wrong "
                     "(use method = \"auto\" or \"certified\")")
    lines.append(f"  the count: {count_verdict(octa, proof)}")
    lines += ["  " + x for x in roots_lines(octa, unit.strip(), "the equivalent octahedron's "
                                            f"octic in s15 (degree {octa.degree})")]
    for k, pose in enumerate(fk.poses):
        R, t = flt(pose.rotation), flt(pose.translation)
        pj = flt(pose.platform_joints)
        s15 = float(getattr(pose.octahedral_pose, "s15", float("nan")))
        detj = float(jacobian_det(bj, pj, warn=False))
        # of the float joints printed, as the octahedral poses' (docs/design.md §3)
        err = floats_segment_error(fk.platform.base_joints, pj, p.m_legs)[0]
        poses.append({"s15": s15, "rotation": R, "translation": t, "platform_joints": pj,
                      "points": pose_points(pose.octahedral_pose),  # the equivalent octahedron's
                      "max_leg_error": err, "max_leg_error_solver": pose.max_leg_error, "det_J66": detj})
        # significant digits: a micrometre-scale scene keeps them (QA V 5)
        lines.append(f"  pose {k + 1:2d}: s15 = {s15:.8g}{sq}, t = ({t[0]: .7g}, "
                     f"{t[1]: .7g}, {t[2]: .7g}){unit}, det J66 = {detj: .3e}"
                     f"{unit + '^3' if unit else ''}, max |m-leg error| = {err:.2e}{unit}")
    result["forward_kinematics"] = {
        "method": p.method,
        "tier": tier,
        "tier_reason": getattr(octa, "tier_reason", ""),
        "count": n,
        "certified": bool(octa.certified),
        "conditioning": None if cond is None else cond.as_dict(),
        "reason": octa.reason,
        "notes": [str(w.message) for w in caught],
        **octic_fields(octa),                 # the equivalent octahedron's octic in s15
        "max_leg_error": max(q["max_leg_error"] for q in poses) if n else None,
        "max_leg_error_solver": fk.max_leg_error if n else None,
        "base_joints": [[str(x) for x in b] for b in fk.platform.base_joints],
        "platform_joints_local": [[str(x) for x in q] for q in fk.platform.platform_joints],
        "poses": poses,
        "accuracy": "max_leg_error: a rigorous bound of max_k | |b_k - p_k| - m_k | for "
                    "the float64 platform_joints p_k printed; max_leg_error_solver: of the "
                    f"{tier} tier's own pose (b_k - (R q_k + t)){bound}",
    }
    if n:
        lines.append(f"  (max |m-leg error|: a bound for the float64 joints printed; the {tier} tier's "
                     f"own poses' residual is at most {fk.max_leg_error:.1e}{unit}{bound}, JSON "
                     "max_leg_error_solver)")
    return lines


@register("forward_kinematics", mechanisms=("platform66",),
          summary="every pose of a 6-6 platform equivalent to an octahedral one (Sec. V-VI)")
class Platform66Forward:
    """``forward_kinematics`` for ``kind = "platform66"``: fields ``legs`` (m1..m6),
    ``method``, ``dps``.  The m-legs are mapped exactly to l-legs by eq. (8), the
    octahedral problem is solved, and every pose is checked on the 6-6 joints."""

    @staticmethod
    def parse(table, mechanism, units, field):
        from ...delta import delta_transform
        check_keys(table, {"type", "legs", "method", "dps"}, field)
        legs = parse_vector(require(table, "legs", field), f"{field}.legs", length=6)
        for i, m in enumerate(legs):
            check_leg_length(m, f"{field}.legs[{i}]")
        tr = delta_transform(mechanism, mechanism.offsets, field="mechanism.offsets")
        method = method_field(table, field, allowed=METHODS_AUTO)
        # (None when not written: the library's default, 30 precise, 50 for auto's fallback)
        dps = dps_field(table, method, field, uses=("precise", "auto")) \
            if "dps" in table else None
        return _Params(mechanism.offsets, legs, True, method, dps, tr, mechanism, field)

    @staticmethod
    def run(p, scene, ctx):
        import sympy as sp
        unit = "" if scene.units.length == "none" else f" {scene.units.length}"
        try:
            l_sq, l = p.transform.map_legs(p.m_legs, field="legs")
        except InfeasibleError as exc:
            if not (exc.margin is not None and exc.margin < 0):
                raise
            return _no_assembly66(p, scene, exc)
        result = {"m_legs": as_written(p.m_legs),
                  "mapped_legs": [sp.sstr(x) for x in l],
                  "mapped_legs_float": [float(x) for x in l],
                  "det_A": str(p.transform.det)}
        lines = ["m-legs -> l-legs of the equivalent octahedral manipulator (eq. (8), exact): "
                 + ", ".join(_shown(x, v, unit) for x, v in zip(result["mapped_legs"], l))]
        lines += _solve(p, result, unit, ctx)
        fk = result.pop("forward_kinematics")
        result.update(fk)
        units = result_units(scene.units)
        result["unit"] = {k: units[k] for k in ("length", "m_legs", "mapped_legs",
                                                "mapped_legs_float")}
        result["unit"].update(units["forward_kinematics"])
        _flag_floats(p.m_legs, "legs", p, result, lines)
        from .platform66_plot import plot_modes66     # each mode on the 6-6 joints
        return Outcome(result, "\n".join(lines),
                       lambda stem: plot_modes66(result, scene.units.length, stem))


def _no_assembly66(p, scene, exc):
    """The answer when the exact inverse map of eq. (8) gives a negative squared l-leg:
    no octahedral manipulator, hence no 6-6 pose, has these m-legs.  Proved exactly
    (sympy, the scene's exact values), so it is an answer (docs/design.md §4): status ok,
    0 poses, the reason; as ``kind = "octahedral"`` reports legs that cannot be
    assembled."""
    reason = _no_map_reason(exc, scene.units.length)
    result = {"m_legs": [m.text for m in p.m_legs], "method": p.method, "tier": "exact",
              "count": 0, "certified": True, "poses": [], "reason": reason, **_NO_OCTIC}
    units = result_units(scene.units)
    result["unit"] = {k: units[k] for k in ("length", "m_legs")}
    lines = [f"6-6 forward kinematics ({p.method}): 0 poses; {reason}"]
    _flag_floats(p.m_legs, "legs", p, result, lines)
    return Outcome(result, "\n".join(lines))


#: no octahedral solve ran (eq. (8) proved that no real l-leg exists): no octic to give
_NO_OCTIC = {"real_roots": None, "octic": None, "root_status": None}


def _no_map_reason(exc, length: str) -> str:
    """Why m-legs whose exact inverse map of eq. (8) has a negative squared l-leg have no
    pose (``exc``: the InfeasibleError of ``map_legs``), the squared l-leg in the
    scene's unit (``length``: ``scene.units.length``; the API, which has no unit, and a
    unitless scene say "squared length units")."""
    message = exc.message
    if length != "none":
        message = message.replace(" squared length units", f" {length}^2")
    return (f"cannot be assembled: {message}: no octahedral manipulator, hence no 6-6 "
            f"pose, has these m-legs (proved exactly by the inverse map of eq. (8))")


def _family_ok(tr) -> bool:
    """A det(A) plot over two parameters is possible (two symbols, or numeric offsets)."""
    return len(tr.free_symbols) in (0, 2)


def _family_finding(tr, result) -> list:
    """The architecturally singular lines of the two-parameter family of
    :func:`_family` (the linear factors of its det(A)) against the paper's sentence
    Delta1 + Delta2 = d12 (Rojas et al., Sec. VI, with d12 = 12): text lines, and
    ``result["family"]``."""
    import sympy as sp
    det, (s1, s2), _, _ = _family(tr)
    d12 = tr.sides[0]
    _, factors = sp.factor_list(sp.expand(det), s1, s2)
    _, box, _ = _family(tr)[1:]
    lines_, curves = [], []
    for f, _k in factors:
        deg = sp.Poly(f, s1, s2).total_degree()
        if deg == 1:
            lines_.append(sp.sstr(f))
        elif deg > 1:
            pt = _real_point(f, s1, s2, box)
            if pt is not None:
                curves.append({"factor": sp.sstr(f), "degree": int(deg),
                               "point": [round(pt[0], 6), round(pt[1], 6)]})
    paper = s1 + s2 - d12
    on = sp.div(sp.expand(det), paper, s1, s2)[1] == 0
    result["family"] = {"parameters": [str(s1), str(s2)],
                        "singular_lines": [f"{x} = 0" for x in lines_],
                        "singular_curves": curves,
                        "paper_line": f"{sp.sstr(paper)} = 0",
                        "paper_line_singular": bool(on)}
    where = ("the scene's symbols" if len(tr.free_symbols) == 2 else
             f"the family {s1} = delta1 = delta3 = delta5, {s2} = delta2 = delta4 = delta6")
    found = [f"{x} = 0" for x in lines_]
    found += [f"a curve of degree {c['degree']} (not a line) through ({s1}, {s2}) = "
              f"({c['point'][0]:.4g}, {c['point'][1]:.4g})" for c in curves]
    none = (f"no line, and no curve was found in 0 < {s1} < {box[0]:.4g}, "
            f"0 < {s2} < {box[1]:.4g} (a sign scan of its other factors)")
    return [f"over {where}: det(A) = 0 on "
            + (" and on ".join(found) if found else none)
            + f"; the paper's sentence {s1} + {s2} = {d12} (Sec. VI) is "
            + ("one of them" if on else "not (det(A) does not vanish along it)")]


def _real_point(f, s1, s2, box, rows: int = 7, cols: int = 200):
    """A point of the real curve ``f = 0`` in the offset box (0, d1) x (0, d2), found by
    a sign change along rows of constant ``s2`` and bisected (brentq); None when the
    scan finds none (a curve touching zero without a sign change is not found)."""
    import numpy as np
    import sympy as sp
    from scipy.optimize import brentq
    g = sp.lambdify((s1, s2), f, "numpy")
    x = np.linspace(0.0, box[0], cols + 2)[1:-1]
    for y in np.linspace(0.0, box[1], rows + 2)[1:-1]:
        v = np.asarray(g(x, y), dtype=float) * np.ones_like(x)
        k = np.flatnonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0)
        if k.size:
            i = int(k[0])
            return float(brentq(lambda t: float(g(t, y)), x[i], x[i + 1])), float(y)
    return None


def _family(tr):
    """(det as a function of two symbols, the symbols, ranges, marked point or None)."""
    import sympy as sp

    from ...delta import DeltaTransform
    if len(tr.free_symbols) == 2:
        s1, s2 = tr.free_symbols
        mark = None
        det = tr.det
    else:
        s1, s2 = sp.symbols("Delta1 Delta2", real=True)
        fam = DeltaTransform(tr.sides, (s1, s2, s1, s2, s1, s2))
        det = fam.det
        o = tr.offsets
        mark = (o[0], o[1]) if o[0] == o[2] == o[4] and o[1] == o[3] == o[5] else None
    d1 = float(min(tr.sides[0], tr.sides[2], tr.sides[4]))
    d2 = float(min(tr.sides[1], tr.sides[3], tr.sides[5]))
    return det, (s1, s2), (d1, d2), mark


def plot_det_family(tr, stem):
    r"""det(A) over two offset parameters with the architecturally singular locus
    (the analogue of Rojas et al., Fig. 7).

    With two symbolic offsets the plot is over those; with numeric offsets over the
    3-fold family :math:`\Delta_1 = \delta_1 = \delta_3 = \delta_5`,
    :math:`\Delta_2 = \delta_2 = \delta_4 = \delta_6`, with the scene's offsets marked
    when they belong to it.  The dotted line is the paper's sentence
    :math:`\Delta_1 + \Delta_2 = 12` (written :math:`\Delta_1 + \Delta_2 = d_{12}`).

    Returns
    -------
    list of pathlib.Path
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    import sympy as sp
    from matplotlib.colors import TwoSlopeNorm
    from pathlib import Path
    det, (s1, s2), (d1, d2), mark = _family(tr)
    f = sp.lambdify((s1, s2), det, "numpy")
    x = np.linspace(-0.25 * d1, 1.25 * d1, 301)
    y = np.linspace(-0.25 * d2, 1.25 * d2, 301)
    X, Y = np.meshgrid(x, y)
    Z = np.broadcast_to(np.asarray(f(X, Y), dtype=float), X.shape)
    fig, ax = plt.subplots(figsize=(6.4, 5.2))
    inside = (X >= 0) & (X <= d1) & (Y >= 0) & (Y <= d2)
    lim = float(np.max(np.abs(Z[inside]))) or 1.0        # colour scale of the physical box
    cs = ax.contourf(X, Y, np.clip(Z, -lim, lim), levels=np.linspace(-lim, lim, 41),
                     cmap="RdBu_r", norm=TwoSlopeNorm(0.0, -lim, lim), extend="both")
    fig.colorbar(cs, ax=ax, label="det(A) (dimensionless; clipped outside the box range)")
    ax.contour(X, Y, Z, levels=[0.0], colors="k", linewidths=2.0)
    ax.plot([], [], "k-", lw=2, label="det(A) = 0 (architecturally singular)")
    ax.plot(x, float(tr.sides[0]) - x, ":", color="0.3",
            label=f"{s1} + {s2} = {tr.sides[0]} (paper, Sec. VI)")
    ax.add_patch(plt.Rectangle((0, 0), d1, d2, fill=False, ls="--", ec="0.4",
                               label="joints on the edges (0 <= delta <= d)"))
    ax.plot([d1 / 2], [d2 / 2], "s", color="w", mec="k", ms=7,
            label="midpoints: architecturally singular Griffis-Duffy platform")
    if mark is not None:
        ax.plot([float(mark[0])], [float(mark[1])], "o", color="gold", mec="k", ms=9,
                label=f"scene offsets ({mark[0]}, {mark[1]})")
    ax.set_xlim(x[0], x[-1])
    ax.set_ylim(y[0], y[-1])
    ax.set_xlabel(f"{s1} = delta1 = delta3 = delta5 (length)")
    ax.set_ylabel(f"{s2} = delta2 = delta4 = delta6 (length)")
    ax.set_title("det(A) of the Δ-transform (cf. Rojas et al., Fig. 7)")
    ax.legend(loc="upper right", fontsize=7)
    out = Path(str(stem) + "_det_family.png")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return [out]
