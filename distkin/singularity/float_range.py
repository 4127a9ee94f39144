r"""The float64 range of the fast singularity tests (:mod:`.conditions`): power-of-two
rescaling of the coordinates, scaling back with a
:class:`~distkin.errors.FloatRangeWarning` when the value itself leaves the
float64 range (:mod:`distkin.geometry.pow2_scale`), and the rounding-error estimate of the fast :math:`\det\mathbf J`.

The tests are homogeneous in the coordinates: the Cayley-Menger conditions of degree 18
(three products of (bi)determinants of degree 6), :math:`\det\hat{\mathbf J}` of degree
9, :math:`\det\mathbf J` of degree 3 (0 with a length scale scaled alike).  Multiplying
the coordinates by :math:`2^{-e}` is exact (no rounding, barring subnormal coordinates
far below the others, which do not matter at float64's precision), and so is multiplying
the value by :math:`2^{ke}` afterwards, unless it over- or underflows: then the value
itself is beyond float64, and the warning gives it as a decimal.  Without rescaling the
products of the conditions underflowed to an exact-looking ``0.0`` with a ``0.0`` error
estimate below coordinates of about 1e-17 (QA), and overflowed to NaN above 1e17.
The check costs one maximum per point set: inputs whose squared distances (or
coordinates) lie within :math:`2^{\pm 64}` are computed unscaled, as before.
"""

from __future__ import annotations

import numpy as np

from ..geometry import pow2_scale
from ..geometry.pow2_scale import exponent as _exponent

__all__: list[str] = []     # helpers of distkin.singularity.conditions

#: squared distances (conditions) or coordinates (det J) within [2^-64, 2^64] are used
#: as they are: every product and error estimate of the tests then stays normal
_LO, _HI = 2.0 ** -64, 2.0 ** 64
#: the smallest positive float64 (subnormal): an error estimate never rounds below it
_SMALLEST = float(np.nextafter(0.0, 1.0))


def scaled_squared_distances(pts):
    """``(sq, e)``: the squared distances of the points (..., 6, 3) times
    :math:`2^{-2e}`, ``e`` an int array of the batch shape (0 where the unscaled squared
    distances are in range), or None when no point set needs it.  The scale puts the
    largest coordinate difference in [0.5, 1): coordinates first divided by a power of
    two near their largest magnitude (no overflow of the differences), then by one near
    the largest difference from P1."""
    from ..geometry.cayley_menger import squared_distances
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        sq = squared_distances(pts)
        s = sq.reshape(sq.shape[:-2] + (-1,)).max(axis=-1)    # (faster than axis=(-2, -1))
        ok = (s >= _LO) & (s <= _HI)
        if ok.all():
            return sq, None
        e = _point_exponent(pts, ok)
        return squared_distances(np.ldexp(pts, -e[..., None, None])), e


def _point_exponent(pts, ok):
    """``e`` (int array, batch shape; 0 where ``ok``) putting the largest coordinate
    difference from P1 of ``pts·2^-e`` in [0.5, 1): coordinates first divided by a power
    of two near their largest magnitude (no overflow of the differences), then by one
    near the largest difference from P1."""
    e1 = _exponent(np.max(np.abs(pts), axis=(-2, -1)))
    p1 = np.ldexp(pts, -e1[..., None, None])
    e = e1 + _exponent(np.max(np.abs(p1 - p1[..., :1, :]), axis=(-2, -1)))
    return np.where(ok, 0, e)


def scaled_points(pts):
    r"""``(pts·2^-e, e)`` for point sets (..., n, 3) whose largest coordinate difference
    from P1 leaves :math:`2^{\pm 32}` (:func:`_point_exponent`; 0 elsewhere), or
    ``(pts, None)`` when none does.  Within that range the products of nine coordinate
    differences of :func:`~.planes.volume_factors` and :func:`~.planes.four_planes`
    (and the squared norms of their plane normals) stay normal: QA 23 found 0.0 and
    a false "collinear" at 1e-100, inf and NaN at 1e80 and 1e150."""
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        if pts.ndim == 2:                     # one point set: scalars (cheaper)
            m = np.abs(pts - pts[0]).max()
            if 2.0 ** -32 <= m <= 2.0 ** 32:
                return pts, None
        else:
            m = np.max(np.abs(pts - pts[..., :1, :]), axis=(-2, -1))
        ok = (m >= 2.0 ** -32) & (m <= 2.0 ** 32)
        if ok.all():
            return pts, None
        e = _point_exponent(pts, ok)
    return np.ldexp(pts, -e[..., None, None]), e


def det_in_range(d) -> bool:
    """Every fast det J within :math:`2^{\\pm 960}` (finite): computed from joints in
    range, no rescaling needed (the check of the hot path, on the value only).  An
    exact 0 fails it too: it is then computed again from rescaled joints (rare)."""
    if np.ndim(d) == 0:
        return 2.0 ** -960 <= abs(float(d)) <= 2.0 ** 960      # (NaN: False)
    with np.errstate(invalid="ignore"):
        a = np.abs(d)
        return bool(np.all((a >= 2.0 ** -960) & (a <= 2.0 ** 960)))


def scaled_joints(b, p):
    """``(b, p, e)``: the joints times :math:`2^{-e}`, ``e`` from the largest coordinate
    magnitude of each pose (0 where that is within :math:`2^{\\pm 64}`).  Called only
    when :func:`det_in_range` fails."""
    m = np.maximum(np.max(np.abs(b), axis=(-2, -1)), np.max(np.abs(p), axis=(-2, -1)))
    ok = ~((m < _LO) | (m > _HI))            # NaN: left as it is, refused later
    e = np.where(ok, 0, _exponent(m))
    return np.ldexp(b, -e[..., None, None]), np.ldexp(p, -e[..., None, None]), e


def scale_back(value, e, degree, what, instead="relative=True"):
    """``value * 2**(degree * e)`` (float or array); a non-zero value that leaves the
    float64 range warns (:func:`distkin.geometry.pow2_scale.scale_back`: the value as a
    decimal, ``instead`` the dimensionless alternative) and reads 0.0 or inf.  ``e``
    None: unchanged."""
    if e is None:
        return value
    out, _ = pow2_scale.scale_back(
        value, degree * np.asarray(e), what,
        f"{instead}, method='precise' / 'certified', or another length unit")
    return float(out) if out.ndim == 0 else out


def scale_error(err, e, degree):
    """An error estimate scaled back like :func:`scale_back`, rounded up: a non-zero
    estimate never becomes 0 (at least the smallest float64); no warning (the value's
    says it)."""
    if e is None:
        return err
    v = np.asarray(err, dtype=float)
    with np.errstate(over="ignore", under="ignore"):
        out = np.ldexp(v, degree * np.asarray(e))
        out = np.where((v > 0) & (out < 2.0 ** -1022), np.nextafter(out, np.inf), out)
    return float(out) if out.ndim == 0 else out


def floor_error(err, exact):
    """A fast error estimate that is 0 only where the value is exact (``exact``):
    elsewhere at least the smallest float64 (an estimate that underflowed)."""
    return np.where(exact, 0.0, np.maximum(err, _SMALLEST))


#: :func:`det_error` is at most 1966.6 :math:`\varepsilon c_u^3 c_m^3` (rows
#: :math:`\|r'_k\| \le \sqrt 2`: :math:`6 \cdot 24 (\sqrt 2 + 1) \sqrt 2^5`), and
#: :math:`c_u^3 c_m^3 \le 3^{4.5}\,\mu^3 (\alpha\mu)^3` with :math:`\mu, \alpha` the
#: largest entries of the directions and arms in magnitude
_ERROR_BOUND = 1967.0 * 3.0 ** 4.5 * 2.0 ** -53


def det_resolved(d, J, arm, unit: bool = False) -> bool:
    r"""True when every fast :math:`|\det\mathbf J|` exceeds a bound of its
    :func:`det_error` estimate (:data:`_ERROR_BOUND` :math:`\mu^3(\alpha\mu)^3`, about
    :math:`3\cdot 10^{-11}` of the scale of the rows; with ``unit`` directions,
    :math:`c_u = 1` and :math:`c_m \le \sqrt 3\,\alpha`: 1967 :math:`\varepsilon\,
    (\sqrt 3\,\alpha)^3`): the check of the hot path (one or two maxima per pose);
    False sends the caller to the estimate itself."""
    one = np.ndim(d) == 0
    ma = np.abs(arm).max() if one else np.max(np.abs(arm), axis=(-2, -1))
    if unit:
        mu, k = 1.0, 1967.0 * 3.0 ** 1.5 * 2.0 ** -53
    else:
        k = _ERROR_BOUND
        mu = np.abs(J[..., :3]).max() if one else np.max(np.abs(J[..., :3]), axis=(-2, -1))
    if one:                                   # one pose: scalars (cheaper than where)
        mu, mam = (mu if mu > 0 else 1.0), (ma * mu if ma > 0 else 1.0)
        return bool(abs(d) > k * (mu * mam) ** 3)
    mu, mam = (np.where(c > 0, c, 1.0) for c in (mu, ma * mu))
    return bool(np.all(np.abs(d) > k * (mu * mam) ** 3))


def unresolved_note(d, err, flag, what: str) -> str:
    """The ConditioningWarning text of fast determinants ``d`` whose estimate ``err``
    exceeds them (``flag``, batch shape): the first one's value and estimate, the
    count, and what to use instead."""
    flag = np.asarray(flag)
    i = int(np.flatnonzero(flag.ravel())[0])
    v = float(np.ravel(d)[i])
    e = float(np.ravel(np.broadcast_to(err, np.shape(d)))[i])
    where = ""
    if flag.ndim:
        idx = tuple(int(j) for j in np.unravel_index(i, flag.shape))
        where = f" at {int(flag.sum())} of {flag.size} pose(s) (first: batch index {idx})"
    return (f"fast {what}{where} = {v:.6g} is within its rounding-error estimate {e:.3g}: "
            f"float64 does not resolve its digits or its sign (ill-conditioned leg lines, "
            f"or a pose at a singularity); use method='precise' (more dps) or 'certified' "
            f"(with_error=True returns the estimate)")


def det_error(J, arm, u, kind):
    r"""Rounding-error estimate of :math:`\det\mathbf J` for Plücker rows
    :math:`r_k = (u_k,\; a_k\times u_k)` (J (..., 6, 6), arms ``a`` and directions ``u``
    (..., 6, 3)).  With the direction and moment columns divided by
    :math:`c_u = \max_k\|u_k\|` and :math:`c_m = \max_k \|a_k\|\|u_k\|` (rows
    :math:`r'_k`; the estimate does not depend on the length unit),

    .. math:: e = c_u^3 c_m^3 \sum_k \|\delta_k\| \prod_{j\ne k}\|r'_j\|,\qquad
              \|\delta_k\| = 4n\,\varepsilon\,(\|r'_k\| + \|a_k\|\|u_k\|/c_m),\quad n = 6,

    first order in the perturbation :math:`\delta_k` of row :math:`k` (Hadamard's
    inequality bounds its cofactors by the other rows' norms): the rounding of the
    directions and of the cross products (a few :math:`\varepsilon\|a_k\|\|u_k\|`,
    which can exceed :math:`\varepsilon\|a_k\times u_k\|` where
    :math:`a_k \parallel u_k`) and the backward error of LU (Higham, *Accuracy and
    Stability of Numerical Algorithms*, 2nd ed., Ch. 9, :math:`n\varepsilon` times
    modest growth).  An estimate, not a proof (the certified tier gives one),
    deliberately larger (by about 1e3 on near-singular test poses); relative to the
    value it grows like :math:`1/|\det\mathbf J|` near a singularity."""
    if kind == "fast":
        un = np.linalg.norm(u, axis=-1)
        au = np.linalg.norm(arm, axis=-1) * un
        cu, cm = (np.max(x, axis=-1) for x in (un, au))
        cu, cm = (np.where(c > 0, c, 1.0) for c in (cu, cm))
        Js = np.concatenate([J[..., :3] / cu[..., None, None], J[..., 3:] / cm[..., None, None]],
                            axis=-1)
        norms = np.linalg.norm(Js, axis=-1)
        pert = 24 * 2.0 ** -53 * (norms + au / cm[..., None])
        err = 0.0
        for k in range(6):
            others = [j for j in range(6) if j != k]
            err = err + pert[..., k] * np.prod(norms[..., others], axis=-1)
        err = err * cu ** 3 * cm ** 3
        return float(err) if np.ndim(err) == 0 else err
    import mpmath
    unit = mpmath.mpf(2) ** -mpmath.mp.prec            # the precise tier's unit roundoff
    nrm = lambda v: mpmath.sqrt(sum(x * x for x in v))  # noqa: E731
    rows = np.asarray(J, dtype=object)
    un = [nrm(x) for x in u]
    au = [nrm(a) * n for a, n in zip(arm, un)]
    cu, cm = (max(x) if max(x) > 0 else mpmath.mpf(1) for x in (un, au))
    norms = [nrm(list(r[:3] / cu) + list(r[3:] / cm)) for r in rows]
    err = mpmath.mpf(0)
    for k in range(6):
        pert = 24 * unit * (norms[k] + au[k] / cm)
        prod = mpmath.mpf(1)
        for j in range(6):
            if j != k:
                prod *= norms[j]
        err += pert * prod
    return err * cu ** 3 * cm ** 3
