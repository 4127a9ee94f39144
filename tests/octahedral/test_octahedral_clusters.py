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


def _tri(a):
    return [[0, 0, 0], [a, 0, 0], [f"{a}/2", f"sqrt(3)*{a}/2", 0]]


@pytest.mark.parametrize("big, small, leg", [(2, 1, 2), (12, 6, 10)])
def test_precise_tier_gives_every_mode_of_a_multiple_root(big, small, leg):
    """The symmetric home configuration (equilateral base and platform, six equal
    legs): the exact octic has two triple roots, each carrying three assembly modes
    (QA, 2026-11-27: the precise tier merged each into one root of multiplicity 1 and
    gave 8 poses without a word).  Against the exact octic factored by python-flint
    (the independent route): every real root with its multiplicity, and three modes
    (six poses) at each triple root, each pose reproducing all six legs and the
    platform's sides (recomputed here from its points), the 16 poses pairwise
    distinct.  (The fast tier warns on these problems and is no reference here.)"""
    import flint
    base, plat, legs = _tri(big), _tri(small), [leg] * 6
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)   # every mode separated
        res = forward_kinematics(base, plat, legs, method="precise")
    x = flint.fmpq_poly([0, 1])
    octic = sum((flint.fmpq(c.numerator, c.denominator) * x ** (len(res.octic) - 1 - k)
                 for k, c in enumerate(res.octic)), flint.fmpq_poly([0]))
    exact = []
    for f, m in octic.factor()[1]:
        for z, _ in f.complex_roots():
            if z.imag == 0:
                exact.append((float(z.real), m))
    exact.sort()
    assert [(r.value, r.multiplicity) for r in res.roots] == [
        (pytest.approx(v, rel=1e-14), m) for v, m in exact]
    assert [m for _, m in exact].count(3) == 2 and len(res) == 16
    for r in res.roots:
        at = [p for p in res if p.s15 == r.value]
        assert len(at) == 2 * r.multiplicity
    # each pose, from its points (float): the six legs and the platform's sides
    B = np.array([[0, 0, 0], [big, 0, 0], [big / 2, 3 ** 0.5 * big / 2, 0]])
    for p in res:
        P = {1: B[0], 2: B[1], 3: B[2], 4: p.points[0], 5: p.points[1], 6: p.points[2]}
        for i, j in ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6)):
            assert np.linalg.norm(P[i] - P[j]) == pytest.approx(leg, rel=1e-12)
        for i, j in ((4, 5), (5, 6), (4, 6)):
            assert np.linalg.norm(P[i] - P[j]) == pytest.approx(small, rel=1e-12)
    pts = np.array([p.points for p in res]).reshape(16, 9)
    gaps = np.linalg.norm(pts[:, None] - pts[None], axis=-1) + np.eye(16) * big
    assert gaps.min() > 1e-6 * big


def test_precise_tier_warns_next_to_a_fold():
    """Griffis-Duffy with leg 5 2^-40 below a fold (hardset: two assembly modes within
    ~2e-6 relative).  At 15 digits the precise tier merged them (its cluster radius was
    10^-(dps//3), 1e-5); it now merges only within 10^-(work/4 - 1) (the radius of a
    four-fold root's cluster at the working precision, 1e-7 here), separates the two,
    finds the certified 12 poses, and still says it cannot vouch for one of them (the
    octic's sign change around it is below what 15 digits resolve); at 30 digits it
    separates them silently."""
    from distkin.octahedral.hardset import hard_set
    case = next(c for c in hard_set() if c.name == "griffis-duffy leg5 -2^-40")
    cert = forward_kinematics(case.base, case.platform, list(case.legs), method="certified")
    with pytest.warns(ConditioningWarning, match="does not change sign"):
        low = forward_kinematics(case.base, case.platform, list(case.legs),
                                 method="precise", dps=15)
    assert len(low) == len(cert) == 12
    assert [round(r.value, 6) for r in low.roots] == [round(r.value, 6) for r in cert.roots]
    assert any("no sign change" in n for n in low.notes)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)
        high = forward_kinematics(case.base, case.platform, list(case.legs), method="precise")
    assert len(high) == len(cert)


def test_certified_tier_at_a_multiple_root_says_what_to_do():
    """The symmetric home configuration in the certified tier: the balls cannot single
    out the placements at a triple root (three modes meet); the error says so, names
    the multiplicity (python-flint's factorisation of the exact octic: (x - 2)^3) and
    points to the precise tier, which gives the modes (test above)."""
    from distkin.errors import UncertifiedError
    with pytest.raises(UncertifiedError, match="multiplicity 3") as err:
        forward_kinematics(_tri(2), _tri(1), [2] * 6, method="certified")
    assert "method='precise'" in str(err.value)


def test_certified_tier_decides_an_open_face_exactly():
    """Legs of 1/2 on an equilateral base of side 2: l1 + l2 = 1 < |P1P2| = 2, so the face
    P1 P2 P4 is no triangle and no assembly exists (the triangle inequality, by hand).
    The certified tier used to stop at a flat face of a banana at one of the spurious
    roots (QA, 2026-11-27); it now says "cannot be assembled" naming the face, and
    ``auto`` gives that answer; the fast tier finds no pose either."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConditioningWarning)
        fast = forward_kinematics(_tri(2), _tri(1), ["1/2"] * 6)
        auto = forward_kinematics(_tri(2), _tri(1), ["1/2"] * 6, method="auto")
    cert = forward_kinematics(_tri(2), _tri(1), ["1/2"] * 6, method="certified")
    assert len(cert) == len(auto) == len(fast) == 0
    assert all(r.status == "spurious" and "P1 P2 P4" in r.reason for r in cert.roots)
    assert cert.reason.startswith("cannot be assembled") and auto.tier == "certified"
    assert auto.real_root_count == cert.real_root_count


@pytest.mark.parametrize("name", ["griffis-duffy leg5 +2^-32", "edge lambda -2^-32"])
def test_precise_tier_warns_at_a_complex_pair_next_to_the_axis(name):
    """Just past a fold (hardset) two roots have become a complex pair a little off the
    real axis; at 15 digits the precise tier used to take it for a real root and give
    more poses than the certified tier, without a word (QA).  The octic does not change
    sign around such a "root": the tier says so (``ConditioningWarning``, a note)."""
    from distkin.octahedral.hardset import hard_set
    case = next(c for c in hard_set() if c.name == name)
    cert = forward_kinematics(case.base, case.platform, list(case.legs), method="certified")
    with pytest.warns(ConditioningWarning, match="does not change sign"):
        low = forward_kinematics(case.base, case.platform, list(case.legs),
                                 method="precise", dps=15)
    assert low.real_root_count > cert.real_root_count          # (the miscount it flags)
    assert any("no sign change" in n for n in low.notes)


def test_precise_tier_gives_the_multiplicity_of_a_spurious_cluster():
    """Six legs of 1 on the Griffis-Duffy triangles (no assembly): the octic has triple
    roots at -71 and 73, outside the feasible interval.  The precise tier said
    multiplicity 1 there (QA), while its own clusters inside the interval carry theirs;
    now it gives the cluster's size, says in a note that this precision sees it (no
    warning: every root of the cluster is spurious, no mode is lost), and agrees with
    the certified tier and with sympy's square-free factorisation of the exact octic
    (the independent routes)."""
    import sympy as sp
    cert = forward_kinematics(GD_BASE, GD_PLATFORM, LEGS, method="certified")
    s = sp.Symbol("s")
    exact = sp.Poly([sp.Rational(c.numerator, c.denominator) for c in cert.octic], s)
    mult = {}
    for f, m in exact.sqf_list()[1]:
        for r in sp.Poly(f, s).real_roots():
            mult[round(float(r), 6)] = m
    assert sorted(mult.values()) == [1, 1, 3, 3]
    for dps in (30, 50):
        with warnings.catch_warnings():
            warnings.simplefilter("error", ConditioningWarning)
            prec = forward_kinematics(GD_BASE, GD_PLATFORM, LEGS, method="precise", dps=dps)
        assert len(prec) == 0 and all(r.status == "spurious" for r in prec.roots)
        assert [r.multiplicity for r in prec.roots] == [r.multiplicity for r in cert.roots]
        assert [r.multiplicity for r in prec.roots] == [mult[round(r.value, 6)]
                                                        for r in prec.roots]
        note = [n for n in prec.notes if "spurious roots merged" in n]
        assert len(note) == 1 and "not proved" in note[0] and "3 roots" in note[0]
        for r, c in zip(prec.roots, cert.roots):
            assert abs(r.value - c.value) <= max(r.radius, 1e-9 * abs(c.value))
