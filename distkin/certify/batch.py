r"""Branch-and-prune on batches of boxes: the ``quadratic64`` form.

The verdicts of :mod:`.boxes` (regular, singular, unreachable, undecided; the same
certificates, see there) for many boxes at once: the reach margins, ``Jq`` and ``Jx``
are enclosed by second-order Taylor models with binary64 coefficients
(:class:`.fptaylor.Quadratics`, every rounding error in the remainder), and the
preconditioned rank test of :func:`.boxes.regularity_certificate` is evaluated in numpy
with every bound rounded outwards:

.. math:: B = |I - Y J_0| + \sum_k |Y T_k| + |Y| e

is bounded above entrywise by ``|fl(I - Y J0)| + Σ|fl(Y T_k)| + G (I + |Y||J0| +
|Y| Σ|T_k|) + |Y| e``: a dot product of length ``n <= 9`` computed in floating point (in
any order, with or without fused multiply-adds) is within ``γ_n`` times the dot product
of the magnitudes of the exact one, plus ``n 2^-1075`` of underflow (Higham 2002,
eq. (3.5)), and ``G = 2^-48 >= γ_16``.  That bound, ``B v`` for the float Perron
vector ``v``, the ratios ``(B v)_i / v_i`` and the σmin bound are all expressions of
``+ ×`` on non-negative doubles (and one division, one square root) with at most 64
roundings on any path; each is computed to nearest and then multiplied by
``1 + 2^-40 >= (1 + u)^64`` and rounded up (R1 of :mod:`.fptaylor`), with ``2^-400``
added for the underflow losses (at most a few hundred products of inputs below
``2^150`` in magnitude: ``|Y| <= 2^100`` is required, the models' coefficients are
checked the same way).  So ``B v < v`` in doubles proves ``ρ(|I - Y Jx|) < 1`` for every
``Jx`` of the box, as in :mod:`.boxes`.

For L = 6 the sign of ``det Jx`` over a regular box is the sign of ``det Y`` (certified
in arb): every eigenvalue ``λ`` of ``Y Jx`` has ``|1 - λ| < 1``, so the real ones are
positive, the others come in conjugate pairs, and ``det(Y) det(Jx) = Π λ > 0``.

The binary64 models have no Chebyshev enclosure of ``sqrt`` and ``1/x``
(:mod:`.linearize`); near a leg's reach limit they certify smaller boxes than
``quadratic``.  So a box they leave undecided at the resolution is classified once more
by :func:`.boxes.certify_box` with the arb ``quadratic`` form (which also tries the
singular certificate there, L = 6): the verdicts at the resolution are those of the arb
route, the binary64 models only decide earlier.
"""

from __future__ import annotations

import time

import numpy as np

from ..argcheck import positive_int
from ..errors import InputError
from .boxes import (REASONS, REGULAR, UNDECIDED, UNREACHABLE, Verdict, _certify_box, bisect,
                    check_box, check_mechanism, check_resolution, finite_rows, leaves,
                    perron_vectors, split_dimension)
from .fptaylor import TINY, Quadratics, as_models, down, sum_up, up, variables
from .intervals import margins

__all__ = ["certify_batch", "branch_and_prune_batched", "rank_bounds"]

_SAFE = 1.0 + 2.0 ** -40
_YMAX = 2.0 ** 100


def _safe(x):
    """An upper bound of a non-negative expression computed to nearest (module doc)."""
    return up(up(x * _SAFE) + TINY)


def _inputs(lo, hi, vary):
    """The pose coordinates over the boxes as models (varying) or constants."""
    with np.errstate(invalid="ignore"):
        mid = np.clip(lo + 0.5 * (hi - lo), lo, hi)
    v = list(vary)
    half = np.maximum(up(hi[:, v] - mid[:, v]), up(mid[:, v] - lo[:, v]))
    models = variables(mid[:, v], half)
    B, n = len(lo), len(v)
    out = []
    for k in range(6):
        if k in vary:
            out.append(models[v.index(k)])
        else:
            out.append(Quadratics(lo[:, k].copy(), np.zeros((B, n)), np.zeros((B, n, n)),
                                  np.zeros(B)))
    return mid, out


def _stack(models, like):
    """Rows of kernel outputs (lists of models or numbers) as arrays c, a, q, e with the
    entries' shape in front of the batch: c (B, *s), a (B, *s, n), q (B, *s, n, n)."""
    flat = [as_models(g, like) for g in models]
    c = np.stack([m.c for m in flat], axis=1)
    a = np.stack([m.a for m in flat], axis=1)
    q = np.stack([m.q for m in flat], axis=1)
    e = np.stack([m.e for m in flat], axis=1)
    return c, a, q, e


def rank_bounds(Y, C, A, Q, E):
    """The preconditioned rank test over batches of Jx enclosures (module docstring).

    Parameters
    ----------
    Y : ndarray (B, 6, L)
        Float preconditioners.
    C, A, Q, E : ndarray (B, L, 6), (B, L, 6, n), (B, L, 6, n, n), (B, L, 6)
        ``Jx`` entries as quadratic models ``C + A ε + εᵀ Q ε ± E``.

    Returns
    -------
    ok : ndarray (B,) bool
        ``ρ(|I - Y Jx|) < 1`` certified for every Jx of the box.
    contraction : ndarray (B,)
        Upper bound of ``max_i (B v)_i / v_i`` (inf where not finite).
    sigma : ndarray (B,)
        Certified lower bound of σmin(Jx) (0 where not ok).
    weights : ndarray (B, n)
        Per box coordinate, the share of ``Σ|Y T_k|`` of its terms (floats, for the
        choice of the coordinate to split).
    """
    Bn, L, _, n = A.shape
    with np.errstate(all="ignore"):
        diag = np.diagonal(Q, axis1=3, axis2=4)                  # (B, L, 6, n)
        J0 = C + 0.5 * diag.sum(axis=-1)
        # rounding of J0 (R3): at most n + 1 terms
        E0 = _safe(E + 2.0 ** -48 * (np.abs(C) + 0.5 * np.abs(diag).sum(axis=-1)))
        iu = np.triu_indices(n, 1)
        T = np.concatenate([A, 0.5 * diag, 2.0 * Q[..., iu[0], iu[1]]], axis=-1)
        T = np.moveaxis(T, -1, 1)                                # (B, nT, L, 6)
        aY = np.abs(Y)
        P = np.einsum("bil,btlj->btij", Y, T)                    # (B, nT, 6, 6)
        absP = np.abs(P)
        R = np.eye(6) - np.einsum("bil,blj->bij", Y, J0)
        sumT = np.abs(T).sum(axis=1)                             # (B, L, 6)
        rnd = 2.0 ** -48 * (np.eye(6) + np.einsum("bil,blj->bij", aY, np.abs(J0) + sumT))
        Bm = _safe(np.abs(R) + absP.sum(axis=1) + rnd + np.einsum("bil,blj->bij", aY, E0))
        good = np.all(np.isfinite(Bm), axis=(1, 2)) & np.all(aY <= _YMAX, axis=(1, 2))
        Bm = np.where(good[:, None, None], Bm, 1.0)
        # weights per coordinate: linear and diagonal terms to their coordinate, mixed
        # terms half to each
        tw = absP.sum(axis=(2, 3))                               # (B, nT)
        w = tw[:, :n] + tw[:, n:2 * n]
        for t, (k, l) in enumerate(zip(*iu)):
            w[:, k] += 0.5 * tw[:, 2 * n + t]
            w[:, l] += 0.5 * tw[:, 2 * n + t]
        v = perron_vectors(Bm)
        Bv = _safe(np.einsum("bij,bj->bi", Bm, v))
        ratios = up(Bv / v)
        cmax = ratios.max(axis=1)
        ok = good & np.all(ratios < 1.0, axis=1)
        contraction = np.where(good & np.isfinite(cmax), cmax, np.inf)
        t = up(aY / v[:, :, None])
        rn = up(np.sqrt(_safe((t * t).sum(axis=2)))).max(axis=1)
        denom = _safe(up(np.sqrt(6.0)) * v.max(axis=1) * rn)
        sigma = np.where(ok, np.maximum(0.0, down(down(1.0 - cmax) / denom)), 0.0)
    return ok, contraction, sigma, w


def _det_sign(Y) -> int:
    from flint import arb_mat
    d = arb_mat(Y.tolist()).det()
    return 1 if d > 0 else (-1 if d < 0 else 0)


def certify_batch(mech, kernels, lo, hi, vary):
    """Verdicts of :func:`.boxes.certify_box` (form ``quadratic64``) for a batch.

    Parameters
    ----------
    mech : RSSMechanism
    kernels : KernelSet
        ``mech.kernels("arb")`` (run on :class:`.fptaylor.Quadratics`).
    lo, hi : ndarray (B, 6)
        Boxes (m, rad), ``lo <= hi`` (no NaN), of zero width outside ``vary`` (checked:
        :class:`~distkin.errors.InputError`, a ``ValueError``).
    vary : tuple of int

    Returns
    -------
    dict of ndarray (B,)
        ``status`` (int8), ``sigma``, ``det_sign`` (int8), ``reason`` (object:
        "reach", "jq", "rank" or ""), ``contraction``; and ``weights`` (B, n).
    """
    lo = np.asarray(lo, dtype=float)
    hi = np.asarray(hi, dtype=float)
    fixed = [k for k in range(6) if k not in vary]
    if lo.ndim != 2 or lo.shape[1:] != (6,) or hi.shape != lo.shape:
        raise InputError(f"expected boxes lo, hi of shape (B, 6), got {lo.shape} and "
                         f"{hi.shape}", field="hi")
    bad = ~np.all(lo <= hi, axis=1) | np.any(lo[:, fixed] != hi[:, fixed], axis=1)
    if bad.any():
        i = int(np.argmax(bad))
        raise InputError(f"expected boxes with lo <= hi and zero width outside the "
                         f"coordinates {tuple(vary)}, got box {i}: lo = {lo[i].tolist()!r}, "
                         f"hi = {hi[i].tolist()!r}", field="hi")
    with np.errstate(all="ignore"):       # nan and inf remainders certify nothing
        return _certify_batch(mech, kernels, lo, hi, vary)


def _certify_batch(mech, kernels, lo, hi, vary):
    Bn, n = len(lo), len(vary)
    status = np.full(Bn, UNDECIDED, dtype=np.int8)
    sigma = np.zeros(Bn)
    dsign = np.zeros(Bn, dtype=np.int8)
    reason = np.full(Bn, "", dtype=object)
    contraction = np.full(Bn, np.inf)
    weights = np.zeros((Bn, n))
    mid, X = _inputs(lo, hi, vary)
    rc, ra, rq, re = _stack(margins(kernels, X), X[0])
    rmod = Quadratics(rc.reshape(-1), ra.reshape(-1, n), rq.reshape(-1, n, n), re.reshape(-1))
    rlo, rhi = (b.reshape(Bn, -1) for b in rmod.bounds())
    unreach = np.any(rhi < 0, axis=1)
    closed = np.all(rlo > 0, axis=1) & ~unreach
    status[unreach] = UNREACHABLE
    open_ = ~unreach & ~closed
    reason[open_] = "reach"
    opened = (rlo <= 0) | ~np.isfinite(rlo)
    weights[open_] = np.einsum("bl,bln->bn", opened[open_].astype(float),
                               finite_rows(np.abs(ra[open_])))
    idx = np.flatnonzero(closed)
    if idx.size == 0:
        return dict(status=status, sigma=sigma, det_sign=dsign, reason=reason,
                    contraction=contraction, weights=weights)
    Xs = [m.take(idx) for m in X]
    rows = kernels.jq_jx(Xs)
    flat = [g for row in rows for g in row]
    c, a, q, e = _stack(flat, Xs[0])
    L = mech.L
    c, a, q, e = (x.reshape((len(idx), L, 7) + x.shape[2:]) for x in (c, a, q, e))
    jq = Quadratics(c[:, :, 0].reshape(-1), a[:, :, 0].reshape(-1, n),
                    q[:, :, 0].reshape(-1, n, n), e[:, :, 0].reshape(-1))
    qlo, qhi = (b.reshape(len(idx), L) for b in jq.bounds())
    jq_ok = np.all((qlo > 0) | (qhi < 0), axis=1)
    reason[idx[~jq_ok]] = "jq"
    sel = idx[jq_ok]
    if sel.size == 0:
        return dict(status=status, sigma=sigma, det_sign=dsign, reason=reason,
                    contraction=contraction, weights=weights)
    c, a, q, e = (x[jq_ok][:, :, 1:] for x in (c, a, q, e))
    _, Jxm = mech.jq_jx(mid[sel])
    fin = np.all(np.isfinite(Jxm), axis=(1, 2))
    Y = np.zeros((len(sel), 6, L))
    if fin.any():
        Y[fin] = np.linalg.pinv(Jxm[fin])
    ok, contr, sig, w = rank_bounds(Y, c, a, q, e)
    contraction[sel] = contr
    weights[sel] = w
    status[sel[ok]] = REGULAR
    sigma[sel[ok]] = sig[ok]
    reason[sel[~ok]] = "rank"
    if L == 6:
        for j in np.flatnonzero(ok):
            dsign[sel[j]] = _det_sign(Y[j])
    return dict(status=status, sigma=sigma, det_sign=dsign, reason=reason,
                contraction=contraction, weights=weights)


def branch_and_prune_batched(mech, lo, hi, min_width, *, max_boxes: int = 200_000,
                             batch: int = 256) -> dict:
    """:func:`.boxes.branch_and_prune` with the ``quadratic64`` form: boxes are taken
    from the stack ``batch`` at a time (256) and evaluated together (:func:`certify_batch`).
    Same arguments, checks and result."""
    t0 = time.perf_counter()
    check_mechanism(mech)
    lo, hi = check_box(lo, hi)
    minw = check_resolution(min_width)
    max_boxes = positive_int(max_boxes, "max_boxes")
    batch = positive_int(batch, "batch")
    ks = mech.kernels("arb")
    vary = tuple(k for k in range(6) if hi[k] > lo[k])
    stack = [(lo, hi)]
    out_lo, out_hi, status, sigma, dsign, why = [], [], [], [], [], []
    budget = []                          # indices of the leaves left by the budget
    evaluated = 0

    def leaf(blo, bhi, st, sg=0.0, ds=0, reason=""):
        out_lo.append(blo)
        out_hi.append(bhi)
        status.append(st)
        sigma.append(sg)
        dsign.append(ds)
        why.append(REASONS.get(reason, 0) if st == UNDECIDED else 0)

    while stack:
        room = max_boxes - evaluated
        if room <= 0:
            for blo, bhi in stack:
                budget.append(len(status))
                leaf(blo, bhi, UNDECIDED)
            break
        take = min(batch, room, len(stack))
        todo = stack[-take:]
        del stack[-take:]
        blo = np.array([b[0] for b in todo])
        bhi = np.array([b[1] for b in todo])
        if not vary:
            for a, b in todo:
                v = _certify_box(mech, ks, a, b, form="quadratic", at_resolution=True)
                leaf(a, b, v.status, v.sigma_lower, v.det_sign, v.reason)
            evaluated += take
            continue
        r = certify_batch(mech, ks, blo, bhi, vary)
        evaluated += take
        for i in range(take - 1, -1, -1):
            a, b = todo[i]
            st = int(r["status"][i])
            if st != UNDECIDED:
                leaf(a, b, st, float(r["sigma"][i]), int(r["det_sign"][i]))
                continue
            v = Verdict(UNDECIDED, reason=r["reason"][i], vary=vary,
                        weights=tuple(r["weights"][i].tolist()))
            k = split_dimension(a, b, minw, v)
            if k is None:                # at the resolution: the arb route decides
                v = _certify_box(mech, ks, a, b, form="quadratic", at_resolution=True)
                leaf(a, b, v.status, v.sigma_lower, v.det_sign, v.reason)
                continue
            left, right = bisect(a, b, k)
            stack.append(right)
            stack.append(left)
    return leaves(out_lo, out_hi, status, sigma, dsign, evaluated, t0, budget, why)
