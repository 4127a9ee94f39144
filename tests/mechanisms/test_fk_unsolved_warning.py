"""The Python API's fast forward kinematics warns when it returns no answer ("fast or
warn", QA 2026-12: leg lengths in mm given to the 6-UPS example, which is in m, gave an
absurd pose with ``converged``/``in_range`` False and no word; the CLI refuses, and
``strict=True`` raises).

References: the pose the joint values came from (the IK of a known pose: the same
values in m are solved silently), the ratio of the lengths given to the legs' lengths at
home computed here from the joints, and the flags the result carries."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from distkin.errors import ConditioningWarning, InfeasibleError
from distkin.mechanisms import preset

EXAMPLE = Path(__file__).parents[2] / "examples" / "gough_stewart_6ups.toml"
POSE = np.array([0.010, 0.005, 0.410, 0.05, -0.05, 0.08])


@pytest.fixture(scope="module")
def gough():
    from distkin.app.scene import load_scene
    return load_scene(EXAMPLE).mechanism


def _home_lengths(mech):
    d = mech.arrays()
    from distkin.spatial import rotation_matrix
    P = mech.home[:3] + d["p"] @ rotation_matrix(mech.home[3:]).T
    return np.linalg.norm(P - d["B"], axis=1)


def test_lengths_in_mm_warn_with_the_values_and_a_unit_hint(gough):
    q, valid = gough.inverse_kinematics(POSE)
    assert valid.all()
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)      # solved: silent
        fk = gough.forward_kinematics(q)
    np.testing.assert_allclose(fk.pose, POSE, atol=1e-12)
    with pytest.warns(ConditioningWarning) as rec:
        bad = gough.forward_kinematics(q * 1000)
    assert not bad.ok and not bad.in_range and not bad.verified    # the flags, as before
    (w,) = [w for w in rec if issubclass(w.category, ConditioningWarning)]
    msg = str(w.message)
    assert f"{q[0] * 1000:.6g}" in msg and "(m)" in msg
    assert "in_range False" in msg and "outside its range [0.35, 0.55] m" in msg
    ratio = np.median(q * 1000) / np.mean(_home_lengths(gough))
    assert f"are {ratio:.3g} x the mechanism's leg length at home" in msg
    assert "lengths in another unit?" in msg
    with pytest.raises(InfeasibleError):                         # strict: unchanged
        gough.forward_kinematics(q * 1000, strict=True)


def test_warn_false_keeps_the_flags_alone(gough):
    q, _ = gough.inverse_kinematics(POSE)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)
        bad = gough.forward_kinematics(q * 1000, warn=False)
    assert not bad.ok and not bad.in_range


def test_a_batch_warns_once_naming_how_many(gough):
    q, _ = gough.inverse_kinematics(POSE)
    batch = np.array([q, q * 1000, q])
    with pytest.warns(ConditioningWarning) as rec:
        fk = gough.forward_kinematics(batch)
    msgs = [str(w.message) for w in rec if issubclass(w.category, ConditioningWarning)]
    assert len(msgs) == 1 and "1 of 3 joint-value sets" in msgs[0] and "set 1" in msgs[0]
    np.testing.assert_array_equal(fk.ok, [True, False, True])
    np.testing.assert_allclose(fk.pose[[0, 2]], [POSE, POSE], atol=1e-12)


def test_crank_angles_in_degrees_warn_on_a_preset_without_ranges():
    """The RSS presets declare no joint ranges: nothing refused the angles, and the
    unconverged answer came back silently."""
    mech = preset("hunt")
    pose = mech.home + np.array([0.01, 0.0, 0.0, 0.05, 0.0, 0.0])
    q, _ = mech.inverse_kinematics(pose)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)
        np.testing.assert_allclose(mech.forward_kinematics(q).pose, pose, atol=1e-12)
    with pytest.warns(ConditioningWarning, match=r"degrees\?") as rec:
        bad = mech.forward_kinematics(np.degrees(q))
    assert not bad.ok
    msg = str(rec[0].message)
    assert f"{np.max(np.abs(np.degrees(q))):.6g} rad" in msg and f"converged {bad.converged}" in msg


def test_the_tiers_do_not_warn_of_their_start(gough):
    """precise and certified start from the fast answer and refuse or answer for
    themselves: no warning of a start they then solve."""
    q, _ = gough.inverse_kinematics(POSE)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)
        res = gough.forward_kinematics(q, guess=POSE + [0.3, 0, 0, 0, 0, 0], max_iter=1,
                                       method="precise")
    np.testing.assert_allclose(res.pose, POSE, atol=1e-12)


def test_strict_names_lengths_in_mm_unreachable_not_a_singularity(gough, tmp_path):
    """Strict FK of lengths in mm given to the 6-UPS without declared ranges (nothing
    refuses them first) raised SingularConfigurationError, "expected a pose away from
    singularities", though Gauss-Newton had not converged to any pose: now a NotFoundError
    saying the values look out of the mechanism's reach, with the unit slip of the
    non-strict warning (fk_failure.unit_hint).  References: the non-strict flags (not
    converged, last iterate past max_condition: what made it "near a singularity"), and
    the ratio of the lengths to the legs at home computed here from the joints."""
    from distkin.app.scene import load_scene
    from distkin.errors import NotFoundError
    text = EXAMPLE.read_text(encoding="utf-8")
    free = tmp_path / "gough_no_ranges.toml"
    free.write_text("\n".join(ln for ln in text.splitlines() if not ln.startswith("range")),
                    encoding="utf-8")
    mech = load_scene(free).mechanism
    q, _ = mech.inverse_kinematics(POSE)
    with pytest.warns(ConditioningWarning):
        flags = mech.forward_kinematics(q * 1000)
    assert not flags.converged and flags.near_singular and flags.in_range
    with pytest.raises(NotFoundError) as exc:
        mech.forward_kinematics(q * 1000, strict=True)
    msg = exc.value.one_line()
    ratio = np.median(q * 1000) / np.mean(_home_lengths(gough))
    assert "expected joint values within the mechanism's reach" in msg
    assert f"{q[0] * 1000:.6g}" in msg and "look out of its reach" in msg
    assert f"are {ratio:.3g} x the mechanism's leg length at home" in msg
    assert "not a pose near a singularity" in msg and exc.value.field == "q"
    np.testing.assert_allclose(mech.forward_kinematics(q, strict=True).pose, POSE, atol=1e-12)


def test_strict_names_crank_degrees_unreachable_not_a_singularity():
    """The hunt preset's crank angles in degrees: strict FK said "near a singularity"
    (the stranded iterate's condition 541 > 300); now the unit slip, as the warning.
    Reference: the degrees of the IK angles of a known pose."""
    from distkin.errors import NotFoundError
    mech = preset("hunt")
    q, _ = mech.inverse_kinematics(mech.home + np.array([0.01, 0.0, 0.0, 0.05, 0.0, 0.0]))
    with pytest.warns(ConditioningWarning):
        flags = mech.forward_kinematics(np.degrees(q))
    assert not flags.converged and flags.near_singular
    with pytest.raises(NotFoundError, match=r"look out of its reach: crank angles up to "
                       + f"{np.max(np.abs(np.degrees(q))):.6g}" + r" rad given, beyond one "
                       r"turn: degrees\?"):
        mech.forward_kinematics(np.degrees(q), strict=True)
