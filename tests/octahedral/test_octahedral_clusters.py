"""Verdict 10 of the proof (:data:`distkin.octahedral.descartes.CLUSTER`): a fast answer
whose real roots outside the feasible interval cluster (a multiple root of the octic
split by rounding) is flagged, and ``auto`` escalates it; checked against the certified
tier's count (python-flint), the independent route."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from distkin.errors import ConditioningWarning
from distkin.octahedral import forward_kinematics, forward_kinematics_batched
from distkin.octahedral.descartes import CLUSTER, VERDICTS
from distkin.octahedral.problem import float_problem
from distkin.octahedral.reference import GD_BASE, GD_PLATFORM, random_octahedron

LEGS = [1.0] * 6            # the Griffis-Duffy triangles with six legs of 1: no assembly


def test_split_multiple_root_is_flagged_and_auto_gives_the_certified_count():
    """Six legs of 1 on the Griffis-Duffy triangles: the exact octic has 4 real roots
    (-872, -71, 73, 153.1; the certified tier proves them), the one at -71 multiple;
    float64 splits it into a cluster and reports 8.  No pose either way, so the proof
    of the assembly roots holds; verdict 10 refuses the count: the single fast call
    warns naming it, the batched tier flags the problem, and ``auto`` answers with the
    certified tier's count."""
    cert = forward_kinematics(GD_BASE, GD_PLATFORM, LEGS, method="certified")
    assert cert.real_root_count == 4 and len(cert) == 0
    with pytest.warns(ConditioningWarning, match="1e-4 relative"):
        fast = forward_kinematics(GD_BASE, GD_PLATFORM, LEGS)
    values = sorted(r.value for r in fast.roots)                # (8 today: the miscount)
    gaps = np.diff(values) / np.maximum(np.abs(values[:-1]), np.abs(values[1:]))
    assert gaps.min() <= CLUSTER
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)     # auto: no warning
        auto = forward_kinematics(GD_BASE, GD_PLATFORM, LEGS, method="auto")
    assert auto.real_root_count == cert.real_root_count
    assert [r.value for r in auto.roots] == pytest.approx([r.value for r in cert.roots])
    B, Q, L = float_problem(GD_BASE, GD_PLATFORM, LEGS)[:3]
    bat = forward_kinematics_batched(B, Q, L, warn=False)
    assert not bat.trusted[0] and bat.verdict[0] == 10
    assert "multiple root" in VERDICTS[10]


def test_no_cluster_verdict_on_random_octahedra():
    """The screen costs nothing where the fast count is right: on 2000 random octahedra
    no problem gets verdict 10 (each of their real roots is simple and well apart), and
    every real-root count of the batch matches the certified tier on a sample of 40."""
    rng = np.random.default_rng(17)
    probs = [random_octahedron(rng) for _ in range(2000)]
    B, Q, L = (np.array([p[j] for p in probs]) for j in range(3))
    bat = forward_kinematics_batched(B, Q, L, warn=False)
    assert not (bat.verdict == 10).any()
    found = np.isfinite(bat.raw["roots"]).sum(axis=1)
    for i in range(0, 2000, 50):
        assert forward_kinematics(B[i], Q[i], L[i], method="certified").real_root_count == found[i]
