"""Bad input to the index functions fails at the entry point with
:class:`~distkin.errors.InputError` naming the argument, as ``worst_case_output`` does
(STYLE.md rule 7; one checker: distkin.argcheck and capability's own), instead of a
LinAlgError, a LAPACK message on stderr, or a finite number from NaN or a negative
limit.  Valid input still gives the values of an independent route."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.indices import (condition_number, max_sensitivities, output_generators,
                             reading_singular_values, scaled_singular_values,
                             true_velocity_worst, worst_case_output)

RNG = np.random.default_rng(7)
J = RNG.normal(size=(3, 8, 6))


def _with(value, at=(0, 2, 3)):
    out = J.copy()
    out[at] = value
    return out


BAD = [
    ("condition_number NaN (QA)", lambda: condition_number(np.full((8, 6), np.nan)), "J"),
    ("condition_number inf (QA)", lambda: condition_number(np.full((8, 6), np.inf)), "J"),
    ("condition_number one inf", lambda: condition_number(_with(np.inf)), "J"),
    ("condition_number ST inf", lambda: condition_number(J, (15, 15, 15, 1, 1, np.inf)), "ST"),
    ("scaled_singular_values text", lambda: scaled_singular_values("J"), "J"),
    ("max_sensitivities NaN (QA)", lambda: max_sensitivities(np.full((2, 8, 6), np.nan)), "J"),
    ("max_sensitivities projection", lambda: max_sensitivities(_with(np.nan), "projection"),
     "J"),
    ("max_sensitivities L < 6", lambda: max_sensitivities(J[:, :3]), "J"),
    ("max_sensitivities twist", lambda: max_sensitivities(J, twist=np.zeros((3, 6, 7))),
     "twist"),
    ("true_velocity_worst negative (QA)", lambda: true_velocity_worst(J, -1, [0, 1, 2]),
     "qdot_max"),
    ("true_velocity_worst NaN J (QA)", lambda: true_velocity_worst(_with(np.nan), 51, [0, 1, 2]),
     "J"),
    ("true_velocity_worst inf limit", lambda: true_velocity_worst(J, np.inf, [0, 1, 2]),
     "qdot_max"),
    ("true_velocity_worst keep", lambda: true_velocity_worst(J, 51, [0, 6]), "keep"),
    ("true_velocity_worst repeated keep", lambda: true_velocity_worst(J, 51, [1, 1]), "keep"),
    ("output_generators inf", lambda: output_generators(_with(np.inf)), "J"),
    ("output_generators mass", lambda: output_generators(J, mass=[1, 1, 1, 0, 1, 1]), "mass"),
    ("reading_singular_values Jq", lambda: reading_singular_values(J, Jq=np.full((3, 8), np.nan)),
     "Jq"),
]


@pytest.mark.parametrize("what, call, field", BAD, ids=[b[0] for b in BAD])
def test_bad_input_names_the_argument(what, call, field, capfd):
    with pytest.raises(InputError) as err:
        call()
    assert err.value.field == field and str(err.value).startswith(f"{field}: expected ")
    assert "DLASCL" not in capfd.readouterr().err            # LAPACK never reached


def test_same_check_as_worst_case_output():
    """The generator of the wrench, Jᵀ, with a NaN: worst_case_output refuses it with the
    same kind of error as the functions above."""
    with pytest.raises(InputError, match="finite"):
        worst_case_output(np.swapaxes(_with(np.nan), 1, 2), -1, 1)
    with pytest.raises(InputError, match="finite"):
        condition_number(_with(np.nan))


def test_valid_input_gives_the_independent_values():
    """κ from numpy's SVD of ST⁻¹Jᵀ written out; the true-velocity worst case as the
    nearest slab plane, min q̇max / |J_i,S| (velocity_set's docstring), by a loop."""
    st = np.array([15, 15, 15, 1, 1, 1.0])
    s = np.linalg.svd(np.swapaxes(J, 1, 2) / st[:, None], compute_uv=False)
    np.testing.assert_allclose(condition_number(J), s[:, -1] / s[:, 0], rtol=1e-14)
    ref = [min(51 / np.linalg.norm(J[n, i, :3]) for i in range(8)) for n in range(3)]
    np.testing.assert_allclose(true_velocity_worst(J, np.float32(51), (0, 1, 2)), ref,
                               rtol=1e-14)
    assert set(max_sensitivities(J)) == {"translational", "rotational", "force", "torque"}


# ---------------------------------------------------------------- QA 23b, 10
@pytest.mark.parametrize("J", [np.zeros((0, 6)), np.zeros((4, 0, 6))])
def test_a_jacobian_without_legs_is_refused(J):
    """σmin/σmax of a map from no actuators are undefined (SVD of a 6 x 0 matrix): an
    InputError naming J and the shape, not numpy's IndexError."""
    from distkin.indices import condition_number, scaled_singular_values
    for f in (condition_number, scaled_singular_values):
        with pytest.raises(InputError, match=r"at least one leg.*got shape") as e:
            f(J)
        assert e.value.field == "J"


def test_an_empty_batch_of_jacobians_still_works():
    from distkin.indices import condition_number
    assert condition_number(np.zeros((0, 8, 6))).shape == (0,)


@pytest.mark.parametrize("kw, field, unit", [
    ({"z0": "x"}, "z0", "m"), ({"half": -1}, "half", "m"), ({"rot_deg": -5}, "rot_deg", "deg"),
    ({"step": float("nan")}, "step", "m"), ({"rot_step_deg": None}, "rot_step_deg", "deg")])
def test_table2_grid_names_the_argument_and_its_unit(kw, field, unit):
    from distkin.indices import table2_grid
    with pytest.raises(InputError, match=unit) as e:
        table2_grid(**kw)
    assert e.value.field == field


def test_a_grid_step_too_small_for_its_range_is_refused_before_building():
    """1e-9 m over ±75 mm is 1.5e8 values per axis (it ran for minutes): refused, with
    the count; Table II's own grid (16 positions, 9 angles per axis) is built."""
    from distkin.indices import table2_grid
    with pytest.raises(InputError, match=r"at most 100000 values.*1\.5e\+08"):
        table2_grid(step=1e-9)
    g = table2_grid()
    assert (len(g.x), len(g.rx)) == (16, 9)
