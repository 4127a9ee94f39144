r"""Poses, paths of poses, their singularity crossings and the nearest singularity of the
octahedral manipulator (Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited*,
ICRA 2012, Sec. IV), on the conditions of :mod:`.conditions`.

Number types as there: ``fast`` float64, ``precise`` mpmath, ``certified`` flint (a sign
that a ball cannot decide raises :class:`~distkin.errors.UncertifiedError`)."""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from ..argcheck import positive_int, positive_number
from ..errors import InputError, UncertifiedError
from .conditions import certified_sign
from .tiers import _checked, _precision, _prepare, _to_flint

__all__ = [
    "rotation_from_vector",
    "pose_points",
    "PosePath",
    "Crossing",
    "SignChange",
    "path_crossings",
    "path_sign_changes",
    "certify_crossing",
    "NearestSingularity",
    "nearest_singularity",
]


# --------------------------------------------------------------------------- poses

def rotation_from_vector(w, method: str | None = None, *, dps: int | None = None):
    r"""Rotation matrix of a rotation vector (axis times angle, rad), Rodrigues:
    :math:`R = I + \frac{\sin\theta}{\theta}K + \frac{1-\cos\theta}{\theta^2}K^2`.

    Parameters
    ----------
    w : array (..., 3) float (batched), or 3 mpf / arb / fmpq values
    method : tier of the result (None: that of ``w``)
    dps : int, optional
        Decimal digits of the precise tier (5..1233, default 30), set locally (mpmath's
        global ``mp.dps`` is not used); only with ``method="precise"``.

    Returns
    -------
    array (..., 3, 3)

    Raises
    ------
    InputError
        ``w`` not of shape (..., 3) (fast) or (3,) (precise, certified), booleans, NaN
        or inf; in the fast and precise tiers an angle :math:`|w|` above
        :math:`10^{-10}\,2^{p}` rad (:data:`MAX_ANGLE_ERROR`; p the precision in bits,
        53 in float64: about 9e5 rad): :math:`|w|` is rounded to about
        :math:`2^{-p}|w|` rad, so the rotation of a larger angle is not determined (QA:
        1e300 gave NaN).  Reduce the angle modulo :math:`2\pi` first, or use the
        certified tier (its balls widen honestly).
    """
    with _precision(dps, method, w):
        return _rotation(w, method)


def _rotation(w, method):
    """:func:`rotation_from_vector` at the working precision."""
    arr, kind = _prepare(w, method, "w")
    if kind == "fast":
        if arr.ndim < 1 or arr.shape[-1] != 3:
            raise InputError(f"expected rotation vectors of shape (..., 3), got {arr.shape}",
                             field="w")
        with np.errstate(over="ignore"):
            th = np.linalg.norm(arr, axis=-1)
        if th.size and not th.max() <= _FAST_MAX_ANGLE:   # one comparison on the hot path
            _check_angle(np.max(np.hypot(np.hypot(arr[..., 0], arr[..., 1]), arr[..., 2])), 53)
        safe = np.where(th > 0, th, 1.0)
        k = arr / safe[..., None]
        K = np.zeros(arr.shape[:-1] + (3, 3))
        K[..., 0, 1], K[..., 0, 2] = -k[..., 2], k[..., 1]
        K[..., 1, 0], K[..., 1, 2] = k[..., 2], -k[..., 0]
        K[..., 2, 0], K[..., 2, 1] = -k[..., 1], k[..., 0]
        s, c = np.sin(th)[..., None, None], np.cos(th)[..., None, None]
        return np.eye(3) + s * K + (1 - c) * (K @ K)
    if arr.shape != (3,):
        raise InputError(f"expected one rotation vector (3,) in the {kind} tier, got "
                         f"{arr.shape}", field="w")
    if kind == "precise":
        import mpmath
        th2 = sum(x * x for x in arr)
        if th2 == 0:
            return np.array([[mpmath.mpf(int(i == j)) for j in range(3)] for i in range(3)],
                            dtype=object)
        th = mpmath.sqrt(th2)
        _check_angle(th, mpmath.mp.prec)
        s, c = mpmath.sin(th) / th, (1 - mpmath.cos(th)) / th2
    else:
        import flint
        ws = [flint.arb(x) for x in arr]
        th2 = ws[0] * ws[0] + ws[1] * ws[1] + ws[2] * ws[2]
        if all(x == 0 for x in ws):
            return np.array([[flint.arb(int(i == j)) for j in range(3)] for i in range(3)],
                            dtype=object)
        th = th2.sqrt()
        s, c = th.sin() / th, (1 - th.cos()) / th2
        arr = np.array(ws, dtype=object)
    x, y, z = arr
    K = np.array([[0 * x, -z, y], [z, 0 * x, -x], [-y, x, 0 * x]], dtype=object)
    R = K.dot(K) * c + K * s
    for i in range(3):
        R[i, i] = R[i, i] + 1
    return R


#: the largest error of a rotation angle (rad) the fast and precise tiers accept: the
#: angle |w| is rounded to 2^-prec |w|, so |w| <= MAX_ANGLE_ERROR 2^prec
MAX_ANGLE_ERROR = 1e-10


_FAST_MAX_ANGLE = MAX_ANGLE_ERROR * 2.0 ** 53


def _check_angle(theta, prec: int) -> None:
    limit = MAX_ANGLE_ERROR * 2.0 ** prec
    if theta > limit:
        raise InputError(f"expected a rotation angle |w| <= {limit:.3g} rad at {prec} bits "
                         f"(|w| is rounded to about 2^-{prec} |w| rad), got {float(theta):.6g} "
                         "rad", field="w",
                         hint="reduce the angle modulo 2 pi exactly, or use method='certified'")


def pose_points(points, rotation, translation):
    """World coordinates ``R @ q + t`` of points ``q`` given in the platform frame.

    Parameters
    ----------
    points : array (n, 3)
    rotation : array (..., 3, 3)
    translation : array (..., 3)

    Returns
    -------
    array (..., n, 3)

    Raises
    ------
    InputError
        Booleans, NaN or inf in any argument, ``points`` not (n, 3), ``rotation`` not
        (..., 3, 3), ``translation`` not (..., 3), or batch shapes that do not
        broadcast (each names its field).
    """
    q, R, t = (_checked(v, f) for v, f in ((points, "points"), (rotation, "rotation"),
                                           (translation, "translation")))
    for bad, arr, field, want in ((q.ndim != 2 or q.shape[-1] != 3, q, "points", "(n, 3)"),
                                  (R.shape[-2:] != (3, 3), R, "rotation", "(..., 3, 3)"),
                                  (t.shape[-1:] != (3,), t, "translation", "(..., 3)")):
        if bad:
            raise InputError(f"expected shape {want}, got {arr.shape}", field=field)
    try:
        np.broadcast_shapes(R.shape[:-2], t.shape[:-1])
    except ValueError:
        raise InputError(f"expected rotations and translations of matching batch shapes, got "
                         f"{R.shape} and {t.shape}", field="translation") from None
    if R.dtype == object or q.dtype == object:
        R = np.asarray(R, dtype=object)
        q = np.asarray(q, dtype=object)
        return np.array([R.dot(qi) + t for qi in q], dtype=object)
    return np.einsum("...ij,nj->...ni", R, q) + t[..., None, :]


# ------------------------------------------------------- paths, crossings and distance

@dataclass(frozen=True)
class PosePath:
    r"""A straight path in pose space: :math:`t(s) = t_0 + s(t_1-t_0)`,
    :math:`R(s) = \operatorname{Rot}(w_0 + s(w_1-w_0))`, :math:`s\in[0,1]`.

    Attributes
    ----------
    t0, t1 : tuple of 3 exact values (Fraction or sympy constants), length units
    w0, w1 : tuple of 3 exact values, rotation vectors (rad, or deg when ``deg``)
    deg : bool
        Rotation vectors in degrees (converted with an exact pi in the certified tier).
    """

    t0: tuple
    w0: tuple
    t1: tuple
    w1: tuple
    deg: bool = False

    def at(self, s):
        """Float poses at ``s`` (array (n,)): R (n, 3, 3), t (n, 3)."""
        s = np.asarray(s, dtype=float)[..., None]
        f = lambda v: np.array([float(x) for x in v])  # noqa: E731
        t = f(self.t0) + s * (f(self.t1) - f(self.t0))
        w = f(self.w0) + s * (f(self.w1) - f(self.w0))
        if self.deg:
            w = w * (np.pi / 180)
        return rotation_from_vector(w), t

    def at_certified(self, s):
        """arb poses at an exact rational ``s`` (fmpq): R (3, 3), t (3,) as arb balls."""
        import flint
        q = lambda v: [_arb(x) for x in v]  # noqa: E731
        t0, t1, w0, w1 = q(self.t0), q(self.t1), q(self.w0), q(self.w1)
        s = flint.arb(s)
        t = np.array([a + s * (b - a) for a, b in zip(t0, t1)], dtype=object)
        w = np.array([a + s * (b - a) for a, b in zip(w0, w1)], dtype=object)
        if self.deg:
            w = w * (flint.arb.pi() / 180)
        return rotation_from_vector(w, method="certified"), t

    def at_precise(self, s, dps: int = 30):
        """mpmath poses at ``s`` (an exact value, or mpf/float taken as it is): R (3, 3),
        t (3,) as mpf object arrays, computed at ``dps`` digits from the path's exact
        ends (not from their float64 roundings, as :meth:`at`)."""
        import mpmath

        from ..exact import to_tier
        with mpmath.workdps(dps):
            q = lambda v: [to_tier(x, "precise") for x in v]  # noqa: E731
            t0, t1, w0, w1 = q(self.t0), q(self.t1), q(self.w0), q(self.w1)
            s = to_tier(s, "precise")
            t = np.array([a + s * (b - a) for a, b in zip(t0, t1)], dtype=object)
            w = np.array([a + s * (b - a) for a, b in zip(w0, w1)], dtype=object)
            if self.deg:
                w = w * (mpmath.pi / 180)
            return rotation_from_vector(w, method="precise", dps=dps), t


def _arb(x):
    """A certified arb enclosure of an exact value (Fraction, int, fmpq, sympy constant)."""
    import flint

    from ..exact import to_tier
    if hasattr(x, "value"):
        x = x.value
    if isinstance(x, float):
        x = Fraction(x)
    v = to_tier(x, "certified")
    return v if type(v).__name__ == "arb" else flint.arb(v)


@dataclass(frozen=True)
class Crossing:
    """A singularity crossed by a path.

    Attributes
    ----------
    s : float
        Path parameter of the root of det J.  Brent's method finds it to 1e-14 in s on
        the *float64* det J (:func:`path_crossings`), not on the exact one: the root of
        the exact det J can lie about (rounding error of det J at s) / |d det J/ds|
        away (QA: 4e-9 and more near a grazing path; the ``singularity`` query reports
        that estimate, ``s_error``).  With a certificate the root lies in ``bracket``.
    bracket : (Fraction, Fraction) or None
        Rational parameters on both sides at which the sign of det J was certified
        (arb), when certification was asked for.
    signs : (int, int) or None
        The certified signs of det J at ``bracket``.
    """

    s: float
    bracket: tuple | None = None
    signs: tuple | None = None


def path_crossings(f, samples: int = 200, *, xtol: float = 1e-14, refine: bool = False):
    """Roots of a scalar function along s in [0, 1]: sign changes on a uniform grid of
    ``samples`` points, refined by Brent's method (:func:`path_sign_changes` says
    which two points of opposite signs each root comes from).

    A pair of roots inside one sample interval leaves no sign change on the grid.  With
    ``refine``, every interior sample where |f| has a strict local minimum without a
    sign change on either side is searched (bounded Brent minimisation of sign(f) f over
    its two neighbouring intervals); a minimum of the opposite sign adds the two roots
    around it (QA F2).  Pairs of roots that leave no local minimum of |f| at a sample
    can still be missed: the count is a lower bound.

    Parameters
    ----------
    f : callable (array of s) -> array of values (batched float)
    samples : int
        At least 2 (both ends of [0, 1]); another value or type is an
        :class:`~distkin.errors.InputError` naming ``samples``.
    xtol : float
        Brent's absolute tolerance (in s, > 0) on each root *of the float function f*;
        a root of the exact function f approximates can lie farther, by about f's
        rounding error over |f'| there, and a sign change within f's rounding error
        may not exist at all.
    refine : bool
        Search the local minima of |f| for root pairs between samples.

    Returns
    -------
    roots : list of float (sorted)
    grid, values : arrays (samples,)
        The sampled function (for plots).
    """
    changes, grid, vals = path_sign_changes(f, samples, xtol=xtol, refine=refine)
    return [c.s for c in changes], grid, vals


@dataclass(frozen=True)
class SignChange:
    """A root of :func:`path_sign_changes` and the evidence for it.

    Attributes
    ----------
    s : float
        The root (Brent's method on the float function, to ``xtol``).
    lo, hi : float
        The two points around ``s`` at which the function was seen with opposite signs
        (``lo == hi == s`` where a sample is exactly 0).
    f_lo, f_hi : float
        The function's values there: the sign change is only as sure as these are
        (a value within its rounding error of 0 may have the wrong sign).
    """

    s: float
    lo: float
    hi: float
    f_lo: float
    f_hi: float


def path_sign_changes(f, samples: int = 200, *, xtol: float = 1e-14, refine: bool = False):
    """:func:`path_crossings` with the evidence of each root: ``(changes, grid,
    values)``, ``changes`` a sorted list of :class:`SignChange`."""
    samples = positive_int(samples, "samples", minimum=2)
    xtol = positive_number(xtol, "xtol")
    grid = np.linspace(0.0, 1.0, samples)
    vals = np.asarray(f(grid), dtype=float)
    roots = []
    scalar = lambda x: float(np.asarray(f(np.array([x])))[0])  # noqa: E731
    # consecutive *finite* samples: a sign change across a NaN sample (a relative
    # condition undefined there) counts too (QA W 3: whether a sample fell on the NaN
    # decided whether the root was found)
    finite = np.flatnonzero(np.isfinite(vals))
    for i, j in zip(finite[:-1], finite[1:]):
        a, b = vals[i], vals[j]
        if a == 0.0:
            x = float(grid[i])
            roots.append(SignChange(x, x, x, 0.0, 0.0))
        elif a * b < 0:
            roots.append(SignChange(_brent(scalar, grid[i], grid[j], xtol), float(grid[i]),
                                    float(grid[j]), float(a), float(b)))
    if finite.size and vals[finite[-1]] == 0.0:
        x = float(grid[finite[-1]])
        roots.append(SignChange(x, x, x, 0.0, 0.0))
    if refine:
        roots.extend(_root_pairs(scalar, grid, vals, xtol, evidence=True))
        roots.sort(key=lambda c: c.s)
    return roots, grid, vals


def _brent(scalar, lo, hi, xtol):
    """A root in [lo, hi] (a sign change) by Brent's method; where ``scalar`` is NaN
    inside (a relative condition undefined, 0/0: QA V 2) by bisection, a NaN midpoint
    being the place of the sign change (the condition's numerator is 0 there)."""
    from scipy.optimize import brentq
    try:
        return float(brentq(scalar, lo, hi, xtol=xtol, rtol=1e-15))
    except ValueError:
        pass
    lo, hi = float(lo), float(hi)
    fl = scalar(lo)
    while hi - lo > xtol:
        mid = 0.5 * (lo + hi)
        fm = scalar(mid)
        if fm != fm or fm == 0.0:        # NaN (0/0: the numerator's zero) or a root
            return mid
        if (fm < 0) == (fl < 0):
            lo, fl = mid, fm
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _root_pairs(scalar, grid, vals, xtol, evidence=False):
    """Root pairs between samples at the strict local minima of |f| (see
    :func:`path_crossings`); with ``evidence`` as :class:`SignChange` (the minimum of the
    opposite sign is one side of both)."""
    from scipy.optimize import minimize_scalar
    a, m, b = np.abs(vals[:-2]), np.abs(vals[1:-1]), np.abs(vals[2:])
    same = (vals[:-2] * vals[1:-1] > 0) & (vals[1:-1] * vals[2:] > 0)
    out = []
    for i in np.flatnonzero(same & (m < a) & (m <= b) & np.isfinite(m)) + 1:
        sg = float(np.sign(vals[i]))
        lo, hi = float(grid[i - 1]), float(grid[i + 1])
        res = minimize_scalar(lambda x: sg * scalar(x), bounds=(lo, hi), method="bounded",
                              options={"xatol": 1e-13})
        if not (res.fun < 0.0):
            continue
        x, fx = float(res.x), sg * float(res.fun)
        r1, r2 = _brent(scalar, lo, x, xtol), _brent(scalar, x, hi, xtol)
        if evidence:
            out += [SignChange(r1, lo, x, float(vals[i - 1]), fx),
                    SignChange(r2, x, hi, fx, float(vals[i + 1]))]
        else:
            out += [r1, r2]
    return out


def certify_crossing(f_arb, s: float, *, lo: float = 0.0, hi: float = 1.0,
                     start: float = 1e-12, limit: float = 1e-3) -> Crossing:
    r"""Certify a sign change of det J around ``s`` with arb balls.

    Evaluates ``f_arb`` (exact rational s -> arb) at :math:`s \mp \epsilon` for
    :math:`\epsilon` = ``start``, 10 ``start``, ... up to ``limit`` (clipped to
    [``lo``, ``hi``]); the first pair of balls that both exclude 0 and have opposite
    signs proves (intermediate value theorem) a zero of det J in the bracket, and a
    sign change: a crossing, never a touch.  Where ``f_arb`` is exactly 0 (an exact ball
    0 or fmpq 0) at ``s`` itself (a float ``s`` tried as its exact binary value) or at
    an end of a bracket, that point is a proved singular pose but not a crossing (a
    touch has the same sign on both sides): the search goes on with the next bracket,
    and the error, if none proves a sign change, says where det J is exactly 0 (review:
    it returned such a point as a Crossing with signs (0, 0), counted as a certified
    sign change).

    Raises
    ------
    InputError
        ``s`` not a finite number in [``lo``, ``hi``]; ``start`` or ``limit`` not
        positive and finite; ``lo`` >= ``hi``.
    UncertifiedError
        No such pair up to ``limit`` (the signs found are named).  Its attribute
        ``same_sign`` lists the brackets ``(a, b, sign)`` at whose ends arb proved one
        and the same non-zero sign (an even number of zeros inside: no evidence of a
        crossing at ``s``); empty when every bracket left a ball containing 0.
    """
    lo, hi = _finite_number(lo, "lo"), _finite_number(hi, "hi")
    if not lo < hi:
        raise InputError(f"expected lo < hi, got lo = {lo!r} and hi = {hi!r}", field="hi")
    s = _finite_number(s, "s")
    if not lo <= s <= hi:
        raise InputError(f"expected s in [lo, hi] = [{lo!r}, {hi!r}], got {s!r}", field="s")
    start, limit = positive_number(start, "start"), positive_number(limit, "limit")
    sign = lambda x: certified_sign(f_arb(_to_flint(x)))  # noqa: E731
    zero = Fraction(s)                     # a float s is tried as its exact binary value
    exact_zeros = []                       # points where det J is exactly 0 (said below)
    try:
        if sign(zero) == 0:
            exact_zeros.append(zero)
    except UncertifiedError:
        pass
    eps = start
    last = None
    same = []                              # brackets with one certified sign at both ends
    while eps <= limit:
        a = Fraction(max(lo, s - eps)).limit_denominator(10 ** 18)
        b = Fraction(min(hi, s + eps)).limit_denominator(10 ** 18)
        try:
            sa, sb = sign(a), sign(b)
        except UncertifiedError as exc:
            last = UncertifiedError(f"could not certify the sign of det J at s = "
                                    f"{float(a):.15g} or {float(b):.15g} (around the crossing "
                                    f"at s = {s:.15g}, up to {limit:g} from it): {exc.message}")
            eps *= 10
            continue
        if sa * sb < 0:
            return Crossing(s, (a, b), (sa, sb))
        exact_zeros += [z for z, sz in ((a, sa), (b, sb)) if sz == 0 and z not in exact_zeros]
        if sa == sb != 0:
            same.append((a, b, sa))
        last = UncertifiedError(f"expected opposite signs of det J around s = {s:.15g}, got "
                                f"{sa:+d} at s = {float(a):.15g} and {sb:+d} at s = "
                                f"{float(b):.15g}")
        eps *= 10
    zeros = ("; det J is exactly 0 at s = " + ", ".join(f"{float(z):.15g}" for z in exact_zeros)
             + " (a proved singular pose, but no sign change was proved: a crossing or a "
             "touch)") if exact_zeros else ""
    if last is not None:
        err = UncertifiedError(last.message + zeros)
    else:
        err = UncertifiedError(f"could not certify the crossing at s = {s:.15g}: no bracket "
                               f"fits in [{lo!r}, {hi!r}] from start = {start:g} up to "
                               f"limit = {limit:g}{zeros}")
    err.same_sign = same
    raise err


def _finite_number(value, field: str) -> float:
    from ..exact import parse_float
    x = parse_float(value, field)
    if not np.isfinite(x):
        raise InputError(f"expected a finite number, got {value!r}", field=field)
    return x


@dataclass(frozen=True)
class NearestSingularity:
    """Result of :func:`nearest_singularity`.

    Attributes
    ----------
    distance : float
        :math:`\\sqrt{|\\Delta c|^2 + L^2|\\Delta w|^2}` to the singular pose found
        (length units; :math:`\\Delta c` the displacement of the reference point
        ``centre``); ``inf`` when the search failed.
    first_order : float
        :math:`|f|/|\\nabla f|` at the start (the linearised distance, length units).
    rotation, translation : arrays (3, 3), (3,)
        The singular pose found (``None`` on failure).
    residual : float
        |det J| (dimensionless) there.
    converged : bool
    centre : array (3,)
        The reference point the rotations turn about, in the platform frame (the
        origin by default).
    """

    distance: float
    first_order: float
    rotation: object
    translation: object
    residual: float
    converged: bool
    centre: object = (0.0, 0.0, 0.0)


def nearest_singularity(f, rotation, translation, length_scale: float, *,
                        tol: float = 1e-10, max_iter: int = 60,
                        centre=None) -> NearestSingularity:
    r"""Distance from a pose to the nearest singular pose found by local search.

    Poses near :math:`(R_0, t_0)` are the platform turned by :math:`\operatorname{Rot}(w)`
    about its reference point :math:`c` (``centre``, platform frame) and shifted by
    :math:`x`: :math:`R = \operatorname{Rot}(w)R_0`, :math:`t = t_0 + x + (R_0 - R)c`,
    measured by :math:`y = (x, L w)` (length units).  The distance depends on
    :math:`c` (QA 25a F3: at the Griffis-Duffy home pose of the example below 5.14
    about P4, its frame's origin, and 4.07 about the centroid); the default :math:`c = 0`, the platform frame's
    origin, gives :math:`t = t_0 + x`.  Starting from :math:`y = 0`,
    minimum-norm Newton steps on :math:`f(y) = 0` reach the singular surface; SLSQP
    then minimises :math:`|y|` on it.  A local method: the result is the nearest
    singularity in the basin of the start, an upper bound of the true distance (at the
    Griffis-Duffy home pose of ``examples/delta_griffis_duffy.toml`` it finds 5.14
    where a 300-start search finds 3.51: QA F11).

    Parameters
    ----------
    f : callable (R (n,3,3), t (n,3)) -> det J (n,), dimensionless
    rotation, translation : the pose (float)
    length_scale : float
        L, converting rotations to lengths (e.g. the platform circumradius).
    centre : array (3,), optional
        The reference point c in the platform frame (length units); None: the origin.
    """
    from scipy.optimize import minimize
    R0 = np.asarray(rotation, dtype=float)
    t0 = np.asarray(translation, dtype=float)
    L = float(length_scale)
    c = np.zeros(3) if centre is None else np.asarray(centre, dtype=float).reshape(3)

    # the search runs in units of L (u = y / L: translations over L, rotation vectors
    # as they are), so its steps and tolerances do not depend on the length unit (QA V 4:
    # an absolute difference step 1e-6 missed the singular surface at L = 3.5e-6)
    def g(u):
        u = np.atleast_2d(u)
        R = rotation_from_vector(u[:, 3:]) @ R0
        return np.asarray(f(R, t0 + L * u[:, :3] + (R0 - R) @ c), dtype=float)

    def grad(u, h=1e-6):
        E = np.eye(6) * h
        v = g(np.concatenate([u + E, u - E]))
        return (v[:6] - v[6:]) / (2 * h)

    y = np.zeros(6)
    f0 = float(g(y)[0])
    g0 = grad(y)
    first = L * abs(f0) / max(np.linalg.norm(g0), 1e-300)
    ok = False
    for _ in range(max_iter):
        fy = float(g(y)[0])
        if abs(fy) < tol:
            ok = True
            break
        gy = grad(y)
        nn = gy @ gy
        if nn == 0 or not np.isfinite(nn):
            break
        y = y - fy * gy / nn
    if not ok:
        return NearestSingularity(float("inf"), first, None, None, float("nan"), False, c)
    res = minimize(lambda z: z @ z, y, jac=lambda z: 2 * z, method="SLSQP",
                   constraints=[{"type": "eq", "fun": lambda z: g(z)[0] / max(abs(f0), 1e-300),
                                 "jac": lambda z: grad(z) / max(abs(f0), 1e-300)}],
                   options={"ftol": 1e-14, "maxiter": 200})
    z = res.x if res.success and abs(g(res.x)[0]) < 10 * tol + 1e-9 and res.x @ res.x <= y @ y \
        else y
    Rs = rotation_from_vector(z[3:]) @ R0
    return NearestSingularity(L * float(np.linalg.norm(z)), float(first), Rs,
                              t0 + L * z[:3] + (R0 - Rs) @ c, float(abs(g(z)[0])), True, c)
