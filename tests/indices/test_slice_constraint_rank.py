"""The farthest point of a sliced zonotope depends on the removed rows G_{S^c} only
through their row space (Kühne et al., eqs. (14), (16)); the vertex enumerations work
on an orthonormal basis of it (distkin.indices.constraint_basis).  Checked against
Qhull on the same slice (the paper's polytope algorithm, capability.hull_worst_best),
against numpy's SVD, and by invariance under scaling and mixing of the removed rows.

QA round E found the best case -inf ("empty slice") at an exactly singular wrench map
with no torque about z, and drifting with the scale of the torque row near it."""

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from distkin.errors import ConditioningWarning
from distkin.indices import best_case_output, max_sensitivities, worst_case_output
from distkin.indices.constraint_basis import constraint_basis
from distkin.indices.slice_farthest import slab_farthest_unit, slice_farthest_unit
from distkin.indices.zonotope import RANK_TOL

FORCE = (0, 1, 2)


def _hull_best(G, keep):
    """Qhull's farthest point of the slice, G of full row rank."""
    return best_case_output(G, -1.0, 1.0, keep, method="hull")


def _all_routes(J, keep=FORCE):
    """The slice's farthest point of the wrench map Jᵀ by every route: the numpy
    enumeration, the split-sign kernel, the Gray-code walk, and max_sensitivities."""
    G = np.ascontiguousarray(J.T)
    name = "force" if tuple(keep) == FORCE else "torque"
    with warnings.catch_warnings():      # its twist parts at a singular J warn (unused)
        warnings.filterwarnings("ignore", "maximum sensitivities.*Moore-Penrose",
                                ConditioningWarning)
        sens = max_sensitivities(J[None])[name][0]
    return [best_case_output(G, -1.0, 1.0, keep),
            slice_farthest_unit(G[None], keep)[0],
            slice_farthest_unit(G[None], keep, walk=True)[0],
            slice_farthest_unit(J[None], keep, transposed=True)[0],
            sens]


# ------------------------------------------------------------------ the basis itself
@pytest.mark.parametrize("transposed", [False, True])
@pytest.mark.parametrize("case", ["regular", "scaled", "mixed", "zero", "tiny", "dependent"])
def test_basis_spans_the_row_space_with_the_rank_of_the_svd(case, transposed):
    """Orthonormal rows, the projector of numpy's SVD on the kept rank, and the rank
    numpy's matrix_rank gives at tolerance RANK_TOL times the largest row norm."""
    rng = np.random.default_rng(7)
    G = rng.normal(size=(6, 8))
    Sc = [3, 4, 5]
    if case == "scaled":
        G[4] *= 1e-9                                   # Cholesky route
    elif case == "mixed":
        G[4] = G[3] + 1e-7 * G[4]                      # nearly dependent: MGS route
    elif case == "zero":
        G[5] = 0.0
    elif case == "tiny":
        G[5] *= 1e-14                                  # below RANK_TOL: treated as zero
    elif case == "dependent":
        G[5] = 2 * G[3] - G[4]
    A = G.T[None] if transposed else G[None]
    Gq, rank = constraint_basis(A, Sc, tol=RANK_TOL, transposed=transposed)
    Q = (Gq[0].T if transposed else Gq[0])[Sc]
    scale = np.linalg.norm(G, axis=1).max()
    expect = np.linalg.matrix_rank(G[Sc], tol=RANK_TOL * scale)
    if case == "tiny":
        expect = 2
    assert rank[0] == expect
    r = rank[0]
    assert np.allclose(Q[:r] @ Q[:r].T, np.eye(r), atol=1e-12)
    assert np.all(Q[r:] == 0)
    keep_rows = G[Sc] if case != "tiny" else G[[3, 4]]
    _, s, Vt = np.linalg.svd(keep_rows)
    V = Vt[:r]
    assert np.allclose(Q[:r].T @ Q[:r], V.T @ V, atol=1e-8)
    # the kept output rows are untouched
    S = [0, 1, 2]
    assert np.array_equal((Gq[0].T if transposed else Gq[0])[S], G[S])


def test_basis_keeps_nan_poses_nan_and_does_not_touch_its_input():
    G = np.random.default_rng(1).normal(size=(3, 6, 8))
    G[1, 4, 2] = np.nan
    before = G.copy()
    Gq, rank = constraint_basis(G, [3, 4, 5], tol=RANK_TOL)
    assert np.array_equal(G, before, equal_nan=True)
    assert rank.tolist() == [3, 3, 3]
    assert np.isnan(Gq[1, 3:]).any() and np.isfinite(Gq[[0, 2]]).all()


# -------------------------------------------------------------- singular wrench maps
@pytest.mark.parametrize("L", [6, 8])
def test_no_torque_about_z_gives_the_slice_of_the_other_rows(L):
    """J with a zero column m_z (no actuator makes torque about z): the force slice at
    zero torque is the slice of the five other rows (m_z = 0 holds for every p); Qhull
    on those five rows is the reference.  It was -inf."""
    rng = np.random.default_rng(5)
    J = rng.normal(size=(L, 6))
    J[:, 5] = 0.0
    ref = _hull_best(J.T[:5], FORCE)
    assert np.isfinite(ref) and ref > 0
    for v in _all_routes(J):
        assert v == pytest.approx(ref, rel=1e-10)
    # the worst case on the same slice is finite too (the flat route), and below it
    assert 0 < worst_case_output(J.T, -1.0, 1.0, FORCE) < ref


@pytest.mark.parametrize("eps", [1e-3, 1e-8, 1e-11])
def test_a_small_torque_row_is_still_a_constraint(eps):
    """Scaling the removed row m_z by eps > 0 does not change the slice: every route
    equals Qhull at eps = 1 (it drifted to 4.10 against 4.84 at eps = 3e-13, and was
    -inf at 3e-14)."""
    rng = np.random.default_rng(5)
    J = rng.normal(size=(8, 6))
    ref = _hull_best(J.T, FORCE)
    J[:, 5] *= eps
    for v in _all_routes(J):
        assert v == pytest.approx(ref, rel=1e-9)


def test_below_the_rank_tolerance_the_row_is_zero_for_best_and_worst_alike():
    """m_z scaled by 1e-14 (σmin/σmax of Jᵀ below RANK_TOL): best and worst case both
    take the pose as exactly singular, and give the values of m_z = 0."""
    rng = np.random.default_rng(5)
    J = rng.normal(size=(8, 6))
    col = J[:, 5].copy()
    J[:, 5] = 0.0
    best0 = _all_routes(J)
    worst0 = worst_case_output(J.T, -1.0, 1.0, FORCE)
    J[:, 5] = 1e-14 * col
    for a, b in zip(_all_routes(J), best0):
        assert a == pytest.approx(b, rel=1e-10)
    assert worst_case_output(J.T, -1.0, 1.0, FORCE) == pytest.approx(worst0, rel=1e-10)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), keep=st.sampled_from([FORCE, (3, 4, 5)]),
       logc=st.floats(0, 4))
def test_mixing_the_removed_rows_changes_nothing(seed, keep, logc):
    """Replacing G_{S^c} by T·G_{S^c} (T invertible, condition number up to 1e4) keeps
    the row space, so every route keeps its value (within the rounding that T's
    conditioning brings)."""
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(8, 6))
    Sc = [i for i in range(6) if i not in keep]
    U, _, Vt = np.linalg.svd(rng.normal(size=(3, 3)))
    T = U @ np.diag([1.0, 10 ** (-logc / 2), 10 ** -logc]) @ Vt
    ref = _all_routes(J, keep)[0]
    J2 = J.copy()
    J2[:, Sc] = J[:, Sc] @ T.T
    for v in _all_routes(J2, keep):
        assert v == pytest.approx(ref, rel=1e-12 * 10 ** (2 * logc) + 1e-10)


# ---------------------------------------------------------- the slab of a square J
def test_a_singular_square_jacobian_has_an_unbounded_twist_slice():
    """L = 6: the translational slice {v : |J_S v|∞ <= 1} holds the null line of J_S
    when its columns are dependent, so the sensitivity is +inf (it was -inf, "empty").
    Next to it the value is finite and grows as 1/δ."""
    rng = np.random.default_rng(1)
    J = rng.normal(size=(6, 6))
    J[:, 2] = J[:, 0] + J[:, 1]
    s = max_sensitivities(J[None])
    assert s["translational"][0] == np.inf
    assert np.all(np.isfinite([s[k][0] for k in ("rotational", "force", "torque")]))
    # the null line: (1, 1, -1) is in the slice at every length
    assert np.abs(J[:, :3] @ (1e6 * np.array([1.0, 1.0, -1.0]))).max() < 1e-6
    vals = []
    for d in (1e-4, 1e-6):
        Jd = J.copy()
        Jd[:, 2] += d * rng.normal(size=6)
        vals.append(slab_farthest_unit(np.ascontiguousarray(Jd[None, :, :3]))[0])
    assert np.all(np.isfinite(vals)) and vals[1] > 30 * vals[0]
