"""QA T 9, T 10: one Jacobian (L, 6) where the batched (N, L, 6) is taken, as
``worst_case_output`` does; ``condition_number``'s ``method``; ``gii`` refuses
σmin > σmax at a pose.

Independent routes: the true velocity worst case as the smallest q̇max/‖J_i,S‖ over the
legs (a loop over rows), κ from numpy's SVD of ST⁻¹Jᵀ written out here, and the single
answers against the batched ones."""

import numpy as np
import pytest

from distkin import indices as ix
from distkin.errors import InputError

RNG = np.random.default_rng(20261127)


def _J(L=8):
    return RNG.normal(size=(L, 6))


def test_true_velocity_worst_one_J():
    J = _J()
    got = ix.true_velocity_worst(J, 2.5, [0, 1, 2])
    want = min(2.5 / np.linalg.norm(J[i, :3]) for i in range(len(J)))
    assert isinstance(got, float)
    assert got == pytest.approx(want, rel=1e-14)
    assert ix.true_velocity_worst(J[None], 2.5, [0, 1, 2])[0] == got


@pytest.mark.parametrize("shape", [(6,), (2, 2, 8, 6)])
def test_true_velocity_worst_names_the_shapes(shape):
    with pytest.raises(InputError) as exc:
        ix.true_velocity_worst(np.ones(shape), 1.0, [0])
    assert exc.value.field == "J"
    assert "(L, d) or (N, L, d)" in str(exc.value) and str(shape) in str(exc.value)
    assert "(N, N, N)" not in str(exc.value)


@pytest.mark.parametrize("mode", ["slice", "projection"])
def test_max_sensitivities_one_J(mode):
    J = _J()
    one = ix.max_sensitivities(J, mode)
    batch = ix.max_sensitivities(np.stack([J, _J()]), mode)
    assert set(one) == set(batch)
    for k, v in one.items():
        assert isinstance(v, float) and v == pytest.approx(batch[k][0], rel=1e-12)
    # with the optional precomputed arguments of one pose
    s = np.linalg.svd(J, compute_uv=False)
    again = ix.max_sensitivities(J, mode, twist=np.linalg.pinv(J), kappa=s[-1] / s[0])
    for k, v in one.items():
        assert again[k] == pytest.approx(v, rel=1e-12)


def test_max_sensitivities_refuses_4d():
    with pytest.raises(InputError) as exc:
        ix.max_sensitivities(np.ones((2, 2, 8, 6)))
    assert exc.value.field == "J" and "(L, 6) or (N, L, 6)" in str(exc.value)


def test_condition_number_method():
    J = _J()
    st = np.asarray(ix.ST_DEFAULT, dtype=float)
    s = np.linalg.svd(J.T / st[:, None], compute_uv=False)
    assert ix.condition_number(J, method="fast") == pytest.approx(s[-1] / s[0], rel=1e-13)
    for bad in ("precise", "certified", "exact"):
        with pytest.raises(InputError) as exc:
            ix.condition_number(J, method=bad)
        assert exc.value.field == "method" and repr(bad) in str(exc.value)


@pytest.mark.parametrize("smin, smax, pose", [([3.0, 0.2], [1.0, 2.0], 0),
                                              ([0.1, 3.0], [1.0, 2.0], 1),
                                              ([3.0], [1.0], 0)])
def test_gii_refuses_smin_above_smax(smin, smax, pose):
    with pytest.raises(InputError) as exc:
        ix.gii(smin, smax)
    assert exc.value.field == "smin" and f"at pose {pose}" in str(exc.value)


def test_gii_in_unit_range():
    J = RNG.normal(size=(20, 8, 6))
    smin, smax = ix.scaled_singular_values(J)
    g, lo, hi = ix.gii(smin, smax)
    assert 0.0 <= g <= 1.0 and g == pytest.approx(smin.min() / smax.max(), rel=1e-15)
    assert ix.gii([1.0], [1.0])[0] == 1.0              # σmin = σmax allowed


def test_condition_number_of_one_j_is_a_float():
    """One (L, 6) J gave a 0-d array (QA T 9, left by fix-x); a batch stays an array."""
    from distkin.indices import condition_number
    from distkin.mechanisms import preset
    m = preset("octopod")
    J = m.jacobian(m.home)
    k = condition_number(J)
    assert type(k) is float and 0 < k <= 1
    batch = condition_number(np.stack([J, J]))
    assert batch.shape == (2,) and batch[0] == k
