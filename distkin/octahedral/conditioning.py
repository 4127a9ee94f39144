r"""A conditioning estimate for the fast tier's real-root count of the octic.

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III:
the assembly modes are the real roots of the octic :math:`O(s_{15})` inside the feasible
interval :math:`[lo, hi]` of the triangle inequalities through :math:`P_1P_5`
(:func:`~.closure.feasible_interval`).  The fast tier finds them in float64; a real-root
count is only as good as the octic's sign pattern is above its rounding error.

The estimate works on the octic in its factored form :math:`H = G^2 - 4R_1R_2`
(:func:`.fast_single.factored_grid`; eq. (3) squared twice, :mod:`.octic`), which the
fast tier polishes with, not on the monomial coefficients (those carry errors of up to :math:`10^7\epsilon`
relative from cancellation in the coefficient map, and a normwise model built on them
distrusted one easy problem in five):

* **error of H at a point** :math:`x`: the kernel is evaluated again at the squared
  lengths perturbed by :math:`\pm 4\epsilon` relative (two sign patterns,
  :func:`kernel_data`), and :math:`e(x) = K\,(\max|H' (x) - H(x)| + \epsilon S(x))`
  with :math:`S = G^2 + 4|R_1R_2|` and :math:`K` = :data:`K_NOISE`.  Calibration: over
  600 random assembled octahedra at scales :math:`10^{-3}`-:math:`10^{3}` and the hard
  set (:mod:`.hardset`), at 9 747 points (roots and grid points of the feasible
  interval), the actual error of the float :math:`H` against the exact ``fmpq`` value
  for the same float inputs was at most 40 times the bracket (median 0.52; 99.9 % under
  18), so :math:`K = 400`.  Without the perturbation term the ratio reached
  :math:`2\times10^{10}`; with one sign pattern only, 3 600;
* **separators**: :math:`lo`, the midpoints between consecutive real roots found, and
  :math:`hi`.  The count is kept only if :math:`|H| > e` at every separator (no root can
  cross a separator or an end of the interval) and :math:`H` changes sign across every
  root found;
* **nearly real complex pairs** (companion-matrix eigenvalues with
  :math:`0 < |\mathrm{Im}| \le 0.05\,c` inside the interval): the extremum of
  :math:`H` there (one Newton step on :math:`H'`, value from the local quadratic model)
  and :math:`H` at 9 points across :math:`\mathrm{Re} \pm 2|\mathrm{Im}|` must stay
  farther from zero than :math:`e`, with one sign (unless a root found lies there) --
  else two real roots may be about to appear or merge (a fold: two assembly modes meet
  at a singular pose), or a multiple root (a flat pose) was spread by rounding into a
  cluster of complex eigenvalues;
* **missed roots**: a real eigenvalue inside the interval with no root found within
  :math:`10^{-4}c` means the polish lost it (two close roots).

It is an *estimate*, not a proof (the error bound is calibrated, and the eigenvalues
that locate the nearly real pairs are rounded); ``method="certified"`` is the proof.
On the hard set it flagged every problem the fast tier miscounted, and on the easy set
it distrusted 3 of 200 (see BENCHMARKS.md, ``python -m benchmarks accuracy``).  Cost:
three kernel evaluations and one evaluation of :math:`H` at a few dozen points
(compiled), and plain Python on a handful of numbers (the eigenvalues are the fast
tier's); ``python -m benchmarks octahedral`` times the default call, which includes it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from .._generated.octic_general import parts_scalar
from .fast_single import factored_grid, octic_array

__all__ = ["Conditioning", "estimate", "kernel_data", "K_NOISE", "EPS"]

EPS = float(np.finfo(float).eps)
#: safety factor on the measured noise of the factored octic (largest observed ratio 40,
#: times ten)
K_NOISE = 400.0
_PATTERNS = ((1, -1) * 6, (1, 1, -1, -1) * 3)
_SIGNS = np.array(_PATTERNS, dtype=float)
_parts = numba.njit(cache=True)(parts_scalar)
_NEAR_REAL = 0.05
_SPREAD_LIST = np.linspace(-2.0, 2.0, 9).tolist()
_TINY = float(np.finfo(float).tiny)
_POW = np.arange(8, -1, -1)
_SHIFT = np.eye(8, k=-1)
_MATCH = 1e-4  # a real eigenvalue farther than this (relative) from every found root


@dataclass(frozen=True)
class Conditioning:
    """What the fast tier can say about its own real-root count.

    Attributes
    ----------
    trusted : bool
        Every root that can matter is isolated from the others, from the real axis and
        from the ends of the feasible interval by more than its error radius.
    reason : str
        Why not (empty when trusted).
    root_condition : float
        Largest first-order error radius :math:`e(r)/|H'(r)|` of a real root found,
        relative to the root and divided by eps: about ``log10(root_condition)`` digits
        of :math:`s_{15}` are lost (a pessimistic bound).
    separation : float
        Smallest relative distance between two consecutive real roots found (inf if
        fewer than two).
    radius : float
        Largest first-order error radius of a real root, in the units of
        :math:`s_{15}` (squared length).
    """

    trusted: bool
    reason: str
    root_condition: float
    separation: float
    radius: float

    def as_dict(self) -> dict:
        return {"trusted": self.trusted, "reason": self.reason,
                "root_condition": self.root_condition, "separation": self.separation,
                "radius": self.radius}


def kernel_data(sides2, legs2, data=None):
    r"""Kernel outputs (3, 39): at the squared lengths ``sides2`` (s12 s13 s23 s45 s46
    s56) and ``legs2`` (s14 .. s16), and the quadratic parts (the first 30) at two
    perturbations of them by :math:`\pm 4\epsilon` relative (sign patterns
    :data:`_PATTERNS`; the octic's coefficients of those rows repeat row 0's).
    ``data``: the unperturbed output when already computed (the fast tier's).  The
    generated scalar kernels, compiled (:mod:`.fast_single`)."""
    s2 = np.array(sides2, dtype=float)
    l2 = np.array(legs2, dtype=float)
    d0 = octic_array(s2, l2) if data is None else np.asarray(data, dtype=float)
    return _perturbed(s2, l2, d0, _SIGNS, 4 * EPS)


@numba.njit(cache=True)
def _perturbed(s2, l2, d0, signs, h):
    out = np.empty((3, 39))
    out[0] = d0
    for r in range(2):
        p = _parts(s2 * (1 + signs[r, :6] * h), l2 * (1 + signs[r, 6:] * h))
        for i in range(30):
            out[r + 1, i] = p[i]
        out[r + 1, 30:] = d0[30:]
    return out


@numba.njit(cache=True)
def _bracket(data, x, k, eps):
    r"""H, H' of row 0 of ``data`` (3, 39) at the points x, and the error bracket
    :math:`e = K(\max_r |H_r - H_0| + \epsilon S_0)` (module docstring)."""
    H, dH, S = factored_grid(data, x)
    e = np.empty(x.size)
    for j in range(x.size):
        e[j] = k * (max(abs(H[1, j] - H[0, j]), abs(H[2, j] - H[0, j])) + eps * S[0, j])
    return H[0], dH[0], e


def estimate(data, lo, hi, roots, eigenvalues=None) -> Conditioning:
    r"""The conditioning estimate of the fast tier's real-root count (module doc).

    Parameters
    ----------
    data : (3, 39) float
        :func:`kernel_data`: the kernel outputs and two perturbations of them.
    lo, hi : float
        The feasible interval of :math:`s_{15}` (:func:`~.closure.feasible_interval`);
        ``lo > hi`` means the triangle inequalities already exclude every assembly.
    roots : sequence of float
        The real roots the fast tier found (every status).
    eigenvalues : sequence of complex, optional
        The 8 roots of the octic as eigenvalues of its companion matrix, when the fast
        tier has them; computed here otherwise.

    Returns
    -------
    Conditioning
    """
    lo, hi = float(lo), float(hi)
    c = max(abs(lo), abs(hi), _TINY)
    if lo > hi:
        gap = (lo - hi) / c
        if gap > K_NOISE * EPS:
            return Conditioning(True, "", 1.0, np.inf, 0.0)
        return Conditioning(False, f"the triangle bounds of s15 miss each other by only "
                            f"{gap:.2g} relative: at the edge of assemblability",
                            np.inf, gap, np.inf)
    data = np.ascontiguousarray(data, dtype=float)
    # (the logic below runs on a handful of numbers: plain Python, one numpy evaluation)
    real = sorted(float(r) for r in roots if lo <= r <= hi)
    coef = data[0, 30:].tolist()
    scaled = [a * c ** (8 - k) for k, a in enumerate(coef)]
    if not abs(scaled[0]) > 1e-12 * max(map(abs, scaled)):
        return Conditioning(False, "the octic's leading coefficient vanishes at rounding "
                            "level: roots near infinity", np.inf, 0.0, np.inf)
    if eigenvalues is None or len(eigenvalues) != 8:
        comp = _SHIFT.copy()
        comp[0] = [-a / scaled[0] for a in scaled[1:]]
        eigenvalues = (np.linalg.eigvals(comp) * c).tolist()
    cand, width = [], []
    for z in eigenvalues:
        zr, zi = z.real, z.imag
        if not lo <= zr <= hi:
            continue
        if zi == 0:
            # a real eigenvalue that no root found is near: the polish lost it
            if not real or min(abs(r - zr) for r in real) > _MATCH * c:
                return Conditioning(False, f"the octic's eigenvalues show a real root near "
                                    f"s15 = {zr:.6g} that the fast tier's polish did not "
                                    "keep (two close roots, or a wandering Newton start)",
                                    np.inf, 0.0, np.inf)
        elif 0 < zi <= _NEAR_REAL * c:           # candidate extremum: a nearly real pair
            cand.append(zr)
            width.append(zi)
    nr, nc = len(real), len(cand)
    ns = nr + 1
    seps = [lo] + [0.5 * (a + b) for a, b in zip(real, real[1:])] + [hi]
    hstep = 1e-7 * c
    # the octic is also sampled across each pair's extent Re ± 2 |Im|: rounding of the
    # monomial coefficients spreads a multiple root into a cluster of that size
    spread = [x + w * f for x, w in zip(cand, width) for f in _SPREAD_LIST]
    pts = (seps + cand + real + [x + hstep for x in cand] + [x - hstep for x in cand]
           + spread)
    h, dh, e = _bracket(data, np.array(pts), K_NOISE, EPS)
    h, dh, e = h.tolist(), dh.tolist(), e.tolist()
    for k in range(nc):
        # one Newton step on H' towards the extremum near each nearly real pair, and the
        # value there from the local quadratic model: H(x*) ~ H - H'^2 / (2 H'')
        m = ns + nc + nr + k
        d2 = (dh[m] - dh[m + nc]) / (2 * hstep)
        j = ns + k
        if d2 != 0:
            drop = dh[j] * dh[j] / (2 * d2)
            if math.isfinite(drop) and abs(drop) <= abs(h[j]):
                h[j] -= drop
    reason = ""
    for k in range(ns):
        if abs(h[k]) <= e[k]:
            what = ("the feasible interval's lo end" if k == 0 else
                    "the feasible interval's hi end" if k == ns - 1 else
                    f"the point between the roots {real[k - 1]:.6g} and {real[k]:.6g}")
            reason = (f"the octic at {what} (s15 = {seps[k]:.6g}) is within its rounding "
                      f"error ({abs(h[k]):.2g} <= {e[k]:.2g}): "
                      + ("a root at the edge of the feasible interval" if k in (0, ns - 1)
                         else "a near-double root (two assembly modes merging)"))
            break
    n9 = len(_SPREAD_LIST)
    for k in range(nc):
        if reason:
            break
        j = ns + k
        m = ns + 3 * nc + nr + n9 * k
        hs, es = h[m:m + n9], e[m:m + n9]
        near_zero = abs(h[j]) <= e[j] or any(abs(a) <= b for a, b in zip(hs, es))
        a, b = cand[k] - 2 * width[k], cand[k] + 2 * width[k]
        flips = any((v > 0) != (hs[0] > 0) for v in hs[1:])
        if near_zero or (flips and not any(a <= r <= b for r in real)):
            reason = (f"near s15 = {cand[k]:.6g} the octic comes within its rounding error "
                      "of zero or changes sign between roots: two real roots about to "
                      "appear or merge, or a multiple root spread by rounding")
    if not reason and any((h[k] > 0) == (h[k + 1] > 0) for k in range(ns - 1)):
        reason = ("the octic does not change sign across every root found: a root of even "
                  "multiplicity, or a root missed")
    # root radii (first order) and the separation
    rr = [e[ns + nc + k] / max(abs(dh[ns + nc + k]), _TINY) for k in range(nr)]
    radius = max(rr, default=0.0)
    cond = max((r / max(abs(x), _TINY) for r, x in zip(rr, real)), default=EPS) / EPS
    sep = min(((b - a) / max(abs(b), _TINY) for a, b in zip(real, real[1:])), default=np.inf)
    return Conditioning(not reason, reason, cond, sep, radius)
