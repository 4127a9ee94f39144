r"""A sharper certified lower bound of σmin(Jx) over a certified-regular region.

Branch-and-prune (:mod:`.boxes`, :mod:`.batch`) stops splitting a box as soon as the
preconditioned rank test proves it regular, and the σmin bound that test gives,

.. math:: \sigma_{\min}(J_x) \ge \frac{1 - c}{\sqrt{6}\,\max_i v_i\,
          \max_i \lVert \mathrm{row}_i(\mathrm{diag}(v)^{-1} Y)\rVert_2}

(:func:`.boxes.regularity_certificate`), falls to zero as the contraction bound
:math:`c` of the box nears 1.  The region's bound is the minimum over its regular boxes,
so a few boxes certified with :math:`c` just below 1 make it useless as a design figure
(the Octo's 150 mm cube × ±20°: 1.2e-7 against a sampled minimum of 0.024).

Here the boxes with the weakest bounds are bisected, weakest first, and their halves
certified again (:func:`.batch.certify_batch`, the ``quadratic64`` form): a half is a
subset of its box, so its bound is the larger of its own (when the half is certified
regular) and its box's.  The region's bound -- the minimum over the current boxes -- can
only rise, and every value it takes is certified.  The loop stops at a budget of box
evaluations or when the bound has risen by less than 1 % over four rounds.
"""

from __future__ import annotations

import heapq
import time
from dataclasses import dataclass

import numpy as np

from .batch import certify_batch
from .boxes import REGULAR, bisect

__all__ = ["SigmaBound", "tighten_sigma"]


@dataclass(frozen=True)
class SigmaBound:
    """The result of :func:`tighten_sigma`.

    Attributes
    ----------
    value : float
        Certified lower bound of σmin(Jx) over the union of the boxes given (Jx is
        L x 6: its first three columns (force) dimensionless, its last three (moment)
        in m).
    initial : float
        The minimum of the boxes' own bounds (before).
    evaluated : int
        Boxes certified (halves).
    seconds : float
        Wall time.
    lo, hi, sigma : ndarray
        The final boxes (n, 6) and their bounds (n,): they cover the boxes given.
    """

    value: float
    initial: float
    evaluated: int
    seconds: float
    lo: np.ndarray
    hi: np.ndarray
    sigma: np.ndarray


def tighten_sigma(mech, lo, hi, sigma, *, scale=None, budget: int = 4096,
                  batch: int = 256, stall_rounds: int = 4) -> SigmaBound:
    """Raise the certified σmin bound of certified-regular boxes by bisecting the weakest.

    Parameters
    ----------
    mech : RSSMechanism or LegMechanism
    lo, hi : array (n, 6)
        Boxes certified regular (m, rad), of zero width outside the varying coordinates.
    sigma : array (n,)
        Their certified σmin bounds.
    scale : array (6,) or None
        Widths against which a box's coordinates are compared to choose the one to
        bisect (the widest relative to it); default the extent of the boxes' union.
    budget : int
        At most this many boxes certified (0: return the bounds as given).
    batch : int
        Boxes certified per call (the weakest ``batch // 2`` are bisected each round).
    stall_rounds : int
        Stop when the bound rose by less than 1 % over this many rounds.

    Returns
    -------
    SigmaBound
    """
    t0 = time.perf_counter()
    lo = np.asarray(lo, dtype=float).reshape(-1, 6)
    hi = np.asarray(hi, dtype=float).reshape(-1, 6)
    sigma = np.asarray(sigma, dtype=float).reshape(-1)
    if len(sigma) == 0:
        return SigmaBound(0.0, 0.0, 0, 0.0, lo, hi, sigma)
    vary = tuple(k for k in range(6) if np.any(hi[:, k] > lo[:, k]))
    if scale is None:
        scale = hi.max(axis=0) - lo.min(axis=0)
    scale = np.where(np.asarray(scale, dtype=float) > 0, scale, 1.0)
    boxes = [(lo[i], hi[i]) for i in range(len(sigma))]
    heap = [(float(s), i) for i, s in enumerate(sigma)]
    heapq.heapify(heap)
    initial = heap[0][0]
    history = [initial]
    evaluated = 0
    ks = mech.kernels("arb") if vary else None
    while vary and evaluated + 2 <= budget:
        take = min(batch // 2, (budget - evaluated) // 2, len(heap))
        picked = [heapq.heappop(heap) for _ in range(take)]
        blo, bhi, parent = [], [], []
        for s, i in picked:
            a, b = boxes[i]
            k = int(np.argmax(np.where(b > a, (b - a) / scale, -1.0)))
            for half in bisect(a, b, k):
                blo.append(half[0])
                bhi.append(half[1])
                parent.append(s)
        r = certify_batch(mech, ks, np.array(blo), np.array(bhi), vary)
        evaluated += len(blo)
        for j in range(len(blo)):
            own = float(r["sigma"][j]) if r["status"][j] == REGULAR else 0.0
            boxes.append((blo[j], bhi[j]))
            heapq.heappush(heap, (max(parent[j], own), len(boxes) - 1))
        history.append(heap[0][0])
        if len(history) > stall_rounds and \
                history[-1] < 1.01 * history[-1 - stall_rounds]:
            break
    live = [i for _, i in heap]
    return SigmaBound(heap[0][0], initial, evaluated, time.perf_counter() - t0,
                      np.array([boxes[i][0] for i in live]).reshape(-1, 6),
                      np.array([boxes[i][1] for i in live]).reshape(-1, 6),
                      np.array([s for s, _ in heap]))
