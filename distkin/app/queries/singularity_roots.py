"""The roots of det J along a path, for the path part of the query ``singularity``
(:mod:`.singularity_path`): which sign changes of the float64 det J it can vouch for,
how far each root may lie from the exact det J's, and, under ``method = "certified"``,
each root polished at 30 digits (mpmath, on the path's exact ends) and arb's evidence.

A sign change is only as sure as the two values that show it
(:class:`~distkin.singularity.SignChange`): where one of them is within its float64
rounding-error estimate (``jacobian_det(..., with_error=True)``) of 0 it is *possibly
round-off* (QA: a path tangent to the Griffis-Duffy locus 1e-8 off it gave two
"crossings" 6e-9 apart where mpmath finds det J >= 1e-8 all along), reported as such and
not counted; under ``certified`` arb decides where it can: a proved sign change is a
certified crossing, one sign proved at both ends of every bracket tried keeps the root
out of the count whatever float64 says.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["classify_roots", "format_s", "fast_det", "PRECISE_DPS"]

#: digits of the precise polish of the roots (method "certified")
PRECISE_DPS = 30

#: least arb precision (bits) of the certificates of the roots
_CERT_BITS = 128

#: step (in s) of the central difference of the float64 det J at a root
_STEP = 1e-5


def fast_det(model, at, s):
    """Float64 det J and its rounding-error estimate at the parameters ``s``."""
    from ...singularity import jacobian_det, octahedral_joints
    R, t = at(np.asarray(s, dtype=float))
    v, e = jacobian_det(*octahedral_joints(model.points(R, t)), length_scale=model.L,
                        warn=False, with_error=True)
    return np.asarray(v, dtype=float), np.asarray(e, dtype=float)


def _fast_s_error(model, at, s):
    """(rounding-error estimate of det J at s) / |d det J/ds| (central difference of
    step 1e-5, one-sided at an end of [0, 1]); inf where the slope is 0."""
    lo, hi = max(0.0, s - _STEP), min(1.0, s + _STEP)
    v, e = fast_det(model, at, [s, lo, hi])
    slope = abs(v[2] - v[1]) / (hi - lo)
    return float(e[0] / slope) if slope > 0 else math.inf


def _precise_f(model, path):
    """s (exact or mpf) -> (det J, its error estimate) at 30 digits on the exact path."""
    def F(s):
        return model.det_j_precise(*path.at_precise(s, PRECISE_DPS), PRECISE_DPS)
    return F


def _polish(F, s, ds, lo, hi):
    """The root of the 30-digit det J within [max(lo, s - w), min(hi, s + w)], w =
    4 ds (at least 1e-12), by the Illinois method, and its error estimate (rounding
    error estimate over |slope|); None where the 30-digit values at the bracket's ends
    are within their estimates of 0 or of one sign (no polish: the float root stays)."""
    import mpmath
    w = max(4 * ds, 1e-12) if math.isfinite(ds) else hi - lo
    a, b = max(lo, s - w), min(hi, s + w)
    if not a < b:
        return None
    with mpmath.workdps(PRECISE_DPS):
        a, b = mpmath.mpf(a), mpmath.mpf(b)
        (fa, ea), (fb, eb) = F(a), F(b)
        if not (abs(fa) > ea and abs(fb) > eb and mpmath.sign(fa) != mpmath.sign(fb)):
            return None
        side = 0
        for _ in range(200):
            c = (a * fb - b * fa) / (fb - fa)
            fc, ec = F(c)
            if abs(fc) <= ec or b - a < mpmath.mpf(10) ** (-PRECISE_DPS + 5):
                break
            if mpmath.sign(fc) == mpmath.sign(fa):
                a, fa = c, fc
                if side == -1:
                    fb /= 2
                side = -1
            else:
                b, fb = c, fc
                if side == 1:
                    fa /= 2
                side = 1
        h = mpmath.mpf(10) ** -12
        slope = abs(F(c + h)[0] - F(c - h)[0]) / (2 * h)
        err = ec / slope if slope > 0 else mpmath.inf
        x = float(c)
        return x, float(max(err, abs(mpmath.mpf(x) - c)))


def classify_roots(model, path, changes, method, certify):
    """Each sign change of the float64 det J along ``path`` as a dict: ``s``, ``status``
    ("certified", "crossing": by the rounding-error estimate, "possibly_round_off",
    "zero_sample": a sample where the float64 det J is exactly 0), ``s_error`` and
    ``s_error_kind``, ``sign_change`` (the two points and their float64 values and
    error estimates), ``certificate`` (a Crossing, the reason it failed, or None),
    ``reason`` (why possibly round-off) and ``polished`` (30 digits)."""
    import flint

    from ...errors import UncertifiedError
    from ...exact_roots import working_precision
    out = []
    F = _precise_f(model, path) if certify is not None else None
    for c in changes:
        rec = {"s": c.s, "s_float": c.s, "polished": False, "certificate": None,
               "reason": None}
        if c.lo == c.hi:                 # a sample where the float det J is exactly 0
            v, e = np.array([0.0]), fast_det(model, path.at, [c.s])[1]
            rec.update(status="zero_sample", sign_change={"s": [c.lo, c.hi],
                       "det_J": [0.0, 0.0], "det_J_error": [float(e[0])] * 2})
        else:
            v, e = fast_det(model, path.at, [c.lo, c.hi])
            rec["sign_change"] = {"s": [c.lo, c.hi], "det_J": [float(x) for x in v],
                                  "det_J_error": [float(x) for x in e]}
            resolved = bool(np.all(np.abs(v) > e))
            rec["status"] = "crossing" if resolved else "possibly_round_off"
            if not resolved:
                rec["reason"] = ("det J is within its float64 rounding-error estimate of 0 "
                                 "at the point(s) that show the sign change")
        ds = _fast_s_error(model, path.at, c.s)
        rec.update(s_error=ds, s_error_kind="estimate: float64 rounding-error estimate of "
                   "det J at s over |d det J/ds|")
        if F is not None and c.lo != c.hi:
            pol = _polish(F, c.s, ds, c.lo, c.hi)
            if pol is not None:           # the 30-digit det J changes sign, resolved
                rec.update(s=pol[0], s_error=pol[1], polished=True, status="crossing",
                           reason=None, s_error_kind=f"estimate: {PRECISE_DPS}-digit "
                           "rounding-error estimate of det J at s over |d det J/ds|")
        if certify is not None:
            try:
                # the path's poses at 128 bits at least: at flint's default 53 the balls
                # of det J stay undecided to 1e-5 from a root (a bracket 1e7 times wider)
                with working_precision(max(flint.ctx.prec, _CERT_BITS)):
                    cert = certify(rec["s"])
            except UncertifiedError as exc:
                rec["certificate"] = exc.message
                if getattr(exc, "same_sign", None):
                    a, b, sg = exc.same_sign[-1]
                    rec["status"] = "possibly_round_off"
                    rec["reason"] = (f"arb proves det J {'>' if sg > 0 else '<'} 0 at both "
                                     f"s = {float(a):.12g} and {float(b):.12g}: no sign change "
                                     "there")
            else:
                rec["certificate"] = cert
                half = max(float(rec["s"] - cert.bracket[0]), float(cert.bracket[1] - rec["s"]))
                rec.update(status="certified", reason=None, s_error=half,
                           s_error_kind="certified: the root lies in the arb bracket")
        out.append(rec)
    return out


def format_s(s: float, err: float) -> str:
    """``s`` with the decimals its error ``err`` supports (at least 2), and the error."""
    if not math.isfinite(err):
        return f"{s:.6f} (error not estimated: d det J/ds = 0 there)"
    digits = min(17, max(2, int(math.floor(-math.log10(max(err, 1e-17)))) + 1))
    return f"{s:.{digits}f} ± {err:.1e}"
