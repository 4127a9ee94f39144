"""Scene query ``forward_kinematics`` for ``kind = "octahedral"``: every assembly mode.

Scene fields (docs/design.md §4)::

    [mechanism]
    kind = "octahedral"
    base = [[0,0,0], [6,"sqrt(108)",0], [12,0,0]]        # P1 P2 P3, base frame
    platform = [[0,0,0], [6,0,0], [3,"sqrt(27)",0]]      # P4 P5 P6, platform frame

    [[query]]
    type = "forward_kinematics"
    legs = ["19.8", "18", "18", "17", "14.9", "17.8"]   # P1P4 P2P4 P2P5 P3P5 P3P6 P1P6
    method = "certified"      # fast | precise | certified | auto
    dps = 30                  # precise (and auto's escalations) only
    tol = 1e-15               # certified: pose enclosure radius / size; precise: root
                              #   residual; auto: its escalations.  0 < tol < 1 (precise:
                              #   at least 1e-dps); refused with "fast", which has none

JSON result: ``real_roots {count, certified, values, radii}`` (every real root of the
octic in s15; each root's ``radius_kind`` in ``root_status`` says what its radius is:
"certified" or "proved", the exact root lies within it of the value; "estimate", the
fast or precise tier's last Newton steps, not an error bound:
:class:`~distkin.octahedral.result.RootInfo`), ``octic {coefficients}`` (highest degree
first; exact strings where exact), ``poses [{s15, rotation, translation, points {P4, P5, P6}, max_leg_error}]``
(plus ``side``, ``max_leg_error_relative`` and ``max_leg_error_solver``), ``count`` (the
number of poses; ``real_roots.count`` counts roots), ``assembly_modes`` (the poses of
side +1), and ``root_status``, ``reason``,
``accuracy``, ``inputs_from_float`` (the legs and points written as bare floats, taken
as their exact binary values; also said in the text), and ``unit`` (the units of those
fields).  Lengths are in the scene's own length unit (the geometry is solved as
written, as ``delta_transform``, ``singularity`` and the 6-6 forward kinematics do: one
unit for every query of a scene; the solve is scale-invariant), unitless for
``length = "none"``; s15 is a squared length (mm^2 in a ``length = "mm"`` scene).  The plot (``--plots``) is the
analogue of Rojas et al., Fig. 8: one panel per assembly mode (side +1; the mirror
images are not drawn), and the octic over the feasible interval of s15 with its real
roots.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, replace
from fractions import Fraction

from ...argcheck import check_keys, dps_field, exact_vector, method_field, require, tol_field
from ...errors import ConditioningWarning, DistkinError, InputError
from ...exact import METHODS_AUTO, default_dps
from ..query import Outcome, register
from ..report import float_inputs, float_inputs_line

__all__ = ["check_leg_length", "OctahedralForwardQuery", "result_units", "octic_fields", "pose_points",
           "roots_lines", "count_verdict", "floats_leg_error",
           "floats_segment_error"]


@dataclass(frozen=True)
class _Params:
    legs: tuple
    method: str
    dps: int | None
    tol: float | None
    field: str = "query"         # "query[2]": the names in ``inputs_from_float``


def check_leg_length(v, fld: str) -> None:
    """Refuse a scene's leg length (:class:`~distkin.exact.Exact`) that is not positive,
    or that is positive but rounds to 0 in float64 (``"1e-400"``: it was refused as "not
    positive", QA), or lies beyond float64, naming ``fld``."""
    try:
        x = float(v)
    except InputError as exc:                 # beyond float64
        raise exc.with_field(fld) from None
    if x > 0:
        return
    positive = v.value > 0 if isinstance(v.value, Fraction) else \
        bool(getattr(v.value, "is_positive", False))
    if positive:
        raise InputError(f"expected a leg length that float64 can hold (above about "
                         f"4.9e-324), got {v.text}, which rounds to 0", field=fld,
                         hint="express the lengths in a smaller unit")
    raise InputError(f"expected a positive leg length, got {v.text}", field=fld)


@register("forward_kinematics", mechanisms=("octahedral",),
          summary="every assembly mode of an octahedral manipulator (octic in s15)")
class OctahedralForwardQuery:
    @staticmethod
    def parse(table, mechanism, units, field):
        check_keys(table, {"type", "legs", "method", "dps", "tol"}, field)
        legs = exact_vector(require(table, "legs", field), f"{field}.legs", 6)
        for i, v in enumerate(legs):
            check_leg_length(v, f"{field}.legs[{i}]")
        method = method_field(table, field, allowed=METHODS_AUTO)
        # (None when not written: the library's default, 30 precise, 50 for auto's fallback)
        dps = dps_field(table, method, field, uses=("precise", "auto")) \
            if "dps" in table else None
        from ...octahedral.auto import PRECISE_DPS         # auto's precise fallback
        tol = tol_field(table, method, field, dps=dps,
                        precise_dps=dps if "dps" in table else PRECISE_DPS)
        return _Params(legs, method, dps, tol, field)

    @staticmethod
    def run(p, scene, ctx):
        from ...octahedral.forward import forward_kinematics
        if p.method in ("fast", "auto"):
            from ...octahedral.warmup import compile_fast_tier
            compile_fast_tier(notice=ctx.notice)  # first solve here: 2 processes
        mech = scene.mechanism                # the scene's unit, as written (module doc)
        base, plat, legs = mech.base, mech.platform, list(p.legs)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ConditioningWarning)
            try:
                res = forward_kinematics(base, plat, legs, method=p.method, dps=p.dps,
                                         tol=p.tol)
            except DistkinError as exc:
                if exc.field and exc.field.startswith(("base", "platform")):
                    exc.field = f"mechanism.{exc.field}"      # where the scene has them
                    exc.args = (exc.one_line(),)
                raise
        if caught:
            res = replace(res, notes=res.notes + tuple(str(w.message) for w in caught))
        unit = "" if scene.units.length == "none" else scene.units.length
        named = ([(f"{p.field}.legs[{i}]", v) for i, v in enumerate(p.legs)]
                 + [(f"mechanism.{k}[{i}][{j}]", v)
                    for k, rows in (("base", mech.base), ("platform", mech.platform))
                    for i, row in enumerate(rows) for j, v in enumerate(row)])
        result = _result(res, base, legs)
        result["unit"] = result_units(scene.units)
        result["inputs_from_float"] = float_inputs(named)
        text = _text(res, unit, p, result["poses"])
        note = float_inputs_line(named)
        return Outcome(result, text + ("\n" + note if note else ""),
                       _plotter(res, base, plat, unit))


def result_units(units) -> dict:
    """The ``unit`` block of an octahedral forward-kinematics result: lengths in the
    scene's own length unit (module docstring), or "none" for a unitless scene
    (``length = "none"``); s15 is a squared length.  A pose's ``max_leg_error`` is a
    bound for its float64 ``points`` as printed (:func:`floats_leg_error`);
    ``max_leg_error_solver`` is the tier's own figure (certified: a bound for the exact
    pose; precise: of its mpmath points; fast: float64 arithmetic on the points)."""
    m = "none" if units.length == "none" else units.length
    m2 = "none" if m == "none" else f"{m}^2"
    return {"s15": m2, "real_roots": f"{m2} (values and radii)",
            "translation": m, "points": m, "rotation": "none (rotation matrix)",
            "max_leg_error": m, "max_leg_error_relative": "none (over the leg length)",
            "max_leg_error_solver": m,
            "side": "none (+1: P5 on the side of the base plane that (P2-P1) x (P3-P1) "
                    "points to; -1: the mirror image in the base plane)",
            "octic": f"coefficients of a polynomial in s15 ({m2}), highest degree first"}


def floats_leg_error(base, points, legs) -> tuple:
    """Rigorous upper bounds of ``max_k | |P_i P_j| - l_k |`` (absolute, and relative to
    ``l_k``) over the six legs (:data:`~distkin.octahedral.problem.LEG_PAIRS`), with the
    platform points the float64 numbers ``points`` as printed (their exact binary
    values), and the base and legs the scene's exact values; arb balls at 256 bits.

    docs/design.md §3: an accuracy statement is of the float number it stands beside.
    The certified tier's own ``max_leg_error`` bounds its exact pose (6.5e-23 for the
    Griffis-Duffy example), which the printed floats, rounded, miss by about 1e-15
    (QA 23 D4).

    Parameters
    ----------
    base : (3, 3) Exact or numbers, P1 P2 P3 (scene unit)
    points : (3, 3) float, P4 P5 P6 in the base frame (scene unit)
    legs : (6,) Exact or numbers, l_1 .. l_6 (scene unit)
    """
    from ...octahedral.banana import LEG_PAIRS       # base P_i (i <= 3) to platform P_j
    return floats_segment_error([base[i - 1] for i, _ in LEG_PAIRS],
                                [points[j - 4] for _, j in LEG_PAIRS], legs)


def floats_segment_error(ends_a, ends_b, legs) -> tuple:
    """Rigorous upper bounds of ``max_k | |A_k B_k| - l_k |`` (absolute, and relative to
    ``l_k``), with the rows of ``ends_b`` the float64 numbers as printed (their exact
    binary values) or exact, ``ends_a`` and ``legs`` the scene's exact values or floats;
    arb balls at 256 bits (:func:`distkin.octahedral.certified.segment_error_bounds`).
    The octahedron's six legs (:func:`floats_leg_error`) and a 6-6 platform's joints
    (the ``platform66`` and ``delta_transform`` poses)."""
    import flint
    from ...exact import to_tier
    from ...exact_roots import working_precision
    from ...octahedral.certified import segment_error_bounds

    def ball(v):
        return to_tier(float(v) if isinstance(v, float) else v, "certified")
    with working_precision(256):
        A = [[ball(v) for v in row] for row in ends_a]
        B = [[to_tier(float(v), "certified") for v in row] for row in ends_b]
        return segment_error_bounds(A, B, [flint.arb(ball(v)) for v in legs])


def _result(res, base, legs):
    poses = []
    for q in res.poses:
        err, rel = floats_leg_error(base, q.points, legs)
        poses.append({
            "s15": q.s15, "side": q.side,
            "rotation": q.rotation, "translation": q.translation,
            "points": pose_points(q),
            "max_leg_error": err,
            "max_leg_error_relative": rel,
            "max_leg_error_solver": q.max_leg_error,
        })
    return {
        "count": len(res.poses),
        "method": res.method,
        "certified": res.certified,
        "accuracy": res.accuracy,
        **octic_fields(res),
        "assembly_modes": _modes(res)[0],
        "octic_degree": res.degree,
        "octic_note": list(res.notes),
        "poses": poses,
        "reason": res.reason,
        "tier": res.tier,
        "tier_reason": res.tier_reason,
        "conditioning": None if res.conditioning is None else res.conditioning.as_dict(),
    }


def octic_fields(res) -> dict:
    """The octic's part of a forward-kinematics result (docs/design.md §4), from an
    octahedral result ``res``: ``real_roots {count, certified, values, radii}``,
    ``root_status`` (what each root became, and what its radius is) and ``octic
    {coefficients}`` (highest degree first; Fractions, exact strings in the JSON, where
    exact).  The 6-6 forward kinematics gives those of its equivalent octahedron."""
    return {
        "real_roots": {"count": res.real_root_count, "certified": res.certified,
                       "values": [r.value for r in res.roots],
                       "radii": [r.radius for r in res.roots]},
        "root_status": [{"s15": r.value, "status": r.status, "reason": r.reason,
                         "multiplicity": r.multiplicity, "radius_kind": r.radius_kind}
                        for r in res.roots],
        "octic": {"coefficients": list(res.octic)},
    }


def roots_lines(res, unit: str, what: str = "the octic") -> list:
    """The report's lines on the real roots of the octic of ``res`` (as ``real_roots``
    and ``root_status`` say them); ``unit``: the scene's length unit ("" unitless)."""
    cert = "certified" if res.certified else (
        "the assembly roots proved; the count outside the feasible interval float64's" if res.conditioning is not None
        and res.conditioning.trusted else "not certified")
    lines = [f"real roots of {what}: {res.real_root_count} ({cert})"]
    for r in res.roots:
        rad = (f" ± {r.radius:.1e} ({r.radius_kind})" if r.radius_kind != "estimate" else
               f" (last Newton step {r.radius:.0e}, not an error bound)")
        mult = f", multiplicity {r.multiplicity}" if r.multiplicity != 1 else ""
        lines.append(f"  s15 = {r.value:.10g}{rad}{_u(unit, 2)}  -> {r.reason}{mult}")
    return lines


def pose_points(q) -> dict:
    """``points {P4, P5, P6}`` of an octahedral pose ``q`` (base frame)."""
    return {"P4": q.points[0], "P5": q.points[1], "P6": q.points[2]}


def count_verdict(octa, cond) -> str:
    """What proves the octahedral solver's count of poses, in the words of the
    octahedral query's report; ``cond``: the fast tier's proof
    when the fast tier answered, else None."""
    if octa.certified:
        return "certified"
    if cond is not None and cond.trusted:
        return ("proved by the fast tier's rounding-error bounds, not by the certified "
                "tier (JSON: conditioning.trusted true, certified false; the assembly "
                "roots proved, the count outside the feasible interval float64's)")
    if cond is not None:
        return f"not proved ({cond.reason})"
    return f"not certified (the {octa.tier or octa.method} tier)"


def _modes(res):
    """Assembly modes (poses up to the mirror image in the base plane: side +1) and how
    many of them have a mirror image (side -1; a flat mode is its own).  A multiple
    root can carry several modes (the equilateral octahedron's triple root: three)."""
    sides = [q.side for q in res.poses]
    return sides.count(1), sides.count(-1)


def _u(unit, power=1):
    if not unit:
        return ""
    return f" {unit}" if power == 1 else f" {unit}^{power}"


def _text(res, unit, p, poses):
    lines = [f"octahedral forward kinematics ({res.method}"
             + (f", {default_dps(p.dps)} digits" if res.method == "precise" else "") + ")"]
    if res.method == "auto":
        lines.append(f"answered by the {res.tier} tier: {res.tier_reason}")
    elif res.conditioning is not None and not res.conditioning.trusted:
        lines.append(f"WARNING: {res.conditioning.reason}; the count may be wrong "
                     "(use method = \"auto\" or \"certified\")")
    head = f"octic in s15 (degree {res.degree}" + (
        ", exact rational coefficients)" if res.octic_exact else ")")
    lines.append(head + ("; " + res.notes[0] if res.notes else ""))
    lines += roots_lines(res, unit)
    if not res.poses:
        lines.append(res.reason)
    else:
        modes, mirrored = _modes(res)
        head = (f"{len(res.poses)} pose{'s' if len(res.poses) != 1 else ''} ({modes} "
                f"assembly mode{'s' if modes != 1 else ''}")
        if mirrored == modes:
            head += " x 2 mirror images in the base plane):"
        elif mirrored == 0:
            head += " in the base plane, each its own mirror image):"
        else:
            head += (f"; {mirrored} with a mirror image in the base plane, "
                     f"{modes - mirrored} in it):")
        lines.append(head)
        for q, out in zip(res.poses, poses):
            t = ", ".join(f"{v:.6g}" for v in q.translation)
            lines.append(f"  s15 = {q.s15:.8g}{_u(unit, 2)}, side {q.side:+d}: translation "
                         f"({t}){_u(unit)}, max leg error {out['max_leg_error']:.2e}"
                         f"{_u(unit)} ({out['max_leg_error_relative']:.1e} relative)")
        if res.method in ("certified", "precise") or res.tier in ("certified", "precise"):
            worst = max(q.max_leg_error for q in res.poses)
            exact = "exact" if res.certified else f"{res.tier or res.method} tier's"
            lines.append(f"  (max leg error: a bound for the float64 points printed; the "
                         f"{exact} poses' own is at most {worst:.1e}{_u(unit)}, JSON "
                         "max_leg_error_solver)")
        lines.append("  side +1: P5 on the side of the base plane that (P2-P1) x (P3-P1) "
                     "points to; side -1: its mirror image in the base plane")
    lines.append(f"accuracy: {res.accuracy}")
    return "\n".join(lines)


def _plotter(res, base, plat, unit):
    def plot(stem):
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import numpy as np
        B = np.array([[float(v) for v in r] for r in base])
        # per assembly root, the mirror image above the base plane (larger mean z)
        best = {}
        for q in res.poses:
            if q.s15 not in best or q.points[:, 2].mean() > best[q.s15].points[:, 2].mean():
                best[q.s15] = q
        modes = [best[s] for s in sorted(best)]
        paths = []
        n = max(len(modes), 1)
        cols = min(3, n)
        rows = (n + cols - 1) // cols
        fig = plt.figure(figsize=(4.2 * cols, 4.0 * rows))
        for k, q in enumerate(modes):
            ax = fig.add_subplot(rows, cols, k + 1, projection="3d")
            P = q.points
            tri = np.vstack([B, B[:1]])
            ax.plot(tri[:, 0], tri[:, 1], tri[:, 2], "k-", lw=2)
            pt = np.vstack([P, P[:1]])
            ax.plot(pt[:, 0], pt[:, 1], pt[:, 2], "b-", lw=2)
            for (i, j) in ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6)):
                a, b = B[i - 1], P[j - 4]
                ax.plot([a[0], b[0]], [a[1], b[1]], [a[2], b[2]], "r-", lw=1)
            ax.set_title(f"s15 = {q.s15:.4g}{_u(unit, 2)}", fontsize=9)
            allp = np.vstack([B, P])
            ax.set_box_aspect(np.ptp(allp, axis=0) + 1e-9 * np.ptp(allp))
            ax.set_xlabel(f"x{_u(unit)}")
            ax.set_ylabel(f"y{_u(unit)}")
            ax.set_zlabel(f"z{_u(unit)}")
        if not modes:
            ax = fig.add_subplot(1, 1, 1)
            ax.text(0.5, 0.5, res.reason or "no assembly mode", ha="center", wrap=True)
            ax.axis("off")
        fig.suptitle("Assembly modes (Rojas et al. Fig. 8 analogue; mirror images omitted)")
        fig.tight_layout()
        path = f"{stem}_modes.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        paths.append(path)
        if res.roots or res.octic:
            fig, ax = plt.subplots(figsize=(6.4, 3.6))
            coef = np.array([float(c) for c in res.octic])
            xs = [r.value for r in res.roots]
            lo = min(xs) if xs else 0.0
            hi = max(xs) if xs else 1.0
            pad = 0.15 * (hi - lo if hi > lo else max(abs(hi), 1.0))
            grid = np.linspace(lo - pad, hi + pad, 800)
            vals = np.polyval(coef / np.max(np.abs(coef)), grid)
            ax.plot(grid, np.sign(vals) * np.log10(1 + np.abs(vals) / np.max(np.abs(vals))
                                                   * 1e12), "k-", lw=1)
            for r in res.roots:
                ax.axvline(r.value, color="g" if r.status == "assembly" else "r", lw=0.8)
            ax.axhline(0, color="0.6", lw=0.5)
            ax.set_xlabel(f"s15{_u(unit, 2)}")
            ax.set_ylabel("sign(O) log10(1 + 1e12 |O|/max|O|)")
            ax.set_title("The octic: real roots (green: assembly, red: spurious)")
            fig.tight_layout()
            path = f"{stem}_octic.png"
            fig.savefig(path, dpi=110)
            plt.close(fig)
            paths.append(path)
        return paths
    return plot
