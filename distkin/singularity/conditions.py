r"""Singularities of six-leg platforms: Plücker Jacobian, Cayley-Menger and four-planes tests.

Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited* (ICRA 2012), Sec. IV.

Three characterisations of the parallel singularities of the octahedral manipulator
(labels of docs/design.md §3; legs P1–P4, P2–P4, P2–P5, P3–P5, P3–P6, P1–P6):

1. :math:`\det \mathbf J = 0`, :math:`\mathbf J` the matrix of normalised Plücker
   coordinates of the six leg lines, eq. (5) (:func:`plucker_jacobian`).
2. The pure condition in Cayley-Menger form (paper, Sec. IV, citing ref. [21]):
   :math:`C = D(1,2,4,5)D(3,4,5,6)D(1,2,3,6) - D(1,2,3,4)D(2,4,5,6)D(1,3,5,6) = 0`
   (:func:`cm_pure_condition`).
3. The planes :math:`P_1P_2P_4`, :math:`P_2P_3P_5`, :math:`P_3P_1P_6`, :math:`P_4P_5P_6`
   meet in a point (:func:`four_planes`).

What we found (checked in ``derivations/delta_transform.py`` and ``tests/singularity``).
With signed volumes :math:`a = V_{1245}V_{3456}V_{1236}` and
:math:`b = V_{1234}V_{2456}V_{1356}`, and :math:`\hat{\mathbf J}` the *unnormalised*
Plücker matrix (rows :math:`(p_k-b_k,\; b_k\times(p_k-b_k))`, i.e.
:math:`\operatorname{diag}(l)\,\mathbf J`):

* :math:`\det\hat{\mathbf J} = -216\,(a+b)`, and the four-planes determinant
  :math:`F` equals :math:`\det\hat{\mathbf J}` exactly;
* since :math:`D(i,j,k,l) = 288\,V_{ijkl}^2`, the paper's form is
  :math:`C = 288^3 (a^2-b^2) = -110592\,(a-b)\det\hat{\mathbf J}`.  The extra factor
  :math:`a-b` vanishes at non-singular poses (e.g. the symmetric home pose of a
  3-fold symmetric manipulator), so :math:`C = 0` is necessary, not sufficient;
* the *signed* Cayley-Menger form, built from the bideterminants
  :math:`D(I;J) = 288\,V_I V_J`,
  :math:`K = D(1,2,4,5)D(3,4,5,6)D(1,2,3,6) + D(1,2,4,5;1,2,3,4)D(3,4,5,6;2,4,5,6)D(1,2,3,6;1,3,5,6)
  = 288^3\,a\,(a+b) = -110592\,a\,\det\hat{\mathbf J}`
  (:func:`signed_cm_condition`), has the ratio :math:`-110592\,a` to
  :math:`\det\hat{\mathbf J}`: one sign wherever none of the tetrahedra
  :math:`P_1P_2P_4P_5`, :math:`P_3P_4P_5P_6`, :math:`P_1P_2P_3P_6` is flat.

Number types: ``fast`` (float64, batched over leading axes), ``precise`` (mpmath object
arrays), ``certified`` (flint ``fmpq`` exact or ``arb`` balls; a sign that a ball cannot
decide raises :class:`~distkin.errors.UncertifiedError`).  sympy is never imported
here unless the caller passes sympy numbers (exact symbolic checks).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from ..errors import InputError, UncertifiedError
from ..exact import check_method

__all__ = [
    "OCTAHEDRAL_LEGS",
    "octahedral_joints",
    "plucker_jacobian",
    "jacobian_det",
    "cm_pure_condition",
    "signed_cm_condition",
    "volume_factors",
    "four_planes",
    "FourPlanes",
    "certified_sign",
    "RATIO_CONSTANT",
    "PLANES",
]

#: legs of the octahedral manipulator as (base label, platform label), docs/design.md §3
OCTAHEDRAL_LEGS = ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6))

#: 288^3 / 216: C = -RATIO_CONSTANT (a - b) det(Jhat), K = -RATIO_CONSTANT a det(Jhat)
RATIO_CONSTANT = 110592


# ------------------------------------------------------------------ number-type helpers

def _kind(x) -> str:
    arr = np.asarray(x)
    if arr.dtype != object:
        return "fast"
    first = arr.ravel()[0]
    name = type(first).__name__
    if (type(first).__module__ or "").startswith("sympy"):
        return "sympy"
    if name in ("arb", "fmpq", "fmpz"):
        return "certified"
    if name == "mpf":
        return "precise"
    if isinstance(first, (int, Fraction)):
        return "exact"
    return "fast"


def _cross(a, b):
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1)


def _sqrt(x, kind):
    if kind == "fast":
        return np.sqrt(x)
    if kind == "precise":
        import mpmath
        return np.vectorize(mpmath.sqrt, otypes=[object])(x)
    if kind == "sympy":
        import sympy
        return np.vectorize(sympy.sqrt, otypes=[object])(x)
    import flint
    return np.vectorize(lambda v: flint.arb(v).sqrt(), otypes=[object])(x)


def _det(M, kind):
    """Determinant of (..., n, n): batched float, or one object matrix."""
    if kind == "fast":
        return np.linalg.det(np.asarray(M, dtype=float))
    M = np.asarray(M, dtype=object)
    if M.ndim != 2:
        raise InputError(f"expected one matrix in the {kind} tier, got shape {M.shape}")
    n = M.shape[0]
    if kind == "precise":
        from ..exact import mp_det
        return mp_det(M.tolist())            # not mpmath.det: see mp_det
    if kind == "sympy":
        import sympy
        return sympy.expand(sympy.Matrix(M.tolist()).det(method="berkowitz"))
    import flint
    flat = [_to_flint(x) for x in M.ravel()]
    if all(type(v).__name__ == "fmpq" for v in flat):
        return flint.fmpq_mat(n, n, flat).det()
    return flint.arb_mat(n, n, [flint.arb(v) if type(v).__name__ != "arb" else v
                                for v in flat]).det()


def _to_flint(x):
    import flint
    if isinstance(x, Fraction):
        return flint.fmpq(x.numerator, x.denominator)
    if isinstance(x, (int, np.integer)):
        return flint.fmpq(int(x))
    if isinstance(x, (float, np.floating)):
        f = Fraction(float(x))
        return flint.fmpq(f.numerator, f.denominator)
    return x


def _prepare(points, method):
    """points -> array in the tier's type; method None keeps the input's type."""
    arr = np.asarray(points) if not isinstance(points, np.ndarray) else points
    if method is None:
        kind = _kind(arr)
        if kind == "exact":
            arr = np.vectorize(_to_flint, otypes=[object])(arr)
            kind = "certified"
        return arr, kind
    check_method(method)
    if method == "fast":
        if arr.dtype == object:
            arr = np.vectorize(_float, otypes=[float])(arr)
        return np.asarray(arr, dtype=float), "fast"
    if method == "precise":
        import mpmath
        return np.vectorize(lambda v: v if type(v).__name__ == "mpf" else mpmath.mpf(_float_or_str(v)),
                            otypes=[object])(arr), "precise"
    return np.vectorize(_to_flint, otypes=[object])(np.asarray(arr, dtype=object)), "certified"


def _sympify(v):
    import sympy
    return sympy.sympify(v)


def _float(v):
    if type(v).__name__ == "arb":
        return float(v.mid())
    if type(v).__name__ == "fmpq":
        return int(v.p) / int(v.q)
    return float(v)


def _float_or_str(v):
    import mpmath
    if isinstance(v, Fraction):
        return mpmath.mpf(v.numerator) / v.denominator
    if type(v).__name__ == "fmpq":
        return mpmath.mpf(int(v.p)) / int(v.q)
    if type(v).__name__ == "arb":
        return mpmath.mpf(v.mid().str(mpmath.mp.dps + 5, radius=False))
    return mpmath.mpf(v)


# ----------------------------------------------------------------------- the Jacobian

def octahedral_joints(points):
    """Leg end points of the octahedral manipulator.

    Parameters
    ----------
    points : array (..., 6, 3)
        P1..P6 in the base frame (length units).

    Returns
    -------
    base_joints, platform_joints : arrays (..., 6, 3)
        Leg k runs from ``base_joints[..., k, :]`` to ``platform_joints[..., k, :]``
        (:data:`OCTAHEDRAL_LEGS`).
    """
    pts = np.asarray(points) if not isinstance(points, np.ndarray) else points
    if pts.shape[-2:] != (6, 3):
        raise InputError(f"expected points of shape (..., 6, 3), got {pts.shape}", field="points")
    bi = [b - 1 for b, _ in OCTAHEDRAL_LEGS]
    pi = [p - 1 for _, p in OCTAHEDRAL_LEGS]
    return pts[..., bi, :], pts[..., pi, :]


def plucker_jacobian(base_joints, platform_joints, *, normalised: bool = True,
                     reference=None, method: str | None = None):
    r"""The Jacobian of eq. (5): Plücker coordinates of the six leg lines.

    Row :math:`k` is :math:`(u_k,\; (b_k - c)\times u_k)` with
    :math:`u_k = (p_k - b_k)/l_k` (``normalised=True``, the :math:`\mathbf J` of
    eq. (5): :math:`\dot l = \mathbf J (v, \Omega)`) or :math:`u_k = p_k - b_k`
    (``normalised=False``: :math:`\hat{\mathbf J} = \operatorname{diag}(l)\mathbf J`,
    :math:`\operatorname{diag}(l)\dot l = \hat{\mathbf J}(v,\Omega)`).  ``c`` is the
    reference point (default the base origin); :math:`v` is the velocity of the
    platform point at :math:`c`, :math:`\Omega` the angular velocity.  The choice of
    :math:`c` does not change :math:`\det\mathbf J`.

    Parameters
    ----------
    base_joints, platform_joints : array (..., 6, 3)
        Joint centres in the base frame (length units).
    normalised : bool
    reference : array (3,), optional
    method : {"fast", "precise", "certified"} or None
        None keeps the input's number type.

    Returns
    -------
    array (..., 6, 6)
        Direction columns dimensionless (normalised) or in length units; moment
        columns one length unit more.
    """
    b, kind = _prepare(base_joints, method)
    p, _ = _prepare(platform_joints, kind if kind in ("fast", "precise", "certified") else None)
    if kind == "sympy" and _kind(p) != "sympy":
        p = np.vectorize(_sympify, otypes=[object])(p)
    if b.shape[-2:] != (6, 3) or p.shape[-2:] != (6, 3):
        raise InputError(f"expected joints of shape (..., 6, 3), got {b.shape} and {p.shape}")
    u = p - b
    if normalised:
        ln = _sqrt(np.sum(u * u, axis=-1), kind)
        u = u / ln[..., None]
    arm = b if reference is None else b - np.asarray(reference, dtype=b.dtype)
    return np.concatenate([u, _cross(arm, u)], axis=-1)


def jacobian_det(base_joints, platform_joints, *, normalised: bool = True,
                 length_scale=None, method: str | None = None):
    r""":math:`\det\mathbf J` of eq. (5) (or of :math:`\hat{\mathbf J}`).

    With ``length_scale`` L the moment columns are divided by L, so that the
    normalised determinant is dimensionless (:math:`\det/L^3`).

    Returns
    -------
    float array (batch shape) | mpf | arb or fmpq (certified; exact for rational
    joints with ``normalised=False``)
    """
    J = plucker_jacobian(base_joints, platform_joints, normalised=normalised, method=method)
    kind = _kind(J) if method is None else method
    if kind == "exact":
        kind = "certified"
    d = _det(J, kind)
    if length_scale is not None:
        d = d / length_scale ** 3
    return d


def certified_sign(value) -> int:
    """The sign of an ``arb``/``fmpq`` value, or :class:`UncertifiedError` when the ball
    contains 0.

    Examples
    --------
    >>> import flint
    >>> certified_sign(flint.arb(2, 0.5)), certified_sign(flint.fmpq(-1, 3))
    (1, -1)
    >>> certified_sign(flint.arb(0, 1e-9))
    Traceback (most recent call last):
    ...
    distkin.errors.UncertifiedError: expected a ball excluding 0, got [+/- 1.01e-9] (hint: raise the precision or move away from the singularity)
    """
    name = type(value).__name__
    if name in ("fmpq", "fmpz"):
        return (value > 0) - (value < 0)
    if name == "arb":
        if value > 0:
            return 1
        if value < 0:
            return -1
        raise UncertifiedError(f"expected a ball excluding 0, got {value.str(5, radius=True)}",
                               hint="raise the precision or move away from the singularity")
    raise InputError(f"expected an arb or fmpq value to certify, got {name}")


# ------------------------------------------------------------- Cayley-Menger conditions

def _sq(points, method):
    from ..geometry.cayley_menger import squared_distances
    pts, kind = _prepare(points, method)
    if pts.shape[-2:] != (6, 3):
        raise InputError(f"expected points P1..P6 of shape (..., 6, 3), got {pts.shape}",
                         field="points")
    return squared_distances(pts), kind


def cm_pure_condition(points, *, method: str | None = None, relative: bool = False):
    r"""The paper's pure condition in Cayley-Menger form (Sec. IV):

    .. math:: C = D(1,2,4,5)D(3,4,5,6)D(1,2,3,6) - D(1,2,3,4)D(2,4,5,6)D(1,3,5,6).

    :math:`C = -110592\,(a-b)\det\hat{\mathbf J}` (module docstring): it vanishes at
    every singularity but also where :math:`a = b`.

    Parameters
    ----------
    points : array (..., 6, 3)
        P1..P6, base frame (length units).
    relative : bool
        Divide by :math:`D(1,2,4,5)D(3,4,5,6)D(1,2,3,6) + D(1,2,3,4)D(2,4,5,6)D(1,3,5,6)`
        (dimensionless, in [-1, 1]).

    Returns
    -------
    number or float array (length units^18 unless relative)
    """
    from ..geometry.cayley_menger import cayley_menger as D
    sq, _ = _sq(points, method)
    left = D(sq, (1, 2, 4, 5)) * D(sq, (3, 4, 5, 6)) * D(sq, (1, 2, 3, 6))
    right = D(sq, (1, 2, 3, 4)) * D(sq, (2, 4, 5, 6)) * D(sq, (1, 3, 5, 6))
    return (left - right) / (left + right) if relative else left - right


def signed_cm_condition(points, *, method: str | None = None, relative: bool = False):
    r"""The signed pure condition from Cayley-Menger (bi)determinants:

    .. math:: K = D(1,2,4,5)D(3,4,5,6)D(1,2,3,6)
              + D(1,2,4,5;1,2,3,4)\,D(3,4,5,6;2,4,5,6)\,D(1,2,3,6;1,3,5,6)
              = 288^3\,a\,(a+b) = -110592\,a\,\det\hat{\mathbf J}.

    Distances only, and :math:`K = 0` exactly at the singularities (where
    :math:`a \ne 0`).  ``relative`` divides by
    :math:`|D(1,2,4,5)D(3,4,5,6)D(1,2,3,6)| + |D(\dots;\dots)D(\dots;\dots)D(\dots;\dots)|`.
    """
    from ..geometry.cayley_menger import cayley_menger as D
    sq, _ = _sq(points, method)
    first = D(sq, (1, 2, 4, 5)) * D(sq, (3, 4, 5, 6)) * D(sq, (1, 2, 3, 6))
    second = (D(sq, (1, 2, 4, 5), (1, 2, 3, 4)) * D(sq, (3, 4, 5, 6), (2, 4, 5, 6))
              * D(sq, (1, 2, 3, 6), (1, 3, 5, 6)))
    if relative:
        return (first + second) / (abs(first) + abs(second))
    return first + second


def _vol(pts, i, j, k, l):
    a = pts[..., i - 1, :]
    return np.sum((pts[..., j - 1, :] - a) * _cross(pts[..., k - 1, :] - a, pts[..., l - 1, :] - a),
                  axis=-1) / 6


def volume_factors(points, *, method: str | None = None):
    r"""Signed-volume products :math:`a = V_{1245}V_{3456}V_{1236}` and
    :math:`b = V_{1234}V_{2456}V_{1356}` (length units^9).

    :math:`\det\hat{\mathbf J} = -216(a+b)`; the ratio of the paper's condition to
    :math:`\det\hat{\mathbf J}` is :math:`-110592(a-b)`, that of the signed one
    :math:`-110592\,a`.
    """
    pts, _ = _prepare(points, method)
    a = _vol(pts, 1, 2, 4, 5) * _vol(pts, 3, 4, 5, 6) * _vol(pts, 1, 2, 3, 6)
    b = _vol(pts, 1, 2, 3, 4) * _vol(pts, 2, 4, 5, 6) * _vol(pts, 1, 3, 5, 6)
    return a, b


# --------------------------------------------------------------------- four planes

#: the four planes of the geometric test (Downing, Samuel, Hunt 2002; paper Sec. IV)
PLANES = ((1, 2, 4), (2, 3, 5), (3, 1, 6), (4, 5, 6))


@dataclass(frozen=True)
class FourPlanes:
    """Result of :func:`four_planes`.

    Attributes
    ----------
    det : number or array
        :math:`F = \\det[n_i,\\; -n_i\\cdot P_i]_{i=1..4}` with
        :math:`n_i = (P_j-P_i)\\times(P_k-P_i)` (length units^9; equals
        :math:`\\det\\hat{\\mathbf J}`).
    relative : float or array
        :math:`F` with unit normals and offsets divided by ``length_scale``
        (dimensionless).
    point : array (..., 3)
        Least-squares common point of the four planes (length units).
    spread : float or array
        Largest distance from ``point`` to one of the planes (length units); 0 when
        the planes meet in a point.
    """

    det: object
    relative: object
    point: object
    spread: object


def four_planes(points, *, length_scale: float | None = None, method: str | None = None
                ) -> FourPlanes:
    r"""Do the planes :math:`P_1P_2P_4`, :math:`P_2P_3P_5`, :math:`P_3P_1P_6`,
    :math:`P_4P_5P_6` meet in a point? (Rojas et al., Sec. IV, ref. [19]).

    Four planes :math:`n_i\cdot x = c_i` have a common (possibly ideal) point iff
    :math:`\det[n_i, -c_i] = 0`.  ``point`` and ``spread`` are computed in float64
    whatever the tier.

    Parameters
    ----------
    points : array (..., 6, 3)
        P1..P6, base frame (length units).
    length_scale : float, optional
        For ``relative`` (default: the largest distance of a point from P1).
    """
    pts, kind = _prepare(points, method)
    if pts.shape[-2:] != (6, 3):
        raise InputError(f"expected points of shape (..., 6, 3), got {pts.shape}", field="points")
    rows = []
    for i, j, k in PLANES:
        a = pts[..., i - 1, :]
        n = _cross(pts[..., j - 1, :] - a, pts[..., k - 1, :] - a)
        c = np.asarray(np.sum(n * a, axis=-1), dtype=n.dtype)
        rows.append(np.concatenate([n, -c[..., None]], axis=-1))
    M = np.stack(rows, axis=-2)
    F = _det(M, kind)
    Mf = M if kind == "fast" else np.vectorize(_float, otypes=[float])(M)
    pf = pts if kind == "fast" else np.vectorize(_float, otypes=[float])(pts)
    L = length_scale
    if L is None:
        L = np.max(np.linalg.norm(pf - pf[..., :1, :], axis=-1), axis=-1)
    nrm = np.linalg.norm(Mf[..., :3], axis=-1)
    U = Mf / nrm[..., None]
    Us = U.copy()
    Us[..., 3] = Us[..., 3] / np.asarray(L)[..., None]
    rel = np.linalg.det(Us)
    N, c = U[..., :3], -U[..., 3]
    x = np.einsum("...ij,...j->...i", np.linalg.pinv(N), c)     # least squares, batched
    spread = np.max(np.abs(np.einsum("...ij,...j->...i", N, x) - c), axis=-1)
    if np.ndim(rel) == 0:
        rel, spread = float(rel), float(spread)
    return FourPlanes(F, rel, x, spread)
