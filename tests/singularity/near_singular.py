"""Leg sets on the singular locus, for the tests of tests/singularity: P6 moved along a
direction to a sign change of det Jhat, bisected to the last float of the path."""

from __future__ import annotations

import numpy as np

from distkin.singularity import jacobian_det, octahedral_joints

__all__ = ["moved", "bisected_sign_change"]


def moved(pts, d, t):
    """``pts`` (6, 3) with P6 moved by ``t d``."""
    q = pts.copy()
    q[5] = pts[5] + t * d
    return q


def bisected_sign_change(pts, d, steps: int = 60):
    """The parameter ``t`` in [-3, 3] (the left end of a bracket bisected ``steps``
    times) where det Jhat of :func:`moved` changes sign, or None when the 61-point
    grid shows no sign change."""
    def f(t):
        return jacobian_det(*octahedral_joints(moved(pts, d, t)), normalised=False,
                            warn=False)
    ts = np.linspace(-3, 3, 61)
    vs = np.array([f(t) for t in ts])
    ch = np.flatnonzero(np.sign(vs[:-1]) * np.sign(vs[1:]) < 0)
    if not ch.size:
        return None
    lo, hi = ts[ch[0]], ts[ch[0] + 1]
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if np.sign(f(mid)) == np.sign(f(lo)) else (lo, mid)
    return lo
