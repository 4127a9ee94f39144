"""The three tiers of the forward kinematics of RSS and leg mechanisms
(distkin.mechanisms.forward_tiers): the certified box (Krawczyk) holds the precise pose
and the closed-form IK of its points; refusals at singularities; bad input."""

import math
import warnings

import numpy as np
import pytest
from scipy.optimize import brentq

from distkin.errors import ConditioningWarning, InputError, UncertifiedError
from distkin.mechanisms import preset
from distkin.mechanisms.forward_tiers import forward_tier

OFFSET = np.array([0.012, -0.018, 0.015, 0.12, -0.07, 0.2])   # m, rad from home


def _q(mech, pose):
    q, valid = mech.inverse_kinematics(np.asarray(pose)[None])
    assert valid.all()
    return q[0]


@pytest.mark.parametrize("name", ["hunt", "hexa", "octo"])
def test_certified_box_holds_the_precise_pose(name):
    """The certified box (radii ~1e-16 m / rad) contains the precise tier's pose at 40
    digits (Newton in mpmath: another arithmetic and another iteration), and the fast
    pose is within its own error estimate of the box's centre."""
    mech = preset(name)
    X = mech.home + OFFSET
    q = _q(mech, X)
    cert = forward_tier(mech, q, method="certified")
    # L = 8: the float angles are inconsistent at the rounding level; compare the pose of
    # the same six legs (the least-squares pose of all eight is ~1e-17 m away)
    prec = forward_tier(mech, q, method="precise", dps=40,
                        legs=cert.legs if mech.legs > 6 else None)
    fast = forward_tier(mech, q)
    assert cert.certified and not prec.certified and cert.method == "certified"
    # the closure residual over the box: a finite bound at the float level (L = 6: every
    # closure holds exactly somewhere in the box)
    assert 0 <= cert.residual < 1e-12
    assert np.all(cert.error < 1e-14) and cert.contraction < 1
    for k in range(6):
        assert abs(prec.native[k] - cert.pose[k]) <= cert.error[k], (name, k)
    assert np.all(np.abs(fast.pose - cert.pose) <= fast.error + cert.error)
    # the precise error is of the float pose: its rounding, the 1e-30 estimate beside it
    assert all(e <= math.ulp(v) / 2 + 1e-30 for v, e in zip(prec.pose, prec.error))
    assert np.all(np.abs(prec.pose - cert.pose) <= prec.error + cert.error)
    assert prec.residual < (1e-35 if mech.legs == 6 else 1e-15)
    if mech.legs > 6:
        assert len(cert.legs) == 6 and set(cert.other_legs) == \
            set(range(1, 9)) - set(cert.legs)
        assert all(0 <= v < 1e-14 for v in cert.other_legs.values())   # consistent angles


def test_certified_box_reproduces_the_joint_values_by_closed_form_ik():
    """A second route: the closed-form IK (float) of the certified centre gives back the
    joint values within |J| times the box (plus rounding), on the Octo (L = 8)."""
    mech = preset("octo")
    q = _q(mech, mech.home + OFFSET)
    cert = forward_tier(mech, q, method="certified")
    J = mech.jacobian(cert.pose[None])[0]
    back = _q(mech, cert.pose)
    assert np.all(np.abs(back - q) <= np.abs(J) @ cert.error + 1e-13)


def test_redundant_inconsistent_angles_are_bounded_not_hidden():
    """Octo, one crank angle moved by 1e-5 rad: no pose closes all eight legs.  The
    certified tier proves the pose of six legs (here chosen by the caller) and bounds the
    other two closure errors, one of them about 1e-5 rad x |dPhi/dq| (positive: not
    closed; the other, whose angle is unchanged, closes); the precise tier gives the
    least-squares pose, with a residual."""
    mech = preset("octo")
    q = _q(mech, mech.home + OFFSET)
    with warnings.catch_warnings():         # consistent angles: nothing to say (QA 23b 8)
        warnings.simplefilter("error", ConditioningWarning)
        forward_tier(mech, q, method="certified", legs=[1, 2, 3, 4, 5, 6])
        assert forward_tier(mech, q, method="precise").residual < 1e-15
    q[7] += 1e-5
    # and they say so: legs left open beyond the fast tier's residual_tol (QA 23b 8)
    with pytest.warns(ConditioningWarning, match=r"rms closure .*legs \[7, 8\].* stay open "
                                                 r"by up to 1\.\d+e-06 m .* inconsistent"):
        cert = forward_tier(mech, q, method="certified", legs=[1, 2, 3, 4, 5, 6])
    assert cert.legs == (1, 2, 3, 4, 5, 6)
    assert cert.other_legs[8] > 1e-8 and cert.other_legs[7] < 1e-14
    with pytest.warns(ConditioningWarning, match=r"rms closure residual .* least-squares"):
        prec = forward_tier(mech, q, method="precise")
    assert prec.residual > 1e-9


def _hunt_singular():
    mech = preset("hunt")

    def det(a):
        return np.linalg.det(mech.jq_jx(np.array([[0, 0, mech.z0, 0, 0, a]]))[1][0])
    a = brentq(det, np.radians(90), np.radians(100), xtol=1e-15)
    return mech, np.array([0, 0, mech.z0, 0, 0, a])


def test_singular_configuration_is_refused():
    """Hunt's singularity (det Jx = 0 near rz = 95 deg, Kühne et al. Fig. 4): two
    assembly modes merge; Krawczyk's test cannot contract and the certified tier raises
    UncertifiedError naming the reason, never a box."""
    mech, X = _hunt_singular()
    q = _q(mech, X)
    with pytest.raises(UncertifiedError, match="near singular"):
        forward_tier(mech, q, X, method="certified")
    # the scene query: an error record naming the scene's field, not the Python argument
    from distkin.app.cli import run_scene
    from distkin.app.scene import loads_scene
    text = ("[mechanism]\nkind = \"rss\"\npreset = \"hunt\"\n[[query]]\n"
            "type = \"forward_kinematics\"\nangles = " + repr([float(v) for v in q])
            + "\nguess = " + repr([float(v) for v in X]) + "\nmethod = \"certified\"\n")
    (rec,), _, worst = run_scene(loads_scene(text))
    assert rec["status"] == "error" and rec["error"]["kind"] == "uncertified"
    assert rec["error"]["message"].startswith("query[0].angles: expected a box of poses")


def test_bad_input_names_the_field():
    mech = preset("hunt")
    q = _q(mech, mech.home)
    with pytest.raises(InputError, match="method"):
        forward_tier(mech, q, method="exact")
    with pytest.raises(InputError, match="legs"):
        forward_tier(mech, q, method="certified", legs=[1, 2, 3])
    with pytest.raises(InputError, match="legs"):
        forward_tier(mech, q, legs=[1, 2, 3, 4, 5, 6])          # fast: all legs
    with pytest.raises(InputError, match="6 joint values"):
        forward_tier(mech, q[:5], method="certified")
    with pytest.raises(InputError, match="bits"):
        forward_tier(mech, q, method="precise", bits=256)
    with pytest.raises(InputError, match="53..4096"):
        forward_tier(mech, q, method="certified", bits=16)


def test_bits_set_the_certified_precision():
    """At 53 bits the balls are float64-wide: the box is still proved and holds the
    128-bit box's centre within both radii; the query names its precision."""
    mech = preset("hexa")
    q = _q(mech, mech.home + OFFSET)
    low = forward_tier(mech, q, method="certified", bits=53)
    high = forward_tier(mech, q, method="certified")
    assert low.certified and np.all(low.error >= high.error)
    assert np.all(np.abs(low.pose - high.pose) <= low.error + high.error)


_SCENE = """
[units]
length = "mm"
angle = "deg"
[mechanism]
kind = "rss"
preset = "octo"
[[query]]
type = "forward_kinematics"
angles = {angles}
{extra}
"""


def _scene(mech, q, extra=""):
    from distkin.app.cli import run_scene
    from distkin.app.scene import loads_scene
    angles = "[" + ", ".join(repr(float(v)) for v in np.degrees(q)) + "]"
    (rec,), texts, _ = run_scene(loads_scene(_SCENE.format(angles=angles, extra=extra)))
    assert rec["status"] == "ok", rec
    return rec["result"], "\n".join(texts)


def test_query_tiers_json_and_text():
    """The scene query: without ``method`` the pose is the Python fast answer bit for bit
    (now with ``pose_error``); ``certified`` reports the proved radii in the JSON and in
    the scene's units, and its box holds the precise query's pose of the same legs."""
    mech = preset("octo")
    q = _q(mech, mech.home + OFFSET)
    qs = np.radians(np.degrees(q))               # the angles as the scene gives them
    fast, _ = _scene(mech, q)
    assert np.array_equal(fast["pose"], mech.forward_kinematics(qs).pose)
    assert fast["method"] == "fast" and not fast["certified"] and len(fast["pose_error"]) == 6
    cert, text = _scene(mech, q, 'method = "certified"\nbits = 200')
    assert cert["certified"] and len(cert["legs"]) == 6
    assert set(cert["other_legs_closure_bound"]) == {str(v) for v in range(1, 9)} - \
        {str(v) for v in cert["legs"]}
    assert "arb balls at 200 bits" in text and " mm, orientation " in text
    prec, _ = _scene(mech, q, f'method = "precise"\ndps = 40\nlegs = {cert["legs"]}')
    assert prec["dps"] == 40
    # (the JSON's precise pose is rounded to float64: one unit in the last place more)
    assert np.all(np.abs(np.array(prec["pose"]) - cert["pose"])
                  <= np.array(cert["pose_error"]) + np.spacing(np.abs(cert["pose"])))


def test_query_bad_legs_name_the_field():
    from distkin.app.scene import loads_scene
    base = _SCENE.format(angles="[0, 0, 0, 0, 0, 0, 0, 0]", extra="{}")
    for extra, expect in (('method = "certified"\nlegs = [1, 2, 3]', "6 distinct leg numbers"),
                          ('method = "certified"\nlegs = [1, 2, 3, 4, 5, 9]', "1..8"),
                          ('legs = [1, 2, 3, 4, 5, 6]', "method 'fast'"),
                          ('method = "exact"', "'certified'"),
                          ('method = "precise"\nbits = 200', "'bits' with method 'certified'"),
                          ('method = "certified"\nbits = 5000', "53..4096")):
        with pytest.raises(InputError, match=expect) as err:
            loads_scene(base.format(extra))
        assert "query[0]." in str(err.value)


def test_ik_and_jacobian_queries_take_bits():
    """The same ``bits`` field on the inverse_kinematics and jacobian queries: the JSON
    names the precision the balls were computed at."""
    from distkin.app.cli import run_scene
    from distkin.app.scene import loads_scene
    for qtype in ("inverse_kinematics", "jacobian"):
        text = (_SCENE.split("[[query]]")[0] + f'[[query]]\ntype = "{qtype}"\n'
                'pose = [10, -5, 320, 3, -2, 5]\nmethod = "certified"\nbits = 96\n')
        (rec,), _, _ = run_scene(loads_scene(text))
        assert rec["status"] == "ok" and rec["result"]["precision"] == "arb at 96 bits"


def test_prismatic_legs_scene_certified_against_precise():
    """A user's 6-UPS Gough-Stewart platform (examples/gough_stewart_6ups.toml, prismatic
    legs: q are lengths in m): the certified box holds the precise pose and the
    residual bound is finite."""
    from pathlib import Path

    from distkin.app.scene import load_scene
    root = Path(__file__).resolve().parents[2]
    mech = load_scene(str(root / "examples" / "gough_stewart_6ups.toml")).mechanism
    q = _q(mech, mech.home + np.array([0.01, 0.005, 0.01, 0.05, -0.05, 0.08]))
    cert = forward_tier(mech, q, method="certified")
    prec = forward_tier(mech, q, method="precise", dps=40)
    assert cert.certified and 0 <= cert.residual < 1e-12
    for k in range(6):
        assert abs(prec.native[k] - cert.pose[k]) <= cert.error[k]
