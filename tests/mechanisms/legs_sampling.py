"""Random leg tables for the tests: every leg type in one mechanism, closing at home."""

from __future__ import annotations

import numpy as np

from distkin.mechanisms.legs import LEG_TYPES, LegsDescription
from distkin.spatial import rotation_matrix

__all__ = ["random_legs", "MIXED_TYPES"]

#: one of each type, then two more revolute legs: L = 7 covers RSS, RUS, RRRS, SPS, UPS
MIXED_TYPES = LEG_TYPES + ("RSS", "RRRS")


def _unit(v):
    return v / np.linalg.norm(v)


def random_legs(seed: int, types=MIXED_TYPES, name="random") -> LegsDescription:
    """A mechanism with one leg per entry of ``types``, random geometry (m, rad) whose
    every leg closes at a random home pose (the distal length is the distance at a random
    crank angle q0 in [-0.6, 0.6] rad; a prismatic stroke is ±50 % of the home length)."""
    rng = np.random.default_rng(seed)
    L = len(types)
    home = np.array([*rng.uniform(-0.02, 0.02, 2), rng.uniform(0.25, 0.35),
                     *rng.uniform(-0.2, 0.2, 3)])
    R = rotation_matrix(home[3:])
    legs = []
    for i, t in enumerate(types):
        th = 2 * np.pi * i / L + rng.uniform(-0.2, 0.2)
        e = np.array([np.cos(th), np.sin(th), 0.0])
        B = rng.uniform(0.10, 0.20) * e + [0, 0, rng.uniform(-0.02, 0.02)]
        tp = th + rng.uniform(-0.5, 0.5)
        p = rng.uniform(0.03, 0.08) * np.array([np.cos(tp), np.sin(tp), 0.0]) \
            + [0, 0, rng.uniform(-0.01, 0.01)]
        P = home[:3] + R @ p
        if t in ("SPS", "UPS"):
            length = float(np.linalg.norm(P - B))
            legs.append(dict(type=t, base=tuple(B), platform=tuple(p),
                             range=(0.5 * length, 1.5 * length), limit=float(rng.uniform(50, 500))))
            continue
        a = _unit(rng.normal(size=3) if rng.random() < 0.3 else
                  np.cross([0, 0, 1.0], e) + 0.3 * rng.normal(size=3))
        u = _unit(np.cross(a, rng.normal(size=3)))
        v = np.cross(a, u) * (1 if rng.random() < 0.5 else -1)
        l1 = rng.uniform(0.03, 0.08)
        o = rng.uniform(-0.03, 0.03) * a if t == "RRRS" else np.zeros(3)
        q0 = rng.uniform(-0.6, 0.6)
        D = B + o + l1 * (np.cos(q0) * u + np.sin(q0) * v)
        legs.append(dict(type=t, base=tuple(B), platform=tuple(p), axis=tuple(a),
                         crank0=tuple(u), crank90=tuple(v), crank=l1, offset=tuple(o),
                         distal=float(np.linalg.norm(P - D)), range=(-np.pi, np.pi),
                         limit=float(rng.uniform(0.5, 5))))
    return LegsDescription(name, legs, tuple(home), 1.0, 1e-3)
