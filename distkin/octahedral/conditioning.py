r"""What the fast tier can say about its own answer: proved, or a warning.

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III.
Every fast solve (single and batched) is checked by :func:`.descartes.vouch`: a proof,
in float64 with rigorous rounding bounds, that its assembly roots of the octic are, one
to one, those of the exact problem (the argument is in :mod:`.descartes`).  When the
proof goes through, the result is *trusted* and each root in the feasible interval has
a proved radius.  When it does not, the fast tier says so: a single solve emits a
:class:`~distkin.errors.ConditioningWarning`, the batched tier flags the problem
(``BatchResult.trusted``), and ``method="auto"`` solves it again with the certified
tier (:mod:`.auto`).

"Not trusted" does not mean wrong: on the easy set of :mod:`.hardset` every answer is
proved, near a fold or a flat pose most are not (float64 cannot separate the roots
there); BENCHMARKS.md (``python -m benchmarks accuracy``) gives the rates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numba
import numpy as np

from .descartes import ETA_FLOAT, VERDICTS, eta_rounded, vouch, vouch_buffer, vouch_rows

__all__ = ["Conditioning", "assess", "assess_buffer", "eta_of", "from_verdict",
           "vouch_tight_row"]

_EPS = float(np.finfo(float).eps)


@dataclass(frozen=True)
class Conditioning:
    """The fast tier's proof of its real-root count, or why there is none.

    Attributes
    ----------
    trusted : bool
        Proved: the assembly roots (and so the poses, two per root) are exactly those
        of the exact problem (:mod:`.descartes`).
    reason : str
        Why not (empty when trusted).
    root_condition : float
        Largest proved radius of a root (``root_radii``), relative to the root,
        divided by eps (about ``log10(root_condition)`` digits of s15 are not proved);
        inf when not trusted.
    separation : float
        Smallest relative distance between two consecutive real roots found (inf if
        fewer than two).
    root_radii : tuple of float
        The proved radius of each real root found, in the order of the result's
        ``roots`` (inf where the proof gives none); empty when not trusted.  A root
        outside the feasible interval (spurious, no pose) has one where the signs
        around it are proved (step 8 of :mod:`.descartes`): a real root of the exact
        octic lies within it, though their count there is float64's.  The result's
        :class:`~.result.RootInfo`
        takes these as its ``radius`` (``radius_kind`` "proved"): tight, a bounded
        evaluation at each side of the root, in the single solve and in a batched
        ``result(i)`` alike (the batched proof's own radii, ``BatchResult.raw["radii"]``,
        are the pieces of its subdivision: looser, see :func:`.descartes.vouch_many`).
    radius : float (property)
        The largest of ``root_radii``, in the units of :math:`s_{15}` (squared length);
        0 when no root has one, inf when not trusted.
    """

    trusted: bool
    reason: str
    root_condition: float
    separation: float
    root_radii: tuple = ()

    @property
    def radius(self) -> float:
        if not self.trusted:
            return np.inf
        return max((r for r in self.root_radii if r < np.inf), default=0.0)

    def scaled(self, k: int) -> "Conditioning":
        """The same proof for the lengths multiplied by ``2**k`` (s15 by ``4**k``,
        exactly; the relative fields do not change)."""
        return replace(self, root_radii=tuple(math.ldexp(r, 2 * k) for r in self.root_radii))

    def as_dict(self) -> dict:
        return {"trusted": self.trusted, "reason": self.reason,
                "root_condition": self.root_condition, "separation": self.separation,
                "radius": self.radius, "root_radii": list(self.root_radii)}


def eta_of(B, Q, L, rounded: bool) -> float:
    """The relative error bound of the squared lengths the fast tier computes from
    ``B``, ``Q``, ``L`` (normalised floats): :data:`.descartes.ETA_FLOAT` for exact
    float inputs, :func:`.descartes.eta_rounded` when the inputs were rounded."""
    if not rounded:
        return ETA_FLOAT
    return float(eta_rounded(np.asarray(B, dtype=float), np.asarray(Q, dtype=float),
                             np.asarray(L, dtype=float)))


def assess(sides2, legs2, data, lo, hi, roots, eta) -> Conditioning:
    """The verdict of :func:`.descartes.vouch` on one fast solve, as a
    :class:`Conditioning`.

    Parameters
    ----------
    sides2, legs2 : (6,) float squared lengths the kernel ran on; ``data`` (39,) its
        output; ``lo``, ``hi`` the float triangle bounds of s15
    roots : (n, 3) rows (s15, step, status code) of
        :func:`.single.solve_fast_single`
    eta : relative error bound of the squared lengths (:func:`eta_of`)
    """
    return _conditioning(*vouch_rows(data, sides2, legs2, eta, lo, hi, roots))


def assess_buffer(buf, nr, lo, hi, eta) -> Conditioning:
    """:func:`assess` on the buffer of the single solve (:func:`.batched.scan_single`:
    its ``nr`` root rows, squared lengths and kernel output)."""
    return _conditioning(*vouch_buffer(buf, nr, eta, lo, hi))


def _conditioning(v, sep, radius, rel, radii):
    if v:
        return Conditioning(False, VERDICTS[v], np.inf, sep)
    return Conditioning(True, "", rel / _EPS if radius else 1.0, sep, tuple(radii.tolist()))


def from_verdict(verdict: int, x, radii) -> Conditioning:
    """The :class:`Conditioning` of a verdict of :func:`.descartes.vouch` on the roots
    ``x`` (increasing) with their proved ``radii`` (inf where none)."""
    x = np.asarray(x, dtype=float)
    sep = min(((b - a) / max(abs(b), 1e-300) for a, b in zip(x.tolist(), x[1:].tolist())),
              default=np.inf)
    if verdict:
        return Conditioning(False, VERDICTS[verdict], np.inf, float(sep))
    radii = np.asarray(radii, dtype=float)
    each = tuple(radii.tolist())
    ok = np.isfinite(radii)
    if not ok.any():
        return Conditioning(True, "", 1.0, float(sep), each)
    rel = radii[ok] / np.maximum(np.abs(x[ok]), 1e-300)
    return Conditioning(True, "", float(rel.max()) / _EPS, float(sep), each)


@numba.njit(cache=True)
def vouch_tight_row(data, s2, l2, eta, lo, hi, roots, status, exponent, i, n, radii):
    """:func:`.descartes.vouch` with tight radii (the single solve's) on problem ``i``
    of the batched arrays of :func:`.descartes.vouch_many`, whose ``roots``, ``lo``,
    ``hi`` are scaled back by ``4**exponent[i]`` (:mod:`.scaling`): its ``n`` roots
    scaled down again (exactly: a power of two), proved, and the ``radii`` (n,) scaled
    back.  Returns the verdict,
    or -1 where the scaling does not go back exactly (a scaled-back root or bound
    subnormal, or a factor beyond float64): the batched radii then stand."""
    e = -2 * exponent[i]
    if e > 1000 or e < -1000:
        return -1
    f = 2.0 ** e
    x = np.empty(n)
    codes = np.empty(n, np.int64)
    for k in range(n):
        x[k] = roots[i, k] * f
        codes[k] = status[i, k]
        if x[k] / f != roots[i, k]:
            return -1
    a, b = lo[i] * f, hi[i] * f
    if a / f != lo[i] or b / f != hi[i]:
        return -1
    v = vouch(data[i], s2[i], l2[i], eta[i], a, b, x, codes, radii)
    for k in range(n):
        radii[k] = radii[k] / f
    return v
