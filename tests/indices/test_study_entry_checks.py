"""evaluate_poses checks its input once at the entry, for the compiled route and the numpy
route alike (QA round H 1, 6, 12): ST, the actuator limits, the poses, route and
sensitivity.  Before, the compiled route read ST of length 8 as its first 6, gave inf σ
for ST of length 3, a negative force for a negative nominal torque and 0 for a zero
velocity limit, while the numpy route raised.  Valid input keeps the values of an
independent route (numpy's SVD of ST⁻¹Jᵀ; the capabilities linear in the limit)."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.indices import study

P = np.array([[0, 0, 0.3, 0, 0, 0.0], [0.02, -0.03, 0.32, 0.1, -0.2, 0.3]])
ACT = dict(study.ACTUATORS)

BAD = [
    ("ST length 3 (QA)", dict(ST=(15, 15, 15)), "ST"),
    ("ST length 8 (QA)", dict(ST=(15,) * 8), "ST"),
    ("ST negative (QA)", dict(ST=(-15, 15, 15, 1, 1, 1)), "ST"),
    ("ST zero (QA)", dict(ST=(15, 15, 15, 1, 1, 0)), "ST"),
    ("ST NaN", dict(ST=(15, 15, 15, 1, 1, np.nan)), "ST"),
    ("nominal torque negative (QA)", dict(actuators=ACT | {"nominal_torque": -2.5}),
     "actuators.nominal_torque"),
    ("velocity negative (QA)", dict(actuators=ACT | {"velocity": -51}), "actuators.velocity"),
    ("velocity zero (QA)", dict(actuators=ACT | {"velocity": 0}), "actuators.velocity"),
    ("stall torque inf", dict(actuators=ACT | {"stall_torque": np.inf}),
     "actuators.stall_torque"),
    ("limit text", dict(actuators=ACT | {"stall_torque": "x"}), "actuators.stall_torque"),
    ("poses (6,) (QA)", dict(poses=P[0]), "poses"),
    ("poses (N, 3) (QA)", dict(poses=P[:, :3]), "poses"),
    ("poses NaN (QA)", dict(poses=np.where(np.eye(2, 6) > 0, np.nan, P)), "poses"),
    ("route Numpy (QA)", dict(route="Numpy"), "route"),
    ("sensitivity typo", dict(sensitivity="slices"), "sensitivity"),
]


@pytest.mark.parametrize("compiled", [True, False])
@pytest.mark.parametrize("what, kw, field", BAD, ids=[b[0] for b in BAD])
def test_bad_input_is_refused_on_both_routes(presets, what, kw, field, compiled):
    kw = dict(kw)
    poses = kw.pop("poses", P)
    with pytest.raises(InputError) as err:
        study.evaluate_poses(presets["octopod"], poses, compiled=compiled, **kw)
    assert err.value.field == field and f"{field}: expected " in str(err.value)


def test_a_non_default_scaling_reaches_the_compiled_kernel(presets):
    """σ of ST⁻¹Jᵀ for ST = (10, 20, 30, 1, 2, 3), against numpy's SVD written out."""
    m = presets["octopod"]
    ST = (10.0, 20.0, 30.0, 1.0, 2.0, 3.0)
    ok, v = study.evaluate_poses(m, P, ST=ST)
    Jq, Jx = m.jq_jx(P[ok])
    J = Jx / Jq[..., None]
    s = np.linalg.svd(np.swapaxes(J, 1, 2) / np.array(ST)[:, None], compute_uv=False)
    np.testing.assert_allclose(v["sigma_min"], s[:, -1], rtol=1e-12)
    np.testing.assert_allclose(v["sigma_max"], s[:, 0], rtol=1e-12)


@pytest.mark.parametrize("compiled", [True, False])
def test_capabilities_scale_with_positive_limits(presets, compiled):
    """Each capability is linear in its limit (the box scales): doubling the limits
    doubles them, on both routes."""
    m = presets["octopod"]
    _, a = study.evaluate_poses(m, P, compiled=compiled)
    _, b = study.evaluate_poses(m, P, compiled=compiled,
                                actuators={k: 2 * x for k, x in ACT.items()})
    for cap in study.CAPABILITIES + study.TRUE_VELOCITIES:
        np.testing.assert_allclose(b[cap[0]], 2 * a[cap[0]], rtol=1e-12)
