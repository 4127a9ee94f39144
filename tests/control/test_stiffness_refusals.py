"""distkin.control.stiffness refuses poses where no stiffness exists instead of returning
numbers: a pose the legs cannot reach (review: 5 m above the Octo's home the servo
stiffness came out as 2.5 N/m along x, from finite but meaningless Jacobian rows) and a
singular Jacobian (previously numpy's LinAlgError, or a huge number)."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.control.stiffness import servo_stiffness, stiffness_summary
from distkin.errors import InfeasibleError, SingularConfigurationError
from distkin.mechanisms import preset


def test_an_unreachable_pose_is_refused_naming_it():
    """5 m above home every platform joint is more than 4.5 m from every base joint,
    while a leg spans at most l2 + l3 = 349.7 mm (docs/design.md §5): no leg closes."""
    mech = preset("octo")
    far = mech.home + np.array([0, 0, 5.0, 0, 0, 0])
    with pytest.raises(InfeasibleError) as exc:
        servo_stiffness(mech, 110.0, far)
    msg = str(exc.value)
    assert exc.value.field == "poses" and "5.3" in msg and "1 of 1" in msg
    # the cube of the paper's 27 positions grown to ±1 m: 26 of them out of reach
    with pytest.raises(InfeasibleError, match="26 of 27"):
        stiffness_summary(mech, 110.0, half=1.0)


class _RankFive:
    """A stand-in mechanism: reachable everywhere, J of rank 5 (no stiffness along z)."""

    home = np.zeros(6)

    def jacobian(self, P):
        J = np.zeros((len(P), 6, 6))
        J[:, [0, 1, 3, 4, 5], [0, 1, 3, 4, 5]] = 5.0
        return J

    def reachable(self, P):
        return np.ones(len(P), bool)


def test_a_singular_jacobian_is_refused():
    with pytest.raises(SingularConfigurationError) as exc:
        servo_stiffness(_RankFive(), 110.0, np.zeros((2, 6)))
    assert exc.value.field == "poses" and "rank 6" in str(exc.value)


def test_reachable_poses_still_give_kp_j_t_j():
    """The full-rank stand-in: J = 5 I gives K = 25 kp I, a reading of 25 kp N/m."""
    class Full(_RankFive):
        def jacobian(self, P):
            return np.broadcast_to(5.0 * np.eye(6), (len(P), 6, 6)).copy()
    np.testing.assert_allclose(servo_stiffness(Full(), 110.0, np.zeros((1, 6))),
                               [[2750.0] * 3], rtol=1e-14)


def test_a_pose_matrix_or_a_short_pose_is_refused_naming_the_shape():
    mech = preset("octo")
    from distkin.errors import InputError
    for bad, shape in ((np.eye(4), "(4, 4)"), (np.zeros(3), "(3,)")):
        with pytest.raises(InputError) as exc:
            servo_stiffness(mech, 110.0, bad)
        assert exc.value.field == "poses" and shape in str(exc.value)
