"""The three tiers of the inverse kinematics and the Jacobian (distkin.mechanisms.
kinematics_tiers; Kühne et al., Sec. II-C, eqs. (1)-(2)): fast, precise and certified
agree, each within its stated accuracy; the certified balls are tight; the precise J
matches finite differences of the precise IK (an independent route: the closed-form
atan2 against the symbolic derivative of the closure); legs that cannot be certified
are refused with the reason."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from flint import arb

from distkin.app.cli import run_scene
from distkin.app.scene import loads_scene
from distkin.errors import (ConditioningWarning, GeometryWarning, InfeasibleError, InputError,
                            UncertifiedError)
from distkin.exact_roots import working_precision
from distkin.mechanisms import preset
from distkin.mechanisms.kinematics import LegMechanism
from distkin.mechanisms.kinematics_tiers import (MPNumber, ik_tier, jacobian_tier,
                                                 on_mpmath)

#: a workspace pose near the centre (offsets from home: m, rad)
OFFSET = np.array([0.012, -0.007, 0.015, 0.06, -0.04, 0.09])


def _mpf(ball):
    """The midpoint of an arb ball as an exact mpmath number."""
    man, exp = ball.mid().man_exp()
    return mpmath.mpf((int(man), int(exp)))


@pytest.mark.parametrize("name", ["octo", "hexa"])
def test_tiers_agree_and_balls_are_tight(name):
    m = preset(name)
    X = m.home + OFFSET
    fast, prec, cert = (ik_tier(m, X, t) for t in ("fast", "precise", "certified"))
    assert cert.certified.all() and not cert.reasons and cert.valid.all()
    assert cert.q_error.max() < 1e-12      # tight: the balls (~1e-37) and q's own rounding
    # fast lies in the ball within its own first-order estimate (a few ulps)
    assert np.all(np.abs(fast.q - cert.q) <= cert.q_error + fast.q_error)
    assert np.all(fast.q_error < 1e-14)
    assert np.array_equal(fast.q[0], m.inverse_kinematics(X)[0])
    # the precise values (30 digits) and their floats meet the balls within the error
    # estimates of the floats: the 30-digit difference (< 1e-28) plus the rounding
    with mpmath.workdps(60):
        for p, q, b, e in zip(prec.values.ravel(), prec.q.ravel(), cert.values.ravel(),
                              prec.q_error.ravel()):
            assert abs(p - _mpf(b)) <= float(b.rad()) + e
            assert abs(mpmath.mpf(q) - _mpf(b)) <= float(b.rad()) + e
            assert abs(mpmath.mpf(q) - p) <= e < 1e-28 + math.ulp(q) / 2
    fj, pj, cj = (jacobian_tier(m, X, t) for t in ("fast", "precise", "certified"))
    assert cj.certified.all() and cj.J_error.max() < 1e-12
    assert np.all(np.abs(fj.J - cj.J) <= cj.J_error + fj.J_error)
    assert np.array_equal(fj.J[0], m.jacobian(X))
    with mpmath.workdps(60):
        for p, b, e in zip(pj.values.ravel(), cj.values.ravel(), pj.J_error.ravel()):
            assert abs(p - _mpf(b)) <= float(b.rad()) + e


def test_python_entry_points_return_the_tier_numbers():
    m = preset("octo")
    X = m.home + OFFSET
    q, valid = m.inverse_kinematics(X, method="certified")
    assert q.shape == (8,) and all(isinstance(b, arb) for b in q) and valid.all()
    qp, _ = m.inverse_kinematics(X, method="precise", dps=40)
    assert all(isinstance(v, mpmath.mpf) for v in qp)
    assert all(b.contains(arb(float(v))) or abs(float(v) - float(b.mid())) < 1e-16
               for v, b in zip(qp, q))
    J = m.jacobian(X[None], method="certified")
    assert J.shape == (1, 8, 6)
    Jq, Jx = m.jq_jx(X, method="certified")
    assert Jq.shape == (8,) and Jx.shape == (8, 6)
    assert all((J[0, i, k] - Jx[i, k] / Jq[i]).contains(0) for i in range(8) for k in range(6))


def test_precise_jacobian_matches_differences_of_precise_ik():
    """dq/d(pose) by central differences of the mpmath IK kernel at 60 digits (h = 1e-20,
    error ~1e-40) against J_precise @ blockdiag(I, E(r)), E written out for
    R = Rz Ry Rx (omega = E rdot).  Both kernels are derived from the exact model (one
    mechanism, constants exact), so they agree to the differences' error: 1e-35."""
    m = preset("octo")
    X = m.home + OFFSET
    J = jacobian_tier(m, X, "precise", dps=50).values[0]          # (8, 6) mpf
    ik = on_mpmath(m.kernels("arb").ik)
    with mpmath.workdps(60):
        P = [mpmath.mpf(float(v)) for v in X]
        h = mpmath.mpf("1e-20")
        fd = []
        for k in range(6):
            up = [MPNumber(v + (h if i == k else 0)) for i, v in enumerate(P)]
            dn = [MPNumber(v - (h if i == k else 0)) for i, v in enumerate(P)]
            fd.append([(a.v - b.v) / (2 * h) for a, b in zip(ik(up), ik(dn))])
        cy, sy = mpmath.cos(P[4]), mpmath.sin(P[4])
        cz, sz = mpmath.cos(P[5]), mpmath.sin(P[5])
        E = [[cz * cy, -sz, 0], [sz * cy, cz, 0], [-sy, 0, 1]]
        for i in range(8):
            for k in range(6):
                jp = J[i][k] if k < 3 else sum(J[i][3 + a] * E[a][k - 3] for a in range(3))
                assert abs(jp - fd[k][i]) < 1e-35 * max(1, abs(jp)), (i, k)


def test_unreachable_pose_is_refused():
    m = preset("octo")
    far = m.home + np.array([0, 0, 0.5, 0, 0, 0])
    res = ik_tier(m, far, "certified")
    assert not res.certified.any() and res.infeasible.all() and not res.valid.any()
    assert "does not close" in res.reasons[0][2]
    with pytest.raises(InfeasibleError, match=r"pose 0, got leg 1 uncertified: the leg "
                                              r"does not close"):
        m.inverse_kinematics(far, method="certified")
    with pytest.raises(InfeasibleError, match="does not close"):
        m.jacobian(far, method="certified")


def test_rss_reach_boundary_is_refused():
    """The float pose next to the reach boundary of the Octo's legs (bisection on z): at
    53 bits its margin ball contains 0 and no leg is certified; at 128 bits the same
    pose is decided (it is not exactly on the boundary), and the fast answer, far less
    accurate there (h = sqrt(margin) ~ 1e-8), still lies in the ball within its own
    estimate."""
    m = preset("octo")
    reach = m.kernels("batched").reach
    lo, hi = 0.3, 0.6
    while (lo + hi) / 2 not in (lo, hi):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if reach(np.array([0, 0, mid, 0, 0, 0]))[0] >= 0 else (lo, mid)
    X = np.array([0, 0, lo, 0, 0, 0])
    res = ik_tier(m, X, "certified", bits=53)
    assert not res.certified.any() and not res.infeasible.any()
    assert "contains 0" in res.reasons[0][2] and "reach boundary" in res.reasons[0][2]
    assert res.reach_undecided.all()               # (the same, as a flag per leg)
    fine = ik_tier(m, X, "certified")
    with pytest.warns(ConditioningWarning, match="reach boundary"):
        fast = ik_tier(m, X, "fast")               # within rounding of it: flagged
    assert fast.reach_undecided.all() and not fine.reach_undecided.any()
    assert fine.certified.all()
    assert np.all(np.abs(fast.q - fine.q) <= fine.q_error + fast.q_error)
    assert fast.q_error.max() > 1e-10              # the estimate sees the boundary


@pytest.fixture(scope="module")
def box6():
    """Six SPS legs, stroke 0.25 ... 1 m; leg 1 vertical from (0.25, 0, 0) to the
    platform point (0.25, 0, 0): its length is exactly z at zero rotation."""
    legs = [dict(type="SPS", base=(0.25, 0.0, 0.0), platform=(0.25, 0.0, 0.0),
                 range=(0.25, 1.0))]
    for k in range(1, 6):
        a = math.pi / 3 * k
        legs.append(dict(type="SPS", base=(0.5 * math.cos(a), 0.5 * math.sin(a), 0.0),
                         platform=(0.25 * math.cos(a + 1), 0.25 * math.sin(a + 1), 0.0),
                         range=(0.25, 1.0)))
    with pytest.warns(GeometryWarning, match="home is a singular pose"):   # rank 4 there
        return LegMechanism("box6", legs, home_pose=(0, 0, 0.5, 0, 0, 0))


def test_prismatic_lengths_and_stroke_end(box6):
    X = np.array([0.0, 0.0, 0.5, 0.0, 0.0, 0.0])
    res = ik_tier(box6, X, "certified")
    assert res.certified.all()
    # each ball lies within q_error of the float q, and q_error is only that rounding
    # (the 128-bit balls, ~1e-37, are far inside an ulp)
    with working_precision(1024):          # q +- q_error exactly
        for q, e, b in zip(res.q.ravel(), res.q_error.ravel(), res.values.ravel()):
            assert e <= math.ulp(q)
            assert arb(q) - arb(e) <= b.lower() and b.upper() <= arb(q) + arb(e)
    assert res.values[0, 0].contains(arb(0.5))                  # exactly 0.5 m
    for j, leg in enumerate(box6.leg_table):                    # |P - B| (analytic)
        d = [arb(p) + arb(x) - arb(b) for p, x, b in zip(leg.platform, X[:3], leg.base)]
        assert res.values[0, j].overlaps(sum(c * c for c in d).sqrt())
    end = ik_tier(box6, [0, 0, 1.0, 0, 0, 0], "certified")     # leg 1 at its stroke end
    assert not end.certified[0, 0]
    assert "contains 0" in end.reasons[0][2] and "stroke" in end.reasons[0][2]
    with pytest.raises(UncertifiedError, match="leg 1 uncertified: the reach margin ball"):
        box6.inverse_kinematics([0, 0, 1.0, 0, 0, 0], method="certified")


SCENE = """
[units]
length = "mm"
angle = "deg"
[mechanism]
kind = "rss"
preset = "octo"
[[query]]
type = "{type}"
poses = [[0, 0, 300, 0, 0, 0], [12, -7, 315, 3, -2, 5], [0, 0, 800, 0, 0, 0]]
{extra}
"""


@pytest.mark.parametrize("qtype", ["inverse_kinematics", "jacobian"])
def test_bad_method_names_field_and_choices(qtype):
    with pytest.raises(InputError) as err:
        loads_scene(SCENE.format(type=qtype, extra='method = "exact"'))
    msg = str(err.value)
    assert "query[0].method" in msg and all(t in msg for t in ("fast", "precise", "certified"))
    assert "'exact'" in msg
    with pytest.raises(InputError, match="method"):
        preset("octo").inverse_kinematics(preset("octo").home, method="exact")


def test_method_omitted_is_todays_fast_output():
    m = preset("octo")
    (ik,), _, _ = run_scene(loads_scene(SCENE.format(type="inverse_kinematics", extra="")))
    (jac,), _, _ = run_scene(loads_scene(SCENE.format(type="jacobian", extra="")))
    X = np.array([r["pose"] for r in ik["result"]["poses"]])
    k = m.kernels("batched")
    assert np.array_equal([r["q"] for r in ik["result"]["poses"]], k.ik(X))
    assert np.array_equal([r["reach_margin"] for r in ik["result"]["poses"]], k.reach(X))
    assert np.array_equal([r["J"] for r in jac["result"]["poses"]], k.jacobian(X))
    assert ik["result"]["method"] == "fast" and ik["result"]["poses"][0]["method"] == "fast"


def test_certified_query_marks_each_leg():
    (rec,), texts, worst = run_scene(loads_scene(SCENE.format(
        type="inverse_kinematics", extra='method = "certified"')))
    rows = rec["result"]["poses"]
    assert [all(r["certified"]) for r in rows] == [True, True, False]
    assert all(max(r["q_error"]) < 1e-12 for r in rows[:2])
    assert len(rows[2]["uncertified"]) == 8 and rows[2]["uncertified"][0]["leg"] == 1
    text = "\n".join(texts)
    assert "NOT certified: leg 1: the leg does not close" in text
    assert "16 of 24 legs certified" in text and "largest radius of q" in text
    (rec,), texts, _ = run_scene(loads_scene(SCENE.format(
        type="jacobian", extra='method = "precise"\ndps = 40')))
    assert rec["result"]["precision"] == "mpmath at 40 digits"
    # the error of each float J: its rounding, the 40-digit estimate (1e-39) beside it
    for r in rec["result"]["poses"][:2]:
        for row, erow in zip(r["J"], r["J_error"]):
            assert all(e <= math.ulp(v) / 2 + 1e-37 for v, e in zip(row, erow))


def test_certified_query_on_legs_scene_says_undecided(box6):
    """A legs scene (written out exactly by legs_toml_text): at the pose where leg 1 ends
    its stroke the report calls it undecided, not unreachable, and the JSON names it."""
    from distkin.app.legs_scene import legs_toml_text
    text = (legs_toml_text(box6, length_unit="m") + '\n[[query]]\ntype = "inverse_kinematics"'
            '\nposes = [[0, 0, 1, 0, 0, 0]]\nmethod = "certified"\n')
    with pytest.warns(GeometryWarning, match="home is a singular pose"):
        scene = loads_scene(text)
    (rec,), texts, _ = run_scene(scene)
    row = rec["result"]["poses"][0]
    assert not row["certified"][0] and row["uncertified"][0]["leg"] == 1
    assert "stroke" in row["uncertified"][0]["reason"]
    verdict = [line for line in texts[0].splitlines() if line.strip().startswith("pose 0")][0]
    assert "undecided (legs [1])" in verdict and "NOT reachable (legs [2, 3, 4, 5, 6])" in verdict


def test_prismatic_leg_beyond_its_stroke_says_so(box6):
    """QA M 8: a prismatic leg longer than its stroke was reported as "does not close".
    Leg 1 is vertical, its length exactly z (analytic): at z = 1.2 m it is 1.2 m, beyond
    the stroke [0.25, 1] m, and the message says so with the numbers."""
    res = ik_tier(box6, [0, 0, 1.2, 0, 0, 0], "certified")
    assert res.infeasible[0, 0] and not res.certified[0, 0]
    why = res.reasons[0][2]
    assert "1.2 ± " in why and "beyond its stroke [0.25, 1] m" in why
    assert "does not close" not in why
    with pytest.raises(InfeasibleError, match="beyond its stroke"):
        box6.inverse_kinematics([0, 0, 1.2, 0, 0, 0], method="certified")
