r"""Hard and easy sets of octahedral forward-kinematics problems, with certified truth.

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III
and VI.  The real-root count of the octic changes only where two real roots merge (a
fold: two assembly modes meet at a singular pose), where a root crosses an end of the
feasible interval (the edge of assemblability) or where a root turns spurious.  The hard
set puts problems at dyadic distances :math:`2^{-k}` (relative, on one leg) on both
sides of such places, found by bisection with the certified tier:

``fold``
    Griffis-Duffy legs (Sec. VI) with leg 5 varied between 15 and 15.5 (6 -> 4
    assembly modes), and random rational octahedra with one leg varied by up to ±30 %
    until the certified count changes;
``edge``
    all Griffis-Duffy legs scaled by :math:`\lambda \in [0.36, 0.38]`: no assembly
    below the edge, four poses above it;
``flat``
    a flat configuration (all six points in a plane, a root of multiplicity 4) with one
    leg perturbed by :math:`2^{-k}`;
``scale``
    fold problems scaled by :math:`10^{-3}` and :math:`10^{3}`.

:func:`hard_families` adds the families of issue 14, where float64 turns clusters of
real roots into complex pairs or drops one of two close roots (each at scales
:math:`10^{-3}`, 1 and :math:`10^{3}`):

``coplanar``
    the platform :math:`10^{-2} \ldots 10^{-6}` (and :math:`10^{-9} \ldots 10^{-14}`)
    of the base size above the base plane, tilted by :math:`10^{-2} \ldots 10^{-5}`
    rad (up to four real roots within 1e-7 of each other);
``line``
    a platform vertex :math:`10^{-4} \ldots 10^{-12}` of the base size from the line of
    a base edge it is joined to (P4 near P1P2, P5 near P2P3, P6 near P3P1);
``cluster``
    random octahedra (:func:`~.reference.random_octahedron`) whose octic has two
    eigenvalues within 1 % of each other over the feasible interval, kept when two of
    their certified real roots there lie within 1e-3 (relative) of each other.

Every datum is a float64 number taken as its exact binary value, so that every tier
solves *the same* problem; the truth (real roots of the octic, assembly modes) comes
from the certified tier on those exact values.  The easy set is random assembled
octahedra (:func:`~.reference.random_octahedron`) at scales :math:`10^{-3}`-:math:`10^{3}`.

Generation runs the certified tier a few hundred times (seconds); results are cached per
process.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..spatial import axis_angle
from .reference import random_triangle

__all__ = ["Case", "hard_set", "hard_families", "easy_set", "certified_truth",
           "near_coplanar", "near_line"]

_GD_BASE = ((0.0, 0.0, 0.0), (6.0, math.sqrt(108.0), 0.0), (12.0, 0.0, 0.0))
_GD_PLAT = ((0.0, 0.0, 0.0), (6.0, 0.0, 0.0), (3.0, math.sqrt(27.0), 0.0))
_GD_LEGS = (19.8, 18.0, 18.0, 17.0, 14.9, 17.8)


@dataclass(frozen=True)
class Case:
    """One forward-kinematics problem, all data float64 (exact binary values).

    Attributes
    ----------
    name : str
    family : {"fold", "edge", "flat", "scale", "easy"}
    base, platform : tuple (3, 3); legs : tuple (6,)
    distance : float
        Relative distance (on the varied leg) to the place where the count changes;
        0 for the easy set; the height, the distance to the line or the root gap
        (relative) for the families of :func:`hard_families`.
    real_roots : int
        Certified number of distinct real roots of the octic.
    modes : int
        Certified number of assembly modes (poses = 2 x modes, except flat ones).
    poses : int
        Certified number of poses.
    """

    name: str
    family: str
    base: tuple
    platform: tuple
    legs: tuple
    distance: float
    real_roots: int
    modes: int
    poses: int


def certified_truth(base, platform, legs, tol=1e-6):
    """(real roots, assembly modes, poses) of the certified tier on the exact floats
    (``tol``: the pose enclosures' refinement, which does not affect the counts)."""
    from .forward import forward_kinematics
    res = forward_kinematics(base, platform, list(legs), method="certified", tol=tol)
    return res.real_root_count, len(res.assembly_roots), len(res)


def _modes(base, platform, legs):
    return certified_truth(base, platform, legs, tol=1e-3)[1]


def _with(legs, i, value):
    out = list(legs)
    out[i] = value
    return tuple(out)


def _fold(base, platform, legs, i, a, b):
    """Bisect leg i between a and b (different certified counts) to adjacent floats."""
    ca = _modes(base, platform, _with(legs, i, a))
    for _ in range(70):
        m = 0.5 * (a + b)
        if m in (a, b):
            break
        if _modes(base, platform, _with(legs, i, m)) == ca:
            a = m
        else:
            b = m
    return a, b


def _around(name, family, base, platform, legs, i, a, b, ks):
    out = []
    for k in ks:
        for side, x in (("-", a - abs(a) * 2.0 ** -k), ("+", b + abs(b) * 2.0 ** -k)):
            lg = _with(legs, i, x)
            out.append(Case(f"{name} leg{i + 1} {side}2^-{k}", family, base, platform, lg,
                               2.0 ** -k, *certified_truth(base, platform, lg)))
    return out


def _random_folds(rng, n_octahedra, ks):
    from .problem import LEG_PAIRS
    from .reference import random_rational_octahedron
    out = []
    found = 0
    while found < n_octahedra:
        P = [tuple(float(c) for c in p) for p in random_rational_octahedron(rng)]
        base, plat_world = tuple(P[:3]), P[3:]
        plat = tuple(tuple(c - plat_world[0][k] for k, c in enumerate(p)) for p in plat_world)
        legs = tuple(math.dist(P[i - 1], P[j - 1]) for i, j in LEG_PAIRS)
        i = int(rng.integers(0, 6))
        grid = [legs[i] * (1 + u) for u in np.linspace(-0.3, 0.3, 13)]
        counts = [_modes(base, plat, _with(legs, i, x)) for x in grid]
        k = next((j for j in range(len(grid) - 1) if counts[j] != counts[j + 1]), None)
        if k is None:
            continue
        a, b = _fold(base, plat, legs, i, grid[k], grid[k + 1])
        out += _around(f"random#{found}", "fold", base, plat, legs, i, a, b, ks)
        found += 1
    return out


@lru_cache(maxsize=4)
def hard_set(n_random: int = 8, ks: tuple = (8, 16, 24, 32, 40, 44, 48), seed: int = 8) -> tuple:
    """The hard set (see module doc): a tuple of :class:`Case`.

    Parameters
    ----------
    n_random : int
        Random rational octahedra with a fold to include.
    ks : tuple of int
        Distances :math:`2^{-k}` to the count change.
    seed : int
    """
    rng = np.random.default_rng(seed)
    out = []
    a, b = _fold(_GD_BASE, _GD_PLAT, _GD_LEGS, 4, 15.0, 15.5)
    out += _around("griffis-duffy", "fold", _GD_BASE, _GD_PLAT, _GD_LEGS, 4, a, b, ks)
    # the edge of assemblability: all legs scaled by lambda
    lo, hi = 0.36, 0.38
    for _ in range(60):
        m = 0.5 * (lo + hi)
        if _modes(_GD_BASE, _GD_PLAT, tuple(m * v for v in _GD_LEGS)) > 0:
            hi = m
        else:
            lo = m
    for k in ks:
        for side, lam in (("-", lo * (1 - 2.0 ** -k)), ("+", hi * (1 + 2.0 ** -k))):
            lg = tuple(lam * v for v in _GD_LEGS)
            out.append(Case(f"edge lambda {side}2^-{k}", "edge", _GD_BASE, _GD_PLAT, lg,
                               2.0 ** -k, *certified_truth(_GD_BASE, _GD_PLAT, lg)))
    # a flat configuration (root of multiplicity 4), one leg perturbed
    fb = ((0.0, 0.0, 0.0), (4.0, 8.0, 0.0), (9.0, 0.0, 0.0))
    fp = ((0.0, 0.0, 0.0), (3.0, -1.0, 0.0), (1.0, 2.0, 0.0))
    fl = tuple(math.sqrt(v) for v in (13, 37, 53, 10, 41, 32))
    for k in ks:
        for sgn in (-1, 1):
            lg = _with(fl, 2, fl[2] * (1 + sgn * 2.0 ** -k))
            out.append(Case(f"flat leg3 {'-' if sgn < 0 else '+'}2^-{k}", "flat", fb, fp, lg,
                               2.0 ** -k, *certified_truth(fb, fp, lg)))
    folds = _random_folds(rng, n_random, ks)
    out += folds
    # extreme scales: Griffis-Duffy folds scaled by 1e-3 and 1e3
    for s in (1e-3, 1e3):
        for p in out[:len(ks) * 2]:
            base = tuple(tuple(c * s for c in r) for r in p.base)
            plat = tuple(tuple(c * s for c in r) for r in p.platform)
            lg = tuple(v * s for v in p.legs)
            out.append(Case(f"{p.name} x{s:g}", "scale", base, plat, lg, p.distance,
                               *certified_truth(base, plat, lg)))
    return tuple(out)


@lru_cache(maxsize=4)
def easy_set(n: int = 200, seed: int = 3) -> tuple:
    """Random assembled octahedra at scales 1e-3 .. 1e3 (truth from the certified tier)."""
    from .reference import random_octahedron
    rng = np.random.default_rng(seed)
    out = []
    for j in range(n):
        base, plat, legs, *_ = random_octahedron(rng, scale=10.0 ** rng.uniform(-3, 3))
        b = tuple(map(tuple, base.tolist()))
        p = tuple(map(tuple, plat.tolist()))
        lg = tuple(legs.tolist())
        out.append(Case(f"easy#{j}", "easy", b, p, lg, 0.0, *certified_truth(b, p, lg)))
    return tuple(out)


def _legs(base, pts):
    from .problem import LEG_PAIRS
    allp = np.vstack([base, pts])
    return np.array([np.linalg.norm(allp[i - 1] - allp[j - 1]) for i, j in LEG_PAIRS])


def near_coplanar(rng, height, tilt):
    """A random octahedron whose platform lies ``height`` (relative to the base size)
    above or below the base plane, tilted by ``tilt`` rad about a random horizontal axis.
    Returns base (3, 3), platform (3, 3) in its own frame, legs (6,)."""
    base = random_triangle(rng)
    plat = random_triangle(rng) * rng.uniform(0.2, 1.5)
    R = axis_angle([*rng.normal(size=2), 0.0], tilt) @ axis_angle([0, 0, 1],
                                                                 rng.uniform(0, 2 * np.pi))
    t = np.array([*rng.uniform(-0.5, 0.5, 2), height * rng.choice([-1, 1])])
    return base, plat, _legs(base, plat @ R.T + t)


def near_line(rng, distance, vertex):
    """A random octahedron whose platform vertex ``vertex`` (0: P4, 1: P5, 2: P6) lies
    ``distance`` (relative to the edge) from the line of the base edge it is joined to
    (P1P2, P2P3, P3P1).  Returns base, platform (in its own frame), legs."""
    base = random_triangle(rng)
    i, j = ((0, 1), (1, 2), (2, 0))[vertex]
    v = base[j] - base[i]
    w = rng.normal(size=3)
    w -= (w @ v) / (v @ v) * v
    pts = np.empty((3, 3))
    pts[vertex] = (base[i] + rng.uniform(0.1, 0.9) * v
                   + distance * np.linalg.norm(v) * w / np.linalg.norm(w))
    for o in range(3):
        if o != vertex:
            pts[o] = pts[vertex] + rng.normal(size=3) * rng.uniform(0.3, 1.0)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return base, (pts - pts[0]) @ q, _legs(base, pts)


def _case(name, family, base, plat, legs, distance):
    b = tuple(map(tuple, np.asarray(base, float).tolist()))
    p = tuple(map(tuple, np.asarray(plat, float).tolist()))
    lg = tuple(np.asarray(legs, float).tolist())
    return Case(name, family, b, p, lg, distance, *certified_truth(b, p, lg, tol=1e-3))


def _clustered(rng, n, tries, max_gap=1e-3):
    """Random octahedra with two certified real roots within 1e-3 relative in the
    feasible interval (module docstring), screened by the eigenvalues of the float
    octic: (base, platform, legs, gap) of at most ``n``."""
    from .forward import forward_kinematics
    from .problem import float_single
    from .reference import random_octahedron
    from .single import solve_fast_single
    out = []
    for _ in range(tries):
        if len(out) >= n:
            break
        base, plat, legs, *_ = random_octahedron(rng)
        B, Q, L, k, _ = float_single(base, plat, legs)
        solve = solve_fast_single(B, Q, L)
        lo, hi = solve.lo, solve.hi
        z = np.array(solve.eigenvalues)
        z = z[(z.real >= lo - 0.05 * (hi - lo)) & (z.real <= hi + 0.05 * (hi - lo))]
        if z.size < 2:
            continue
        d = np.abs(z[:, None] - z[None, :])
        np.fill_diagonal(d, np.inf)
        if not d.min() < 1e-2 * max(abs(hi), 1e-300):
            continue
        res = forward_kinematics(base, plat, legs, method="certified", tol=1e-3)
        x = np.ldexp([r.value for r in res.roots], -2 * k)
        x = x[(x >= lo * (1 - 1e-9)) & (x <= hi * (1 + 1e-9))]
        if x.size >= 2:
            gap = float(np.min(np.diff(x) / np.abs(x[1:])))
            if gap < max_gap:
                out.append((base, plat, legs, gap))
    return out


@lru_cache(maxsize=4)
def hard_families(scales: tuple = (1e-3, 1.0, 1e3), n_coplanar: int = 24,
                  n_flat: int = 8, n_line: int = 18, n_cluster: int = 30,
                  seed: int = 14) -> tuple:
    """The families of issue 14 (module docstring): a tuple of :class:`Case`, each
    problem at every scale of ``scales`` (the float data multiplied by the scale; each
    truth computed again on the scaled floats).

    Parameters
    ----------
    n_coplanar : int
        Near-coplanar problems with heights 1e-6 .. 1e-2 and tilts 1e-5 .. 1e-2
        (log-uniform); ``n_flat`` more with heights 1e-14 .. 1e-9 and tilts 1e-9 ..
        1e-5.
    n_line : int
        Problems with a platform vertex 1e-12 .. 1e-4 from a base-edge line.
    n_cluster : int
        Random octahedra with two close real roots (screened from up to 400 x
        ``n_cluster`` random octahedra).
    """
    rng = np.random.default_rng(seed)
    raw = []
    for j in range(n_coplanar):
        h, t = 10.0 ** rng.uniform(-6, -2), 10.0 ** rng.uniform(-5, -2)
        raw.append((f"coplanar#{j} h={h:.1e} tilt={t:.1e}", "coplanar",
                    *near_coplanar(rng, h, t), h))
    for j in range(n_flat):
        h, t = 10.0 ** rng.uniform(-14, -9), 10.0 ** rng.uniform(-9, -5)
        raw.append((f"coplanar-flat#{j} h={h:.1e} tilt={t:.1e}", "coplanar",
                    *near_coplanar(rng, h, t), h))
    for j in range(n_line):
        dist = 10.0 ** rng.uniform(-12, -4)
        raw.append((f"line#{j} P{4 + j % 3} at {dist:.1e}", "line",
                    *near_line(rng, dist, j % 3), dist))
    for j, (b, p, lg, gap) in enumerate(_clustered(rng, n_cluster, 400 * n_cluster)):
        raw.append((f"cluster#{j} gap={gap:.1e}", "cluster", b, p, lg, gap))
    out = []
    for sc in scales:
        for name, fam, b, p, lg, dist in raw:
            out.append(_case(f"{name} x{sc:g}", fam, b * sc, p * sc, lg * sc, dist))
    return tuple(out)
