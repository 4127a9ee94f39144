"""The farthest point of a sliced zonotope, compiled (Kühne et al., eqs. (14), (16)).

The paper's maximum sensitivities (Sec. II-C-4) run its polytope algorithm with unit
actuator limits, ``|p|∞ <= 1`` (rad or N·m), and take in its last step the largest
distance from the origin to a point of the *sliced* polytope, eq. (16): e.g. the largest
translation at zero rotation.  For a generator matrix G (d × L) and the slice that keeps
the output coordinates S and sets the k others (S^c) to zero, every vertex of
``{G_S p : |p|∞ <= 1, G_{S^c} p = 0}`` has at least L − k actuators at a limit
(DESIGN.md §6).  So with F the k free actuators and X the others,

.. math::  p_F = -K p_X,\\quad K = (G_{S^c,F})^{-1} G_{S^c,X},\\qquad
           u = (G_{S,X} - G_{S,F} K)\\, p_X,

over the C(L, k) sets F and the 2^(L−k) sign vectors p_X (half of them, the set being
symmetric), kept when ``|p_F|∞ <= 1``.  This is the vertex enumeration of
:func:`distkin.indices.zonotope.zonotope_best` specialised to symmetric unit limits and
k = 3, compiled by numba with a Gray-code walk over the sign vectors (about 1.6 µs per
pose and slice for L = 6 and 11 µs for L = 8, against 22 and 180 µs for the numpy
route): the Table II study evaluates four sensitivities at 9 million poses per
redundant device.

Exact up to rounding when ``G_{S^c}`` has full row rank (a singular 3 × 3 block F is
skipped: its vertices are found from other sets); an empty slice gives −inf.
"""

from __future__ import annotations

from functools import lru_cache
from itertools import combinations

import numpy as np

__all__ = ["slice_farthest_unit"]

#: feasibility slack of |p_F| <= 1 (relative), as zonotope._best_chunk
_TOL = 1e-12


@lru_cache(maxsize=None)
def _tables(L: int, k: int):
    """Free sets F, their complements X, and a Gray-code walk over half the sign vectors
    of X (first sign +1): the start vector and, per step, the index that flips."""
    F = np.array(list(combinations(range(L), k)), dtype=np.int64)
    X = np.array([[i for i in range(L) if i not in f] for f in F], dtype=np.int64)
    m = L - k
    flips = np.array([int(np.log2(((g ^ (g >> 1)) ^ ((g - 1) ^ ((g - 1) >> 1)))))
                      for g in range(1, 2 ** (m - 1))], dtype=np.int64) + 1
    return F, X, flips


@lru_cache(maxsize=1)
def _kernel():
    import numba

    @numba.njit(cache=True)
    def run(G, S, Sc, F, X, flips, out):                    # pragma: no cover (compiled)
        N = G.shape[0]
        nF, m = X.shape
        nS = S.shape[0]
        a = np.empty((3, 3))
        inv = np.empty((3, 3))
        K = np.empty((3, m))
        E = np.empty((nS, m))
        p = np.empty(3)
        u = np.empty(nS)
        sg = np.empty(m)
        for n in range(N):
            best = -1.0
            for f in range(nF):
                for i in range(3):
                    for j in range(3):
                        a[i, j] = G[n, Sc[i], F[f, j]]
                c00 = a[1, 1] * a[2, 2] - a[1, 2] * a[2, 1]
                c01 = a[1, 2] * a[2, 0] - a[1, 0] * a[2, 2]
                c02 = a[1, 0] * a[2, 1] - a[1, 1] * a[2, 0]
                det = a[0, 0] * c00 + a[0, 1] * c01 + a[0, 2] * c02
                scale = 1.0
                for j in range(3):
                    scale *= np.sqrt(a[0, j] ** 2 + a[1, j] ** 2 + a[2, j] ** 2)
                if not abs(det) > 1e-12 * scale:
                    continue
                inv[0, 0] = c00 / det
                inv[1, 0] = c01 / det
                inv[2, 0] = c02 / det
                inv[0, 1] = (a[0, 2] * a[2, 1] - a[0, 1] * a[2, 2]) / det
                inv[1, 1] = (a[0, 0] * a[2, 2] - a[0, 2] * a[2, 0]) / det
                inv[2, 1] = (a[0, 1] * a[2, 0] - a[0, 0] * a[2, 1]) / det
                inv[0, 2] = (a[0, 1] * a[1, 2] - a[0, 2] * a[1, 1]) / det
                inv[1, 2] = (a[0, 2] * a[1, 0] - a[0, 0] * a[1, 2]) / det
                inv[2, 2] = (a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0]) / det
                for i in range(3):
                    for j in range(m):
                        s = 0.0
                        for r in range(3):
                            s += inv[i, r] * G[n, Sc[r], X[f, j]]
                        K[i, j] = s
                for i in range(nS):
                    for j in range(m):
                        s = G[n, S[i], X[f, j]]
                        for r in range(3):
                            s -= G[n, S[i], F[f, r]] * K[r, j]
                        E[i, j] = s
                # start at the all-ones sign vector; p_F = -K s, u = E s
                for j in range(m):
                    sg[j] = 1.0
                for i in range(3):
                    s = 0.0
                    for j in range(m):
                        s -= K[i, j]
                    p[i] = s
                for i in range(nS):
                    s = 0.0
                    for j in range(m):
                        s += E[i, j]
                    u[i] = s
                for v in range(flips.shape[0] + 1):
                    if v > 0:                      # Gray step: flip one sign
                        j = flips[v - 1]
                        d = -2.0 * sg[j]
                        sg[j] = -sg[j]
                        for i in range(3):
                            p[i] -= d * K[i, j]
                        for i in range(nS):
                            u[i] += d * E[i, j]
                    if abs(p[0]) > 1.0 + _TOL or abs(p[1]) > 1.0 + _TOL or \
                            abs(p[2]) > 1.0 + _TOL:
                        continue
                    nrm = 0.0
                    for i in range(nS):
                        nrm += u[i] * u[i]
                    if nrm > best:
                        best = nrm
            out[n] = np.sqrt(best) if best >= 0 else -np.inf
    return run


def slice_farthest_unit(G, keep):
    """Largest ``||G_S p||`` over ``|p|∞ <= 1`` with ``G_{S^c} p = 0`` (eq. (16) after the
    slice of eq. (14)), for slices that remove exactly three coordinates.

    Parameters
    ----------
    G : ndarray (N, d, L)
        Generator matrices (e.g. J# or Jᵀ of eqs. (5)-(6)), L >= 3.
    keep : sequence of int
        The d − 3 kept output coordinates S (e.g. (0, 1, 2): translation at zero
        rotation).

    Returns
    -------
    ndarray (N,)
        In the output unit per unit actuator quantity; −inf for an empty slice.
    """
    G = np.ascontiguousarray(G, dtype=float)
    N, d, L = G.shape
    S = np.array(sorted(int(k) for k in keep), dtype=np.int64)
    Sc = np.array([i for i in range(d) if i not in set(S.tolist())], dtype=np.int64)
    if len(Sc) != 3:
        raise ValueError(f"expected a slice removing 3 of {d} coordinates, got keep={list(keep)}")
    F, X, flips = _tables(L, 3)
    out = np.empty(N)
    if N:
        _kernel()(G, S, Sc, F, X, flips, out)
    return out
