"""Certified zero exclusion of det Ĵ along a path (QA F2), distkin.singularity.enclosure.

Checked against a second route (the value term of the series against the package's arb
det Ĵ of the pose, and against an mpmath det written here), and for soundness: an
interval around a certified crossing, and one holding the root pair of QA F2 that the
float grid missed, must never be proven free of zeros."""

from __future__ import annotations

import flint
import mpmath as mp
import pytest

from distkin.app.queries.singularity import OctahedralModel
from distkin.app.scene import loads_scene
from distkin.singularity import certify_crossing, det_series, exclude_zeros
from distkin.singularity.enclosure import monotone_on

SCENE = """
[units]
length = "none"
angle = "rad"
[mechanism]
kind = "octahedral"
base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
[[query]]
type = "singularity"
method = "certified"
[query.path.from]
translation = ["4.600749310927605", "0.7794051903049409", "10.35834177112095"]
rotation = ["1.9638735043221598", "1.975015002843553", "0.20475660701544626"]
[query.path.to]
translation = ["4.408779717087266", "0.9472923729966088", "9.639789994194691"]
rotation = ["2.324716540906057", "2.3212240237206094", "-0.2058241153973472"]
"""


@pytest.fixture(scope="module")
def f2():
    sc = loads_scene(SCENE)
    p = sc.queries[0].params
    model = OctahedralModel.build(sc.mechanism, p.offsets, p.length_scale)
    path = model.pose_path(*p.path)
    return model, path, (lambda ball: det_series(path, model.base_a, model.plat_a, ball))


def _mp_det_hat(path, s):
    """Unnormalised det Ĵ (rows (p - b, b x (p - b))) in mpmath, 40 digits."""
    with mp.workdps(40):
        s = mp.mpf(s)
        q = lambda v: [mp.mpf(str(x.value if hasattr(x, "value") else x)) for x in v]  # noqa: E731
        t = [a + s * (b - a) for a, b in zip(q(path.t0), q(path.t1))]
        w = [a + s * (b - a) for a, b in zip(q(path.w0), q(path.w1))]
        th = mp.sqrt(sum(x * x for x in w))
        k = [x / th for x in w]
        K = mp.matrix([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
        R = mp.eye(3) + mp.sin(th) * K + (1 - mp.cos(th)) * K * K
        base = [mp.matrix([0, 0, 0]), mp.matrix([6, mp.sqrt(108), 0]), mp.matrix([12, 0, 0])]
        plat = [mp.matrix([0, 0, 0]), mp.matrix([6, 0, 0]), mp.matrix([3, mp.sqrt(27), 0])]
        P = base + [R * v + mp.matrix(t) for v in plat]
        rows = []
        for i, j in ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6)):
            b, u = P[i - 1], P[j - 1] - P[i - 1]
            rows.append([u[0], u[1], u[2], b[1] * u[2] - b[2] * u[1],
                         b[2] * u[0] - b[0] * u[2], b[0] * u[1] - b[1] * u[0]])
        return mp.det(mp.matrix(rows))


@pytest.mark.parametrize("s", [0.0, 0.25, 0.4987, 1.0])
def test_value_term_matches_two_other_routes(f2, s):
    model, path, fs = f2
    v = fs(flint.arb(s))[0]
    ref = model.det_j_arb(*path.at_certified(flint.fmpq(*s.as_integer_ratio())))
    assert v.overlaps(ref)
    exact = _mp_det_hat(path, s)
    assert abs(float(v.mid()) - float(exact)) <= float(v.rad()) + 1e-12 * abs(float(exact))


def test_derivative_term_encloses_a_difference_quotient(f2):
    _, path, fs = f2
    d = fs(flint.arb(0.3, 1e-6))[1]
    h = mp.mpf("1e-7")
    with mp.workdps(40):
        q = (_mp_det_hat(path, 0.3 + h) - _mp_det_hat(path, 0.3 - h)) / (2 * h)
    # the quotient is f' at a point of the ball up to O(h^2): inside the enclosure
    assert abs(float(d.mid()) - float(q)) <= float(d.rad()) + 1e-6 * abs(float(q))


def test_never_proves_an_interval_with_a_zero(f2):
    model, path, fs = f2
    f_arb = lambda x: model.det_j_arb(*path.at_certified(x))  # noqa: E731
    c = certify_crossing(f_arb, 0.496219522192856)
    a, b = (float(x) for x in c.bracket)
    ex = exclude_zeros(fs, [(a - 1e-3, b + 1e-3)], budget=500)
    assert ex.undecided and any(u0 <= a and b <= u1 for u0, u1 in ex.undecided)
    # the sample interval of the 120-point grid holding both roots (mpmath: + - +)
    ex = exclude_zeros(fs, [(59 / 119, 60 / 119)], budget=500)
    assert ex.undecided and ex.proven < 60 / 119 - 59 / 119
    assert mp.sign(_mp_det_hat(path, 59 / 119)) == mp.sign(_mp_det_hat(path, 60 / 119)) == 1


def test_monotone_only_where_the_derivative_keeps_its_sign(f2):
    """``monotone_on`` proves one zero in a crossing's bracket (mpmath: the difference
    quotients across it share one sign) and never in the sample interval holding the
    root pair, where det J goes + - + (mpmath) so its derivative changes sign."""
    model, path, fs = f2
    f_arb = lambda x: model.det_j_arb(*path.at_certified(x))  # noqa: E731
    c = certify_crossing(f_arb, 0.496219522192856)
    a, b = (float(x) for x in c.bracket)
    assert monotone_on(fs, a, b)
    with mp.workdps(40):
        m = (mp.mpf(a) + b) / 2
        q = [(_mp_det_hat(path, x + mp.mpf("1e-12")) - _mp_det_hat(path, x)) for x in (a, m, b)]
    assert len({mp.sign(v) for v in q}) == 1
    assert not monotone_on(fs, 59 / 119, 60 / 119)
