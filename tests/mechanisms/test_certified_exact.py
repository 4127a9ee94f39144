"""The certified tier certifies the stated mechanism, every number exact
(distkin.mechanisms.kinematics_tiers; symbolic's exact model): an RSS preset's parameters,
a leg table's floats, each taken as its exact binary value.

The reference is an independent route: the closed form of Kühne et al., Sec. II-C
(A cos q + B sin q = C, the atan2 of its solution, Jq_ii = dPhi/dq, Jx = -(g, r x g)),
and for a prismatic leg q = |P - B| with its Plücker line (Rojas et al., eq. (5)),
written out here in mpmath at 60 digits from the leg table's floats taken exactly, or
for an RSS preset from its parameters by the reading of Fig. 2 (distkin.mechanisms.
presets: pairs at azimuths 2 pi k / (L/2), tangential axes): no sympy, no generated
code.  Every certified ball (128 bits, radius ~1e-35) must contain it; a kernel whose
constants were rounded to doubles (1e-16 relative) does not.
"""

from __future__ import annotations

from pathlib import Path

import mpmath as mp
import numpy as np
import pytest
from flint import arb

from distkin.app.scene import load_scene
from distkin.exact_roots import working_precision
from distkin.mechanisms import LegMechanism, preset
from distkin.mechanisms.forward_tiers import forward_tier
from distkin.mechanisms.kinematics_tiers import ik_tier, jacobian_tier

ROOT = Path(__file__).resolve().parents[2]
DPS = 60
OFFSETS = np.array([[0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
                    [0.012, -0.007, 0.009, 0.06, -0.04, 0.09],
                    [-0.015, 0.011, -0.006, -0.08, 0.05, -0.03]])


def _x(v):
    """A float as its exact binary value."""
    return mp.mpf(float(v))


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _rotation(rx, ry, rz):
    """R = Rz(rz) Ry(ry) Rx(rx), written out."""
    cx, sx, cy, sy = mp.cos(rx), mp.sin(rx), mp.cos(ry), mp.sin(ry)
    cz, sz = mp.cos(rz), mp.sin(rz)
    return [[cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx],
            [sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx],
            [-sy, cy * sx, cy * cx]]


def _table_legs(mech):
    """The leg table's legs at the current dps, every float its exact value."""
    out = []
    for leg in mech.leg_description().leg_table:
        d = {"prismatic": leg.prismatic, "range": leg.range,
             "B": [_x(c) for c in leg.base], "p": [_x(c) for c in leg.platform]}
        if not leg.prismatic:
            d.update({k: [_x(c) for c in getattr(leg, f)] for k, f in
                      (("o", "offset"), ("u", "crank0"), ("v", "crank90"))},
                     l1=_x(leg.crank), l3=_x(leg.distal), branch=leg.branch)
        out.append(d)
    return out


def _fig2_legs(mech):
    """An RSS preset's legs at the current dps from its parameters taken exactly: pair k
    at azimuth 2 pi k / (L/2), side s = -1, +1; B = l0 e + s ld/2 t, axis
    a = Rz(s beta) t, crank u = a x z (v = z), offset o = s l2 a, platform joint
    p = Rz(s gamma) (lp e + s ld/2 t) (e radial, t tangential); branch +1."""
    assert mech.layout == "tangential"
    L = mech.legs
    l0, l1, l2, l3, lp, ld = (_x(getattr(mech, n)) for n in ("l0", "l1", "l2", "l3", "lp",
                                                              "ld"))
    cb, sb, cg, sg = (f(_x(a)) for a in (mech.beta, mech.gamma) for f in (mp.cos, mp.sin))
    out = []
    for i in range(L):
        k, s = i // 2, (-1 if i % 2 == 0 else 1)
        th = 2 * mp.pi * k / (L // 2)
        e, t = [mp.cos(th), mp.sin(th), 0], [-mp.sin(th), mp.cos(th), 0]
        a = [cb * t[0] - s * sb * t[1], s * sb * t[0] + cb * t[1], 0]
        p0 = [lp * e[j] + s * ld / 2 * t[j] for j in range(3)]
        out.append({"prismatic": False, "range": None, "branch": 1, "l1": l1, "l3": l3,
                    "B": [l0 * e[j] + s * ld / 2 * t[j] for j in range(3)],
                    "u": [a[1], -a[0], 0], "v": [0, 0, 1], "o": [s * l2 * c for c in a],
                    "p": [cg * p0[0] - s * sg * p0[1], s * sg * p0[0] + cg * p0[1], 0]})
    return out


def _legs(mech):
    return _fig2_legs(mech) if mech.kind == "rss" else _table_legs(mech)


def _leg(leg, pose, q=None):
    """Leg ``leg`` (:func:`_legs`) at ``pose`` (6 mpf) at the current dps: {ik, reach,
    jq_jx (7)} and, given its joint value ``q`` (mpf), the closure row [Phi, g, r x g]."""
    R = _rotation(*pose[3:])
    r = [_dot(row, leg["p"]) for row in R]
    P = [pose[k] + r[k] for k in range(3)]
    B = leg["B"]
    if leg["prismatic"]:
        w = [P[k] - B[k] for k in range(3)]
        n2 = _dot(w, w)
        ik = mp.sqrt(n2)
        lo_hi = leg["range"]
        reach = n2 if lo_hi is None else (ik - _x(lo_hi[0])) * (_x(lo_hi[1]) - ik)
        g = [c / ik for c in w]
        out = {"ik": ik, "reach": reach,
               "jq_jx": [mp.mpf(-1)] + [-c for c in g + _cross(r, g)]}
        if q is not None:
            g = [c / q for c in w]
            out["closure"] = [(n2 - q * q) / (2 * q)] + g + _cross(r, g)
        return out
    o, u, v, l1, l3 = leg["o"], leg["u"], leg["v"], leg["l1"], leg["l3"]
    w = [P[k] - B[k] - o[k] for k in range(3)]
    A, Bz = _dot(w, u), _dot(w, v)
    C = (_dot(w, w) + l1 * l1 - l3 * l3) / (2 * l1)
    reach = A * A + Bz * Bz - C * C
    h, s = mp.sqrt(reach), leg["branch"]
    ik = mp.atan2(Bz * C - s * A * h, A * C + s * Bz * h)

    def row(qq):
        # Phi = (C - A cos q - Bz sin q) l1 / l3 and its derivatives (g = dPhi/dP)
        c, sn = mp.cos(qq), mp.sin(qq)
        g = [(w[k] - l1 * (c * u[k] + sn * v[k])) / l3 for k in range(3)]
        return (C - A * c - Bz * sn) * l1 / l3, (A * sn - Bz * c) * l1 / l3, g

    _, jq, g = row(ik)
    out = {"ik": ik, "reach": reach, "jq_jx": [jq] + [-c for c in g + _cross(r, g)]}
    if q is not None:
        phi, _, g = row(q)
        out["closure"] = [phi] + g + _cross(r, g)
    return out


def _holds(ball, v):
    """The certified ``ball`` (a ~1e-35 one) contains the 60-digit value ``v``
    (give or take 1e-50 relative, its own rounding)."""
    assert float(ball.rad()) < 1e-30 * max(1.0, abs(float(v)))
    with working_precision(256):
        return ball.contains(arb(v) + arb(0, 1e-50 * max(1.0, abs(float(v)))))


@pytest.fixture(scope="module",
                params=["octo", "ergin", "rus8_device.toml", "octo as legs"])
def mech(request):
    if request.param.endswith(".toml"):
        return load_scene(ROOT / "examples" / request.param).mechanism
    if request.param.endswith("as legs"):
        # the Octo's float64 leg table as a mechanism of its own: its balls are for the
        # table (cos 90 deg = 6.1e-17), not for the preset's parameters
        m = LegMechanism.from_description(preset("octo").leg_description())
        own = m.kernels("arb").module.SOURCE_SHA256
        assert own != preset("octo").kernels("arb").module.SOURCE_SHA256
        return m
    return preset(request.param)


def test_fig2_reference_is_the_preset():
    """The reference legs of an RSS preset, from its parameters, are its leg table (the
    float64 geometry of distkin.mechanisms.presets) to a few ulps: 1e-15 (m, or unitless)."""
    for name in ("octo", "ergin"):
        m = preset(name)
        table = _table_legs(m)
        with mp.workdps(DPS):
            for ref, leg in zip(_fig2_legs(m), table):
                for k in ("B", "p", "u", "v", "o"):
                    assert max(abs(a - b) for a, b in zip(ref[k], leg[k])) < 1e-15, (name, k)


def test_certified_ik_and_jacobian_contain_the_closed_form(mech):
    X = mech.home + OFFSETS
    ik = ik_tier(mech, X, "certified")
    jac = jacobian_tier(mech, X, "certified")
    assert ik.certified.all() and jac.certified.all()
    reach = mech.kernels("arb").reach
    with mp.workdps(DPS):
        table = _legs(mech)
        for n, x in enumerate(X):
            with working_precision(128):
                margins = reach([arb(float(v)) for v in x])
            pose = [_x(c) for c in x]
            for i, leg in enumerate(table):
                ref = _leg(leg, pose)
                assert _holds(ik.values[n, i], ref["ik"]), (n, i)
                assert _holds(margins[i], ref["reach"]), (n, i)
                assert _holds(jac.jq_values[n, i], ref["jq_jx"][0]), (n, i)
                for k in range(6):
                    assert _holds(jac.jx_values[n, i][k], ref["jq_jx"][1 + k]), (n, i, k)


def test_certified_closure_and_forward_kinematics_contain_the_closed_form(mech):
    """The arb closure kernel at float joint values (taken exactly) off the IK, and the
    certified forward kinematics: its box contains the 60-digit Newton zero of the six
    legs' closures written out above."""
    X = mech.home + OFFSETS[1:]
    Q = mech.inverse_kinematics(X)[0] + 1e-3
    closure = mech.kernels("arb").closure
    with mp.workdps(DPS):
        table = _legs(mech)
        for x, q in zip(X, Q):
            with working_precision(128):
                rows = closure([arb(float(v)) for v in q], [arb(float(v)) for v in x])
            pose = [_x(c) for c in x]
            for i, leg in enumerate(table):
                ref = _leg(leg, pose, _x(q[i]))["closure"]
                for k in range(7):
                    assert _holds(rows[i][k], ref[k]), (i, k)
    q = mech.inverse_kinematics(X[0])[0]
    fk = forward_tier(mech, q, X[0], method="certified")
    legs = [i - 1 for i in fk.legs]
    with mp.workdps(DPS):
        table = _legs(mech)

        def closures(*pose):
            return [_leg(table[i], list(pose), _x(q[i]))["closure"][0] for i in legs]
        zero = mp.findroot(closures, [_x(c) for c in fk.pose])
        assert max(abs(v) for v in closures(*zero)) < mp.mpf(10) ** -55
        for k in range(6):
            assert fk.native[k].contains(arb(zero[k])), k
