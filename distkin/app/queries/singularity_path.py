"""The path part of the scene query ``singularity`` (:mod:`.singularity`): every
crossing of det J = 0 along a path of poses, the three tests of Rojas, Borràs, Thomas
(*The Octahedral Manipulator Revisited*, Sec. IV) evaluated there, and with
``method = "certified"`` arb brackets on each crossing and an arb proof that det J has no
other zero on the path (:mod:`distkin.singularity.enclosure`), or the intervals of s where
that proof did not succeed.
"""

from __future__ import annotations

import numpy as np

from ..query import Outcome
from .singularity_model import _check66, _check_legs, _first, _opt, _sampled, _tests
from .singularity_roots import classify_roots, fast_det, format_s

__all__ = ["run_path", "plot_path"]


def _roundoff(model, R, t):
    """Round-off level of the float det J at poses R (n,3,3), t (n,3): 64 n eps times
    Hadamard's bound prod_k |J_k| (rows of J with the moments over L), n = 6."""
    from ...singularity import octahedral_joints, plucker_jacobian
    J = plucker_jacobian(*octahedral_joints(model.points(R, t)))
    J[..., 3:] /= model.L
    return 64 * 6 * np.finfo(float).eps * np.prod(np.linalg.norm(J, axis=-1), axis=-1)


def _try_certify(certify_crossing, f_arb, s):
    """The :class:`~distkin.singularity.Crossing` arb proves around ``s``, or the reason
    (a string) why it could not (a root at an end of the path, a ball containing 0)."""
    from ...errors import UncertifiedError
    try:
        return certify_crossing(f_arb, s)
    except UncertifiedError as exc:
        return exc.message


def _possible_line(r):
    """The report's line on a sign change that may be round-off (not counted)."""
    sc = r["sign_change"]
    return (f"  possible crossing at s = {format_s(r['s'], r['s_error'])} (possibly round-off, "
            f"not counted): det J = {sc['det_J'][0]:.1e} at s = {sc['s'][0]:.12g} and "
            f"{sc['det_J'][1]:.1e} at s = {sc['s'][1]:.12g}, float64 rounding-error "
            f"estimates {sc['det_J_error'][0]:.1e} and {sc['det_J_error'][1]:.1e}; "
            f"{r['reason']}")


def _exclude(model, path, f_arb, roots, certs, certify_crossing, Crossing):
    """Certified zero exclusion of det J on [0, 1] outside brackets of the certified
    crossings (:func:`distkin.singularity.enclosure.exclude_zeros`, QA F2).  Brackets
    of about 1e-7 in s are used (a tighter one leaves |det J| within the balls' radius
    at its ends); their signs are certified as the crossings' own."""
    from ...singularity.enclosure import det_series, exclude_zeros, monotone_on
    brackets = []
    for s in roots:
        c = certs.get(s)
        if not isinstance(c, Crossing):
            continue                     # not certified: its neighbourhood stays undecided
        wide = _try_certify(lambda f, x: certify_crossing(f, x, start=1e-7), f_arb, s)
        brackets.append(tuple(float(x) for x in (wide if isinstance(wide, Crossing)
                                                 else c).bracket))
    gaps, at = [], 0.0
    for a, b in sorted(brackets):
        if a > at:
            gaps.append((at, a))
        at = max(at, b)
    if at < 1.0:
        gaps.append((at, 1.0))
    series = lambda ball: det_series(path, model.base_a, model.plat_a, ball)  # noqa: E731
    ex = exclude_zeros(series, gaps, min_width=1e-9, budget=2000)
    brackets = sorted(brackets)
    return {"undecided": [list(u) for u in ex.undecided], "proven": ex.proven,
            "evaluations": ex.evaluations, "brackets": [list(b) for b in brackets],
            # arb: d(det J)/ds != 0 over the bracket, so its zero is exactly one
            "simple": [monotone_on(series, a, b) for a, b in brackets],
            "max_bracket": max((b - a for a, b in brackets), default=0.0),
            "method": "arb mean-value form over intervals of s, bisected to 1e-9 within "
                      "2000 evaluations"}


def run_path(model, p, unit):
    from ...singularity import (Crossing, certify_crossing, cm_pure_condition, four_planes,
                              nearest_singularity, path_crossings, path_sign_changes,
                              signed_cm_condition)
    a, b = p.path
    path = model.pose_path(a, b)
    at = path.at

    f_det = lambda s: model.det_j(*at(s))  # noqa: E731
    _check_legs(model, *at(np.linspace(0.0, 1.0, p.samples)), "path")
    changes, grid, vals = path_sign_changes(f_det, p.samples, refine=True)
    # a sign change between two samples that are both at the round-off level of det J is
    # round-off on the singular locus, not a crossing (a path along the locus: QA F 07).
    # The level is _roundoff (or the tolerance, if smaller), not the tolerance: a
    # tolerance of the order of det J's change over one sample deleted real crossings
    # (QA F1); under "certified" a sign change arb proves is a crossing whatever the level
    on = np.abs(vals) < p.tolerance
    tiny = np.abs(vals) < np.minimum(p.tolerance, _roundoff(model, *at(grid)))
    cell = lambda s: min(int(np.searchsorted(grid, s, side="right")) - 1,  # noqa: E731
                         len(grid) - 2)                 # the samples i, i + 1 around s
    f_arb = lambda q: model.det_j_arb(*path.at_certified(q))  # noqa: E731
    # each sign change with its evidence: a value within det J's rounding-error estimate
    # of 0 makes it possibly round-off, not counted; under "certified" arb decides where
    # it can (QA: a path tangent to the locus 1e-8 off it gave two such "crossings")
    recs = classify_roots(model, path, changes, p.method,
                          (lambda s: certify_crossing(f_arb, s))      # (all round-off:
                          if p.method == "certified" and not tiny.all() else None)  # no proof)
    on_locus = [tiny[cell(c.s)] and tiny[cell(c.s) + 1] and r["status"] != "certified"
                for c, r in zip(changes, recs)]
    locus = [r["s"] for r, x in zip(recs, on_locus) if x]
    kept = [r for r, x in zip(recs, on_locus) if not x]
    possible = [r for r in kept if r["status"] == "possibly_round_off"]
    counted = [r for r in kept if r["status"] != "possibly_round_off"]
    roots = [r["s"] for r in counted]
    certs = {r["s"]: r["certificate"] for r in counted}
    notes = []
    f_cm, nan_cm = _rounding_nan(_sampled(
        lambda s: cm_pure_condition(model.points(*at(s)), relative=True),
        "the paper's CM condition", notes))
    f_k, nan_k = _rounding_nan(_sampled(
        lambda s: signed_cm_condition(model.points(*at(s)), relative=True),
        "the signed CM form", notes))
    f_fp = _sampled(lambda s: np.asarray(four_planes(model.points(*at(s)),   # root finding
                                                     length_scale=model.L, warn=False).relative),
                    "the four-planes test", notes)
    cm_roots, _, cm_vals = path_crossings(f_cm, p.samples, refine=True)
    k_roots, _, k_vals = path_crossings(f_k, p.samples, refine=True)
    fp_roots, _, fp_vals = path_crossings(f_fp, p.samples, refine=True)
    for what, bad, why in (
            ("the paper's CM condition", nan_cm, "a and b are 0 up to rounding there, and so is "
             "det Jhat = -216 (a + b)"),
            ("the signed CM form", nan_k, "both carry the factor a = V1245 V3456 V1236: a "
             "flat tetrahedron, not a singularity where det J != 0")):
        if bad:
            # the grid's samples, apart from the evaluations of the root refinement
            # (QA W 3: those were counted as samples, one s twice)
            bad = {round(x, 9) for x in bad}           # one s once
            on_grid = sorted({x for x in bad if abs(x * (p.samples - 1)
                                                    - round(x * (p.samples - 1))) < 1e-6})
            other = sorted(bad - set(on_grid))
            where = []
            if on_grid:
                where.append(f"at {len(on_grid)} of the {p.samples} samples (s = "
                             f"{', '.join(f'{x:.6g}' for x in on_grid[:5])}"
                             f"{', ...' if len(on_grid) > 5 else ''})")
            if other:
                where.append(f"at {len(other)} point(s) of the root refinement (s = "
                             f"{', '.join(f'{x:.6g}' for x in other[:3])}"
                             f"{', ...' if len(other) > 3 else ''})")
            notes.append(f"  {what} undefined {' and '.join(where)}: both products within "
                         f"their float64 rounding error estimate of 0, 0/0 cannot be ruled "
                         f"out ({why})")
    crossings, lines = [], []
    n_cert = sum(isinstance(certs.get(s), Crossing) for s in roots)
    # (not tried on a path whose every sample is at round-off: it cannot succeed there)
    excl = (_exclude(model, path, f_arb, roots, certs, certify_crossing, Crossing)
            if p.method == "certified" and not tiny.all() else None)
    complete = excl is not None and not excl["undecided"] and n_cert == len(roots)
    lines.append(f"path: {p.samples} samples, s in [0, 1]; L = {model.L:.6g}{unit}; "
                 f"{len(roots)} crossing(s) of det J = 0 found"
                 + (f", {n_cert} of them certified (arb)" if p.method == "certified" else "")
                 + (f"; {len(possible)} more sign change(s) possibly round-off, not counted"
                    if possible else ""))
    if complete:
        lines.append(f"  the count is certified complete: arb (mean-value form over s) proves "
                     f"det J != 0 on [0, 1] outside the {len(roots)} bracket(s) of the "
                     f"crossings (width <= {excl['max_bracket']:.1e} in s), each of which "
                     + ("holds exactly one zero (a certified sign change, and d(det J)/ds "
                        "!= 0 over it)" if all(excl["simple"]) else
                        "holds a certified sign change (an odd number of zeros; "
                        f"{sum(excl['simple'])} of {len(excl['simple'])} proven exactly "
                        "one by d(det J)/ds != 0)"))
    else:
        lines.append("  the count is a lower bound, not certified: sign changes on the grid, "
                     "and root pairs searched at the local minima of |det J|; two crossings "
                     "inside one sample interval that leave no such minimum are missed; a "
                     "sign change shown by a value within det J's float64 rounding-error "
                     "estimate of 0 is not counted (possibly round-off)"
                     + (", nor one arb finds of one sign on both sides"
                        if p.method == "certified" else ""))
        if excl is not None:
            shown = ", ".join(f"[{a:.9g}, {b:.9g}]" for a, b in excl["undecided"][:8])
            more = len(excl["undecided"]) - 8
            lines.append(f"  arb (mean-value form over s) proved det J != 0 on "
                         f"{excl['proven']:.6g} of the path's length 1; not decided on "
                         f"{len(excl['undecided'])} interval(s) of s: {shown}"
                         + (f" and {more} more" if more > 0 else "")
                         + ("" if n_cert == len(roots) else
                            f"; {len(roots) - n_cert} crossing(s) not certified"))
    if tiny.all():
        lines.append(f"  the whole path lies on the singular locus: |det J| <= "
                     f"{np.max(np.abs(vals)):.1e}, at the round-off level, at every sample "
                     f"(its {len(locus)} sign changes are round-off)")
    elif on.any():
        lines.append(f"  |det J| < tolerance {p.tolerance:g} at {int(on.sum())} of {p.samples} "
                     f"samples" + (f"; {len(locus)} sign changes between samples at the "
                                   "round-off level of det J are round-off on the singular "
                                   "locus, not crossings" if locus else ""))
    possible_entries = []
    for rec in counted + possible:      # the possible ones: the tests there too (QA F5b)
        maybe = rec["status"] == "possibly_round_off"
        s = rec["s"]
        R, t = at(np.array([s]))
        tests = _first(_tests(model, R, t))
        # the other tests' roots are float64 roots too: compared with det J's float64
        # root (a 30-digit polish moves s by up to its float64 error estimate)
        sf = rec["s_float"]
        near = lambda rs: min((abs(r - sf) for r in rs), default=float("inf"))  # noqa: E731
        und = tests["undefined"]
        # a test fires where it has a root of its own next to s, or where its value is at
        # round-off (a root at an end of the path leaves no sign change: QA F5)
        zero = lambda k: k not in und and tests[k] is not None and abs(tests[k]) < 1e-12  # noqa: E731
        fire = {"det_J": bool(abs(tests["det_J"]) < p.tolerance),
                "cayley_menger": bool("cm_condition_relative" not in und
                                      and (near(cm_roots) < 1e-9 or zero("cm_condition_relative"))
                                      and abs(tests["cm_condition_relative"]) < 1e-6),
                "signed_cayley_menger": bool(near(k_roots) < 1e-9 or zero("signed_cm_relative")),
                "four_planes": bool("four_planes" not in und
                                    and (near(fp_roots) < 1e-9 or zero("four_planes_relative"))
                                    and tests["four_planes_spread"] < 1e-6 * model.L)}
        entry = {"s": s, "s_error": rec["s_error"], "s_error_kind": rec["s_error_kind"],
                 "status": rec["status"], "polished": rec["polished"],
                 "sign_change": rec["sign_change"],
                 "rotation_matrix": R[0], "translation": t[0],
                 "det_J": float(tests["det_J"]), "sigma_min": float(tests["sigma_min"]),
                 "cm_condition_relative": _opt(tests["cm_condition_relative"]),
                 "signed_cm_relative": _opt(tests["signed_cm_relative"]),
                 "four_planes_spread": _opt(tests["four_planes_spread"]),
                 "four_planes_point": tests["four_planes_point"], "undefined": und,
                 # None: the test has no root on the path (was the string "inf": QA F12)
                 "root_distance": {k: (None if d == float("inf") else d) for k, d in
                                   (("cayley_menger", near(cm_roots)),
                                    ("signed_cayley_menger", near(k_roots)),
                                    ("four_planes", near(fp_roots)))},
                 "fires": fire, "all_fire": all(fire.values())}
        e = lambda k: "undefined" if entry[k] is None else f"{entry[k]:.1e}"  # noqa: E731
        head = (_possible_line(rec) + "\n    there:" if maybe else
                f"  crossing at s = {format_s(s, rec['s_error'])} "
                f"({rec['s_error_kind'].split(':')[0]}):")
        text = (f"{head} t = ({t[0, 0]:.6f}, {t[0, 1]:.6f}, {t[0, 2]:.6f}){unit}; "
                f"det J = {entry['det_J']:.1e}, CM = {e('cm_condition_relative')}, "
                f"four-planes spread = {e('four_planes_spread')}{unit}; all three fire: "
                f"{entry['all_fire']}")
        text += "".join(f"\n    {k} undefined: {why}" for k, why in und.items())
        if maybe:
            entry["reason"] = rec["reason"]
            entry["certified"] = (None if rec["certificate"] is None else
                                  {"bracket": None, "signs": None,
                                   "reason": str(rec["certificate"])})
            if rec["certificate"] is not None:
                text += f"\n    sign change not certified (arb): {rec['certificate']}"
        elif p.method == "certified":
            c = certs[s]
            if isinstance(c, Crossing):
                entry["certified"] = {"bracket": [c.bracket[0], c.bracket[1]],
                                      "signs": list(c.signs),
                                      "width": float(c.bracket[1] - c.bracket[0])}
                text += (f"\n    certified (arb): sign det J = {c.signs[0]:+d} at s = "
                         f"{float(c.bracket[0]):.15f} and {c.signs[1]:+d} at s = "
                         f"{float(c.bracket[1]):.15f}")
            else:               # a root at an end of the path, or on the locus (QA F5)
                entry["certified"] = {"bracket": None, "signs": None, "reason": c}
                text += (f"\n    sign change not certified (arb): {c} -- det J is 0 there "
                         "or within the radius of the balls of it")
        if model.platform66 is not None:
            entry["platform66"] = _check66(model, R, t)
            text += (f"\n    6-6 platform: det(A) = {entry['platform66']['det_A']}, "
                     f"|Jhat66 - A Jhat| / |Jhat66| = "
                     f"{entry['platform66']['identity_error']:.1e} (det(AJ) = det(A) det(J))")
        (possible_entries if maybe else crossings).append(entry)
        lines.append(text)
    near_det = [r["s_float"] for r in counted + possible]   # (possibly round-off: det J ~ 0)

    def elsewhere(rs):          # zeros of a test away from det J's, where det J != 0
        rs = [r for r in rs if min((abs(r - s) for s in near_det), default=1) > 1e-9
              and not on[int(np.argmin(np.abs(grid - r)))]]
        if not rs:
            return rs
        v, e = fast_det(model, at, rs)      # det J != 0 by its rounding-error estimate
        return [r for r, x, y in zip(rs, v, e) if abs(x) > y]

    spurious = elsewhere(cm_roots)
    if spurious:
        lines.append(f"  the paper's CM condition also vanishes at s = "
                     f"{', '.join(f'{r:.6f}' for r in spurious)} where det J != 0 (its factor "
                     f"a - b, see distkin.singularity)")
    k_spurious = elsewhere(k_roots)
    if k_spurious:
        lines.append(f"  the signed CM form also vanishes at s = "
                     f"{', '.join(f'{r:.6f}' for r in k_spurious)}: a flat tetrahedron "
                     f"(a = V1245 V3456 V1236 = 0), not a singularity")
    lines.extend(dict.fromkeys(notes))
    dist = []
    c, about = model.reference_point(p.rotation_about, unit)
    for s in (0.0, 1.0):
        R, t = at(np.array([s]))
        ns = nearest_singularity(lambda Rs, ts: model.det_j(Rs, ts), R[0], t[0], model.L,
                                 centre=c)
        dist.append({"s": s, "distance": ns.distance, "first_order": ns.first_order,
                     "converged": ns.converged, "is_upper_bound": True,
                     "rotation_about": {"point": p.rotation_about,
                                        "platform_frame": [float(x) for x in c],
                                        "description": about}})
        lines.append(f"  distance to the nearest singular pose at s = {s:g}: "
                     f"{ns.distance:.6g}{unit} (local search: an upper bound; rotations "
                     f"about {about}, times L = {model.L:.6g}{unit})")
    res = {"samples": p.samples, "length_scale": model.L, "crossings": crossings,
           "notes": [n.strip() for n in dict.fromkeys(notes)],     # as the text (QA W 3)
           "cm_condition_roots": cm_roots, "signed_cm_roots": k_roots,
           "four_planes_roots": fp_roots, "cm_spurious_roots": spurious,
           "nearest_singularity": dist, "min_abs_det_J": float(np.min(np.abs(vals))),
           "samples_on_locus": int(on.sum()), "on_singular_locus": bool(tiny.all()),
           "method": p.method,
           # sign changes shown by a value within det J's rounding-error estimate of 0,
           # or with one arb sign on both sides: not counted (QA: a tangent path)
           "possible_crossings": possible_entries,
           "conditions_tier": "fast (float64 along the path and at the crossings, also "
                              "under method certified: only det J is certified; undefined "
                              "where both products are within their rounding error "
                              "estimate of 0)",
           "crossing_count": {
               "found": len(roots), "is_lower_bound": not complete,
               "possibly_round_off": len(possible),
               "counted": "sign changes whose values on both sides exceed their float64 "
                          "rounding-error estimates (or their 30-digit ones, method "
                          "certified), or that arb proves; not one that arb finds of one "
                          "sign on both sides",
               "certified_complete": complete,
               "exact": bool(complete and all(excl["simple"])),
               "certified_crossings": n_cert if p.method == "certified" else None,
               "search": "sign changes on the sample grid, and root pairs at the local "
                         "minima of |det J| (QA F2)",
               "zero_exclusion": excl}}
    data = {"s": grid, "det_J": vals, "cm": cm_vals, "signed_cm": k_vals, "four_planes": fp_vals,
            "roots": roots, "spurious": spurious,
            # the s where the text calls a CM form undefined (0/0 within rounding)
            "undefined": {"cm": sorted({round(x, 9) for x in nan_cm}),
                          "signed_cm": sorted({round(x, 9) for x in nan_k})}}
    return Outcome(res, "\n".join(lines), lambda stem: plot_path(data, stem))


def plot_path(data, stem):
    """det J, the paper's CM condition, its signed form and the four-planes determinant
    along a path, with the crossings of det J = 0 marked.  det J and the four-planes
    determinant are divided by their own largest magnitude on the path (the divisor is
    in the legend: "scaled" says by what); the CM conditions are relative already
    (in [-1, 1]).  A sample where the report calls a CM form undefined (both products
    within their rounding error of 0, ``data["undefined"]``) has no value to draw: it is
    marked on the zero line and named in the legend.

    Returns
    -------
    list of pathlib.Path
    """
    import matplotlib
    matplotlib.use("Agg")
    from pathlib import Path

    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7.6, 4.8))
    s = data["s"]
    peak = lambda v: float(np.nanmax(np.abs(v), initial=0.0))  # noqa: E731
    norm = lambda v: np.asarray(v) / max(peak(v), 1e-300)  # noqa: E731
    ax.axhline(0.0, color="0.6", lw=0.8)
    drawn = lambda k: k in data and np.isfinite(np.asarray(data[k], dtype=float)).any()  # noqa: E731
    ax.plot(s, norm(data["det_J"]), lw=2.2,
            label=f"det J (eq. 5) / its max |value| on the path, {peak(data['det_J']):.3g}")
    if drawn("four_planes"):
        ax.plot(s, norm(data["four_planes"]), "--", lw=1.6, label=f"four-planes "
                f"determinant / its max |value|, {peak(data['four_planes']):.3g}")
    if drawn("cm"):
        ax.plot(s, data["cm"], "-.", lw=1.4, label="paper's CM condition (relative)")
    if drawn("signed_cm"):
        ax.plot(s, data["signed_cm"], ":", lw=1.8, label="signed CM condition (relative)")
    for i, (a, b) in enumerate(data.get("unreachable", ())):
        ax.axvspan(a, b, color="0.85", label="not reachable: no det J" if i == 0 else None)
    for key, what, mark in (("cm", "paper's CM condition", "X"),
                            ("signed_cm", "signed CM condition", "P")):
        at = data.get("undefined", {}).get(key) or []
        if at:
            shown = ", ".join(f"{x:.6g}" for x in at[:4]) + (", ..." if len(at) > 4 else "")
            ax.plot(at, np.zeros(len(at)), mark, ms=9, mfc="none", mec="k", ls="none",
                    label=f"{what} undefined (0/0 within rounding) at s = {shown}")
    for i, r in enumerate(data["roots"]):
        ax.axvline(r, color="crimson", lw=1.0, label="det J = 0 (crossing)" if i == 0 else None)
    for i, r in enumerate(data["spurious"]):
        ax.axvline(r, color="orange", lw=1.0, ls="--",
                   label="CM = 0 but det J != 0" if i == 0 else None)
    ax.set_xlabel("path parameter s")
    ax.set_ylabel("value (dimensionless): det J, four planes\n÷ their max |value| on the "
                  "path; CM relative")
    ax.set_title("Singularity tests along the path")
    ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    out = Path(str(stem) + "_path.png")
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return [out]


def _rounding_nan(f):
    """``f`` (a fast relative CM condition over s) with its CancellationWarnings
    silenced (the report says it instead), and the list of s where it is NaN because
    both products are within their rounding error of 0 (QA V 2)."""
    import warnings
    from ...geometry.cm_float import CancellationWarning
    seen = []

    def g(s):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", CancellationWarning)
            v = np.asarray(f(s), dtype=float)
        bad = np.atleast_1d(np.isnan(v))
        seen.extend(float(x) for x in np.atleast_1d(s)[bad])
        return v
    return g, seen
