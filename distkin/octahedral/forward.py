r"""Forward kinematics of the octahedral manipulator: every real assembly mode.

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III:
the real roots of the octic in :math:`s_{15}` (eq. (3) squared twice, see
:mod:`distkin.octahedral.octic`) are the assembly modes; each gives two mirror poses by
the trilateration sequence :math:`P_5 \leftarrow (P_1,P_2,P_3)`,
:math:`P_4 \leftarrow (P_1,P_2,P_5)`, :math:`P_6 \leftarrow (P_1,P_4,P_5)`, checked
against leg 5.

Tiers
-----
``fast``
    float64: generated octic kernel, a projective sign scan of the octic
    (:mod:`.signscan`, single and batched; the problems it doubts take the
    companion-matrix eigenvalues of :mod:`.single`), Newton polish on eq. (3),
    trilateration and poses in compiled scalar code (numba); batched over many leg
    sets by
    :func:`forward_kinematics_batched`.  The first call on a machine compiles (about
    15-20 s, kept in numba's cache); see BENCHMARKS.md for the cost per solve.  Legs
    reproduced to ~1e-12 relative on well-conditioned problems; every pose states its
    residual, and every solve (single and batched) proves its assembly roots or says
    it cannot (:mod:`.descartes`, :mod:`.conditioning`:
    :class:`~distkin.errors.ConditioningWarning`, ``BatchResult.trusted``), unless the
    caller skips the proof (the bare fast tier: ``warn=False`` single, ``prove=False``
    batched; then nothing is vouched for, and the result says so).
``precise``
    mpmath at ``dps`` digits: exact octic (when the data are rational) rounded once,
    ``mpmath.polyroots``, Newton polish on eq. (3) at ``dps`` (:mod:`.precise`).
``certified``
    exact ``fmpq`` octic and FLINT's certified root isolation: the real-root count is
    proved, spurious roots are rejected by certified signs, and root enclosures are
    refined until every pose point is enclosed to ``tol`` (relative to the size of the
    mechanism) (:mod:`.certified`).  Raises :class:`~distkin.errors.UncertifiedError`
    rather than guess.
``auto``
    the fast tier, escalated to ``certified`` (or ``precise`` for data that cannot be
    made exact) when the fast tier cannot prove its assembly roots or a leg is
    reproduced worse than 1e-9 relative (:mod:`.auto`); the result's ``tier`` and
    ``tier_reason`` say which tier answered and why.

Every tier solves the problem with its lengths divided by a power of two and scales the
answer back, exactly (:mod:`.scaling`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..argcheck import relative_tol
from ..errors import ConditioningWarning, DegenerateGeometryError, InputError
from ..errors import warn as _warn
from ..exact import METHODS_AUTO, check_method, default_dps
from .problem import exact_problem, float_problem, float_single
from .scaling import in_units, rescale_result

from .result import (_VERDICTS, AssemblyResult, BatchResult, Pose, RootInfo,
                     _buffer_result, _fast_result, _single_result)

__all__ = ["Pose", "RootInfo", "AssemblyResult", "BatchResult", "forward_kinematics",
           "forward_kinematics_batched", "proved_single"]

def _tier_args(method: str, dps, tol):
    """``dps`` and ``tol`` checked at the entry (``auto``'s escalations too): dps in
    5..1233, and at least :data:`.precise.MIN_DPS` where the precise tier may run; both
    refused where they would be ignored (dps: ``fast``, ``certified``; tol: ``fast``);
    tol relative (:func:`~distkin.argcheck.relative_tol`, bounded by those digits)."""
    if dps is not None:
        if method not in ("precise", "auto"):     # it would be ignored (QA T 9)
            raise InputError(f"expected 'dps' only with method 'precise' or 'auto' (the "
                             f"mpmath digits), got method {method!r}", field="dps")
        from .precise import check_precise_dps
        dps = check_precise_dps(dps)
    if tol is not None and method == "fast":     # it would be ignored, as dps (and the CLI)
        raise InputError(f"expected 'tol' only with method 'precise', 'certified' or 'auto' "
                         f"(the exact tiers' tolerance), got method {method!r}", field="tol")
    return dps, None if tol is None else relative_tol(tol, "tol",
                                                      digits=_tol_digits(method, dps))


def _tol_digits(method: str, dps: int | None) -> int | None:
    """The digits that bound ``tol`` below (:func:`~distkin.argcheck.relative_tol`): the
    precise tier's dps, and for ``auto`` the digits of its precise fallback (data that
    cannot be made exact); None for the tiers without that bound."""
    if method == "precise":
        return default_dps(dps)
    if method == "auto":
        from .auto import PRECISE_DPS
        return PRECISE_DPS if dps is None else dps
    return None


def forward_kinematics(base, platform, legs, *, method: str = "fast", dps: int | None = None,
                       tol: float | None = None, warn: bool = True) -> AssemblyResult:
    r"""Every real assembly mode of an octahedral manipulator.

    Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited* (ICRA 2012), Sec. III
    and eq. (3); labels of docs/design.md §3.

    Parameters
    ----------
    base : (3, 3) array_like
        P1, P2, P3 in base coordinates (rows).  Numbers, numeric strings
        (``"sqrt(108)"``), Fractions or :class:`~distkin.exact.Exact`.
    platform : (3, 3) array_like
        P4, P5, P6 in the platform frame (rows); any non-degenerate triangle.
    legs : (6,) array_like
        Leg lengths :math:`l_1..l_6` of P1P4, P2P4, P2P5, P3P5, P3P6, P1P6 (same
        length unit as the points).
    method : {"fast", "precise", "certified", "auto"}
        ``"auto"``: the fast tier, kept when it proves its assembly roots
        (:mod:`.descartes`) and every leg is reproduced to 1e-9 relative; otherwise
        escalated to ``certified`` (or ``precise`` when the data cannot be made
        exact).  ``.tier`` and ``.tier_reason`` of the result say
        which tier answered and why (:mod:`.auto`).
    dps : int, optional
        Decimal digits of the ``precise`` tier (default 30; at least
        :data:`.precise.MIN_DPS` = 15: fewer digits than float64's would make its
        residual test, 10^(8 - dps) relative, meaningless); ``auto``: of its precise
        fallback (default 50).  Refused with ``fast`` and ``certified``, which would
        ignore it.
    tol : float, optional
        ``certified``: relative radius (to the size of the mechanism) the pose
        enclosures are refined to (default 1e-15).  ``precise``: the relative residual
        accepted for a root (default :math:`10^{8-dps}`).  A number 0 < tol < 1, and
        for ``precise`` at least :math:`10^{-dps}` (``auto``: of its precise fallback,
        dps or 50 digits); :func:`~distkin.argcheck.relative_tol`.  Refused with
        ``fast``, which would ignore it.
    warn : bool
        ``fast``: prove the assembly roots (:mod:`.descartes`, a few µs) into
        ``.conditioning`` and emit a :class:`~distkin.errors.ConditioningWarning` when
        the proof fails (default True).  ``warn=False`` skips the proof
        (``.conditioning`` is None): the bare fast tier.

    Returns
    -------
    AssemblyResult
        A sequence of :class:`Pose` (two mirror poses per assembly root), empty when
        the legs admit no assembly (``.reason`` says why), with the octic and every
        real root of it (``.roots``).

    Raises
    ------
    InputError
        Malformed data; ``certified`` with irrational squared lengths; lengths whose
        squares do not fit float64 (:mod:`.scaling`).
    DegenerateGeometryError
        A collinear base or platform triangle, or an octic that vanishes identically.
        ``fast`` also refuses a triangle thinner than 16 area^2 / (sum of squared
        sides)^2 = 1e-12, which float64 cannot resolve; ``precise``, ``certified`` and
        ``auto`` (which hands it to them) solve it, refusing only a collinear one.
    UncertifiedError
        ``certified`` could not decide something (never a wrong answer).

    Examples
    --------
    The example of Rojas et al., Sec. VI (Griffis-Duffy legs): six real roots, twelve
    poses.

    >>> base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
    >>> plat = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
    >>> res = forward_kinematics(base, plat, ["19.8", 18, 18, 17, "14.9", "17.8"])
    >>> len(res), [round(r.value, 1) for r in res.roots]
    (12, [269.2, 328.7, 359.5, 463.6, 497.9, 513.0])
    """
    check_method(method, allowed=METHODS_AUTO)
    dps, tol = _tier_args(method, dps, tol)
    if method in ("fast", "auto"):
        from .batched import scan_single
        try:
            B, Q, L, k, rounded = float_single(base, platform, legs)
        except DegenerateGeometryError as exc:
            if method == "fast":
                if exc.hint is None:
                    exc.hint = ("method='auto' or 'certified' solve a thin triangle "
                                "exactly, refusing only a collinear one")
                    exc.args = (exc.one_line(),)
                raise
            from .auto import escalate_thin
            return escalate_thin(exc, base, platform, legs, dps=dps, tol=tol)
        out = scan_single(B, Q, L)
        if method == "fast" and not warn:                   # the bare fast tier
            if out is None:                                 # doubted: the careful way
                from .single import solve_fast_single
                return _single_result(solve_fast_single(B, Q, L), k=k)
            return _buffer_result(*out, k=k)
        res, cond = proved_single(B, Q, L, k, None, out, rounded)
        if method == "auto":
            from .auto import escalate
            return escalate(res, base, platform, legs, dps=dps, tol=tol)
        if not cond.trusted:
            _warn(f"fast tier: the real-root count is not proved ({cond.reason}); "
                  "use method='auto' or 'certified'", ConditioningWarning)
        return res
    problem = exact_problem(base, platform, legs)
    with in_units(problem.exponent):
        if method == "precise":
            from .precise import solve_precise
            res = replace(solve_precise(problem, default_dps(dps), tol), tier="precise")
        else:
            from .certified import solve_certified
            res = replace(solve_certified(problem, 1e-15 if tol is None else float(tol)),
                          tier="certified")
    return replace(rescale_result(res, problem.exponent),
                   accuracy=res.accuracy + problem.float_note())


def forward_kinematics_batched(base, platform, legs, *, method: str = "fast",
                               warn: bool = True, prove: bool = True,
                               dps: int | None = None,
                               tol: float | None = None) -> BatchResult:
    """The fast tier (or ``auto``) for N leg sets at once.

    Parameters
    ----------
    base : (3, 3) or (N, 3, 3); platform : (3, 3) or (N, 3, 3); legs : (N, 6) or (6,)
        At most one batch axis; an array without one is shared by the N problems.
    method : {"fast", "auto"}
        ``"fast"``: every problem is checked by the proof of :mod:`.descartes`;
        ``.trusted`` flags, per problem, the answers it cannot vouch for.  ``"auto"``:
        those problems, and those whose poses reproduce a leg worse than 1e-9 relative,
        are solved again by the certified tier (``precise`` for data that cannot be
        made exact), as :func:`forward_kinematics` does (:mod:`.auto`); ``.tier`` says
        which tier answered each problem.
    warn : bool
        ``"fast"``: emit one :class:`~distkin.errors.ConditioningWarning` naming how
        many problems are not proved (default True).
    prove : bool
        ``"fast"``: run the proof (default True).  ``prove=False`` skips it, as
        ``forward_kinematics(..., warn=False)`` does for one problem: the bare batched
        fast tier, which vouches for nothing: ``.trusted`` is False and ``.verdict``
        :data:`.descartes.NOT_CHECKED` for every problem, ``raw`` has no proved radii,
        ``.result(i).conditioning`` is None, and no warning is emitted (the caller
        chose).  ``method="auto"`` needs the proof: ``prove=False`` is refused there.
    dps, tol : as for :func:`forward_kinematics` (``auto``'s escalations)

    Returns
    -------
    BatchResult
        Arrays padded to 8 roots / 16 poses per problem; ``.result(i)`` gives the
        :class:`AssemblyResult` of problem ``i``.
    """
    check_method(method, allowed=("fast", "auto"))
    dps, tol = _tier_args(method, dps, tol)
    if not prove and method != "fast":
        raise InputError("expected prove=True with method='auto' (it escalates what the "
                         "proof cannot vouch for), got prove=False", field="prove")
    from .descartes import ETA_FLOAT, NOT_CHECKED, eta_rounded, vouch_many
    from .batched import recover_flagged, solve_fast
    B, Q, L, s2, l2, k, rounded, thin = float_problem(base, platform, legs, flat="mask")
    raw = solve_fast(B, Q, L, s2, l2)
    raw["sides2"], raw["legs2"], raw["exponent"] = s2, l2, k    # the kernel's inputs
    n = len(k)
    if prove:
        eta = np.full(n, ETA_FLOAT)
        for i in np.flatnonzero(rounded):
            eta[i] = eta_rounded(B[i], Q[i], L[i])
        verdict = np.empty(n, np.int64)
        radii = np.empty((n, 8))
        vouch_many(raw["data"], s2, l2, eta, raw["lo"], raw["hi"], raw["roots"],
                   raw["status"], verdict, radii)
        # what the proof refused, solved again from the proof's own isolation
        raw["recovered"] = (recover_flagged(B, Q, L, s2, l2, raw, eta, verdict, radii)
                            if (verdict != 0).any() else np.empty(0, np.int64))
        raw["verdict"], raw["radii"], raw["eta"] = verdict, radii, eta
    else:                                       # the bare fast tier: nothing vouched
        verdict = np.full(n, NOT_CHECKED)
    if thin.any():          # placeholders of thin triangles: no answer, flagged (QA N 1)
        from .descartes import THIN_TRIANGLE
        from .result import blank_row
        for i in np.flatnonzero(thin):
            blank_row(raw, i)
            if prove:
                radii[i] = np.nan
        verdict[thin] = THIN_TRIANGLE
    _scale_back(raw, k)
    trusted = verdict == 0
    out = BatchResult(raw["count"], raw["s15"], raw["points"], raw["rotation"],
                      raw["translation"], raw["leg_error"], raw["leg_error_rel"],
                      raw["valid"], raw, trusted, verdict, np.full(n, "fast", dtype=object))
    if method == "auto":
        from .auto import escalate_batch
        return escalate_batch(out, base, platform, legs, dps=dps, tol=tol)
    if warn and prove and not trusted.all():
        bad = np.flatnonzero(~trusted)
        _warn(f"fast tier: the real-root count of {bad.size} of {n} problems is not "
              f"proved (first: problem {bad[0]}, {_VERDICTS()[verdict[bad[0]]]}); "
              "see .trusted, or use method='auto'", ConditioningWarning)
    return out


def proved_single(B, Q, L, k, eta, out, rounded=True):
    """The fast tier's answer to one problem with its proof: ``(AssemblyResult,
    Conditioning)``.  ``B, Q, L, k``: :func:`.problem.float_single`; ``eta``: the
    relative error bound of the squared lengths the proof covers
    (None: :func:`.conditioning.eta_of` of the problem, ``rounded`` saying whether its
    lengths were rounded to float64; or wider: the 6-6 tier adds the rounding of its leg
    map); ``out``: :func:`.batched.scan_single`'s answer, or None when the scan doubts
    the problem (then the careful way, :func:`.single.solve_fast_single`).  A count the
    proof refuses for a reason the batched way can settle is solved again that way
    (:func:`_recovered_single`)."""
    from .conditioning import assess, assess_buffer, eta_of
    if eta is None:
        eta = eta_of(B, Q, L, rounded)
    if out is None:
        from .single import solve_fast_single
        raw = solve_fast_single(B, Q, L)
        cond = assess(raw.sides2, raw.legs2, raw.data, raw.lo, raw.hi, raw.roots, eta)
        res = _single_result(raw, conditioning=cond, k=k)
        s2, l2, d, lo, hi = raw.sides2, raw.legs2, raw.data, raw.lo, raw.hi
    else:
        lo, hi, nr, m, buf = out
        cond = assess_buffer(buf, nr, lo, hi, eta)
        res = _buffer_result(lo, hi, nr, m, buf, conditioning=cond, k=k)
        s2, l2, d = buf[:6], buf[6:12], buf[12:51]
    if not cond.trusted and cond.reason in _RECOVERABLE_REASONS():
        again = _recovered_single(B, Q, L, s2, l2, d, lo, hi, eta, k)
        if again is not None:
            res, cond = again, again.conditioning
    return res, cond


def _RECOVERABLE_REASONS():
    """The reasons of the proof's verdicts after which a problem is solved again from
    the proof's own isolation of its roots (:data:`.batched._RECOVERABLE`)."""
    from .batched import _RECOVERABLE
    return {_VERDICTS()[v] for v in _RECOVERABLE}


def _recovered_single(B, Q, L, s2, l2, d, lo, hi, eta, k):
    """A single problem whose fast answer the proof refused as miscounted, solved again
    the batched tier's way (:func:`.batched.solve_fast` on one row, the proof, then
    :func:`.batched.recover_flagged` where the proof refuses that too): its
    :class:`AssemblyResult`, proved, or None when no answer is proved (then the refused
    answer stands, with its warning).  The same squared lengths ``s2``, ``l2`` and
    ``eta`` as the single solve, its kernel output ``d`` and triangle bounds ``lo``,
    ``hi``; ``k``: the normalising exponent (:mod:`.scaling`).  The proof's isolation runs first, on the
    single solve's own data (a few µs): where it cannot isolate the roots (clusters
    float64 cannot split, most refused problems of the hard sets) nothing more is
    tried."""
    from .batched import recover_flagged, solve_fast
    from .descartes import recover, vouch_many
    if recover(d, np.asarray(s2, dtype=float), np.asarray(l2, dtype=float), eta, lo, hi,
               np.empty(8))[0] < 0:
        return None
    one = [np.ascontiguousarray(np.asarray(a, dtype=float)[None]) for a in (B, Q, L, s2, l2)]
    raw = solve_fast(*one)
    etas, verdict, radii = np.full(1, eta), np.empty(1, np.int64), np.empty((1, 8))
    vouch_many(raw["data"], one[3], one[4], etas, raw["lo"], raw["hi"], raw["roots"],
               raw["status"], verdict, radii)
    if verdict[0] != 0 and not recover_flagged(*one, raw, etas, verdict, radii).size:
        return None
    raw["verdict"], raw["radii"], raw["eta"] = verdict, radii, etas
    raw["sides2"], raw["legs2"], raw["exponent"] = one[3], one[4], np.array([k])
    _scale_back(raw, np.array([k]))
    return _fast_result(raw, 0)


def _scale_back(raw, k):
    """The arrays of :func:`.batched.solve_fast` for the lengths divided by ``2**k``
    (N,), in place, scaled back (:mod:`.scaling`)."""
    if not k.any():
        raw["octic_exponent"] = np.zeros(len(k), np.int64)
        return
    k1, k2 = k[:, None], 2 * k[:, None]
    for name in ("roots", "step", "s15", "radii"):
        if name in raw:                         # (no radii without the proof)
            raw[name] = np.ldexp(raw[name], k2)
    for name in ("lo", "hi"):
        raw[name] = np.ldexp(raw[name], 2 * k)
    raw["leg_error"] = np.ldexp(raw["leg_error"], k1)
    raw["points"] = np.ldexp(raw["points"], k[:, None, None, None])
    raw["translation"] = np.ldexp(raw["translation"], k[:, None, None])
    deg = 12 - np.arange(8, -1, -1)
    with np.errstate(over="ignore", under="ignore"):
        coef = np.ldexp(raw["coef"], k2 * deg[None, :])
    bad = ~np.isfinite(coef).all(axis=1) | ((raw["coef"] != 0) & (np.abs(coef) < 2.0 ** -1022)
                                           ).any(axis=1)
    raw["coef"] = np.where(bad[:, None], raw["coef"], coef)
    raw["octic_exponent"] = np.where(bad, k, 0)
