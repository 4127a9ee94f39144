"""The certified ``singularity`` query on a leg table reports as ``det_J`` the midpoint of
the arb ball that decided its sign (QA: at the 90° twist of the Δ 6-6 platform of [1]
Sec. VI, ``examples/delta66_indices.toml``, the report said "det J 0 (its arb ball's
midpoint)" beside "det J certified < 0": the 0 was the 128-bit ball's midpoint, which
contains 0, the sign that of the 256-bit ball, -2.7e-17).  Reference: the sign of the
unnormalised det Jhat of the same float64 joints, exact in fmpq (the normalisation
divides each row by a positive length)."""

import numpy as np

from distkin.app.queries.leg_singularity import leg_lines, singularity_tests_at
from distkin.app.scene import loads_scene
from distkin.singularity.conditions import certified_sign, jacobian_det

SCENE = """
[units]
length = "cm"
angle = "deg"
[mechanism]
kind = "legs"
name = "delta66"
octahedral = { base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]] }
height = 17
stroke = [14, 22]
force = 50
origin = [3, "sqrt(3)", 0]
offsets = ["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]
[[query]]
type = "singularity"
pose = [6, "sqrt(12)", 17, 0, 0, 90]
method = "certified"
"""


def test_det_j_is_the_midpoint_of_the_deciding_ball():
    mech = loads_scene(SCENE).mechanism
    pose = np.array([0.06, 0.02 * np.sqrt(3), 0.17, 0, 0, np.pi / 2])   # the 90° twist
    out = singularity_tests_at(mech, pose, "certified")
    b, p = leg_lines(mech, pose)
    exact = certified_sign(jacobian_det(b, p, normalised=False, method="certified"))
    assert exact != 0 and out["det_sign_certified"] == exact
    assert np.sign(out["det_J"]) == exact           # was 0.0 (the 128-bit midpoint)
    assert 0 < abs(out["det_J"]) < 1e-9 and out["near_singular"] and out["singular"] is False
