r"""Enclosures of σmin and σmax of the scaled :math:`W = S_T^{-1}J^\mathsf{T}` and of
κ = σmin/σmax (Kühne et al., eq. (4), Sec. II-C-2) over a box of Jacobians
:math:`|J' - J| \le r` entrywise (QA 25a F7: the ``jacobian`` query printed κ, a float64
SVD, beside the certified tier's radii without a word on its own accuracy).

Proof sketch.  For L >= 6 the symmetric :math:`(6+L)\times(6+L)` matrix
:math:`H(J') = \begin{pmatrix}0 & W'\\ W'^\mathsf{T} & 0\end{pmatrix}` (Jordan-Wielandt)
has the eigenvalues :math:`\pm\sigma_i(W')` and L - 6 zeros, so its k-th largest
eigenvalue is :math:`\sigma_k(W')` for k <= 6 (for L < 6: :math:`\pm\sigma_1..\sigma_L`
and zeros, σmin = 0 as :func:`.isotropy.scaled_singular_values` says).  Let
:math:`H(J) \approx Q\hat\Lambda Q^\mathsf{T}` be numpy's float eigendecomposition:

* Ostrowski: the k-th largest eigenvalue of :math:`Q\hat\Lambda Q^\mathsf{T}` is
  :math:`\theta_k\hat\lambda_k` with :math:`\theta_k` between the extreme eigenvalues of
  :math:`QQ^\mathsf{T}`, which are those of :math:`Q^\mathsf{T}Q`, so in
  :math:`[1-\eta, 1+\eta]` for :math:`\eta \ge \|Q^\mathsf{T}Q - I\|_F \ge
  \|Q^\mathsf{T}Q - I\|_2` (needs η < 1);
* Weyl: :math:`|\lambda_k(H(J')) - \lambda_k(Q\hat\Lambda Q^\mathsf{T})| \le
  \|H(J') - H(J)\|_2 + \|H(J) - Q\hat\Lambda Q^\mathsf{T}\|_2 \le \delta`: the first
  term is :math:`\|E\|_2 \le \|E\|_F` for :math:`E = S_T^{-1}(J' - J)^\mathsf{T}`
  (the block matrix of E has E's singular values), at most the Frobenius norm of
  :math:`S_T^{-1}r^\mathsf{T}` over the whole box (Weyl's :math:`|\sigma_i(W+E) -
  \sigma_i(W)| \le \|E\|_2` for the radii); the second, the float decomposition's own
  error, at most the Frobenius norm of the ball matrix :math:`H(J) - Q\hat\Lambda
  Q^\mathsf{T}`.

η and δ are computed with arb balls from the exact binary values of J, r, ST, Q and
:math:`\hat\Lambda`, and the bounds are rounded outwards, so the enclosure is rigorous
whenever r bounds J's error (the certified tier's radii); with the precise or fast
tier's error estimates it is an estimate of the same kind.  Its width is about
:math:`2\|r/S_T\|_F + 10^{-15}\sigma_{max}`: absolute in σ, so σmin's relative width
grows like 1/κ near a singular pose (an honest wide enclosure, not a failure).
"""

from __future__ import annotations

import math

import numpy as np

from .isotropy import ST_DEFAULT, check_scaling

__all__ = ["scaled_sigma_bounds", "kappa_bounds"]


def scaled_sigma_bounds(J, radius, ST=ST_DEFAULT, *, bits: int = 128):
    """Enclosures ``((smin_lo, smin_hi), (smax_lo, smax_hi))`` (floats, rounded outwards)
    of σmin and σmax of ``ST⁻¹J'ᵀ`` for every ``J'`` with ``|J' - J| <= radius``
    (module docstring), or None where a radius is not finite or the float
    eigendecomposition is too far from orthogonal (η >= 1, not seen in practice).

    Parameters
    ----------
    J, radius : array (L, 6)
        One Jacobian (rows: legs; q̇ = J (v, ω)) and its entrywise error bound (>= 0).
    ST : 6 floats
        The scaling matrix's diagonal (N, N, N, N·m, N·m, N·m).
    bits : int
        Working precision of the arb balls.
    """
    import flint

    from ..exact_roots import working_precision
    J = np.asarray(J, dtype=float)
    r = np.asarray(radius, dtype=float)
    if J.ndim != 2 or J.shape[1] != 6 or r.shape != J.shape:
        raise ValueError(f"expected J and radius of one shape (L, 6), got {J.shape} and "
                         f"{r.shape}")
    if not (np.all(np.isfinite(J)) and np.all(np.isfinite(r))):
        return None
    st = check_scaling(ST)
    L = J.shape[0]
    n = 6 + L
    W = J.T / st[:, None]
    H = np.zeros((n, n))
    H[:6, 6:], H[6:, :6] = W, W.T
    lam, Q = np.linalg.eigh(H)                      # ascending
    with working_precision(bits):
        Hb = [[flint.arb(0)] * n for _ in range(n)]
        box = flint.arb(0)                # ||E||_F^2 of the radii over ST: Weyl's term
        for i in range(6):
            s = flint.arb(float(st[i]))
            for j in range(L):
                w = flint.arb(float(J[j, i])) / s
                Hb[i][6 + j] = Hb[6 + j][i] = w
                e = flint.arb(float(r[j, i])) / s
                box += e * e
        Qa = flint.arb_mat(n, n, [float(x) for x in Q.ravel()])
        D = flint.arb_mat(n, n, [float(lam[i]) if i == j else 0.0
                                  for i in range(n) for j in range(n)])
        # ||H(J') - QΛ̂Qᵀ||_2 <= ||H(J') - H(J)||_2 + ||H(J) - QΛ̂Qᵀ||_F, and the first
        # is ||E||_2 <= ||E||_F for the block matrix of E = ST⁻¹(J' - J)ᵀ
        delta = (box.sqrt().upper()
                 + _frobenius_upper(flint.arb_mat(Hb) - Qa * D * Qa.transpose()))
        eta = _frobenius_upper(Qa.transpose() * Qa - flint.arb_mat(n, n, [
            1.0 if i == j else 0.0 for i in range(n) for j in range(n)]))
        if not eta < 1:
            return None

        def down(k):                      # θ λ̂ - δ, θ in [1 - η, 1 + η], at its lowest
            x = float(lam[k])
            return _lower((1 - eta if x >= 0 else 1 + eta) * x - delta)

        def up(k):
            x = float(lam[k])
            return _upper((1 + eta if x >= 0 else 1 - eta) * x + delta)
        top = n - 1                                  # largest eigenvalue: σmax
        smax = (max(down(top), 0.0), up(top))
        smin = (max(down(n - 6), 0.0), up(n - 6)) if L >= 6 else (0.0, 0.0)
    return smin, smax


def kappa_bounds(J, radius, ST=ST_DEFAULT, *, bits: int = 128):
    """``(lo, hi)`` enclosing κ = σmin/σmax (eq. (4)) of ``ST⁻¹J'ᵀ`` over the box (as
    :func:`scaled_sigma_bounds`), clipped to [0, 1]; None where that gives none."""
    b = scaled_sigma_bounds(J, radius, ST, bits=bits)
    if b is None:
        return None
    (smin_lo, smin_hi), (smax_lo, smax_hi) = b
    lo = math.nextafter(smin_lo / smax_hi, -math.inf) if smax_hi > 0 else 0.0
    hi = math.nextafter(smin_hi / smax_lo, math.inf) if smax_lo > 0 else 1.0
    return max(lo, 0.0), min(hi, 1.0)


def _frobenius_upper(M):
    """An arb holding an upper bound of the Frobenius norm of every matrix in the ball
    matrix ``M``."""
    import flint
    s = flint.arb(0)
    for i in range(M.nrows()):
        for j in range(M.ncols()):
            a = M[i, j].abs_upper()
            s += a * a
    return s.sqrt().upper()


def _lower(x) -> float:
    """A float <= every point of the arb ``x`` (an arb or a Python expression of one)."""
    import flint
    return math.nextafter(float(flint.arb(x).lower()), -math.inf)


def _upper(x) -> float:
    """A float >= every point of the arb ``x``."""
    import flint
    return math.nextafter(float(flint.arb(x).upper()), math.inf)
