"""The certified classification does not depend on the device's physical scale.

``B >= |I - Y Jx|`` mixes entries of order ``s`` and ``1/s`` (the moment columns of
``Jx`` are in m); the Perron vector of the Collatz-Wielandt test used an absolute
regularisation, so the contraction bound of a box of a HEXA scaled by 1e-6 grew from
0.0595 to 0.214 and most of the workspace fell to "undecided (rank)".  Reference: the
spectral radius of ``B`` by ``numpy.linalg.eigvals`` and the same box at scale 1.
"""

import warnings

import numpy as np
import pytest

from distkin.certify.batch import certify_batch
from distkin.certify.boxes import block_balance, certify_box, perron_vectors
from distkin.mechanisms.rss import preset

LENGTHS = ("l0", "l1", "l2", "lp", "ld", "z0", "l3")
LO = np.array([0.0, 0.0, 0.30, 0.0, 0.0, 0.0])
HI = np.array([0.009375, 0.009375, 0.309375, 0.0, 0.0, 0.0])


def _scaled_matrix(s, seed=3):
    rng = np.random.default_rng(seed)
    B = 0.02 * rng.random((6, 6))
    d = np.array([1.0, 1.0, 1.0, 1.0 / s, 1.0 / s, 1.0 / s])
    return B, B * d[:, None] / d[None, :]


@pytest.mark.parametrize("s", [1e-6, 2.0 ** -20, 1e6])
def test_perron_bound_matches_spectral_radius_at_any_scale(s):
    B, Bs = _scaled_matrix(s)
    rho = max(abs(np.linalg.eigvals(B)))
    for M in (B, Bs):
        v = perron_vectors(M[None])[0]
        assert np.all(v > 0) and 0.5 <= v.max() < 1.0
        bound = max((M @ v) / v)
        assert rho <= bound * (1 + 1e-12)
        assert bound == pytest.approx(rho, rel=1e-6)


def test_power_of_two_scale_is_exact():
    B, Bs = _scaled_matrix(2.0 ** -20)
    assert block_balance(Bs[None])[0] == block_balance(B[None])[0] * 2.0 ** 20
    v, vs = perron_vectors(np.stack([B, Bs]))
    d = np.array([1.0, 1.0, 1.0, 2.0 ** 20, 2.0 ** 20, 2.0 ** 20])
    e = np.frexp((v * d).max())[1]
    np.testing.assert_array_equal(vs, np.ldexp(v * d, -e))


def _hexa(s):
    base = preset("hexa", layout="radial")
    return preset("hexa", layout="radial", **{k: getattr(base, k) * s for k in LENGTHS})


@pytest.mark.parametrize("s", [2.0 ** -20, 1e-6])
def test_box_contraction_is_scale_invariant(s):
    """The QA's box: x, y in [0, 9.375 mm], z in [300, 309.375 mm], no rotation."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = {}
        for scale in (1.0, s):
            m = _hexa(scale)
            ks = m.kernels("arb")
            k = np.array([scale, scale, scale, 1.0, 1.0, 1.0])
            v = certify_box(m, ks, LO * k, HI * k, form="quadratic")
            b = certify_batch(m, ks, (LO * k)[None], (HI * k)[None], (0, 1, 2))
            out[scale] = (v, b)
    (v1, b1), (vs, bs) = out[1.0], out[s]
    assert v1.status == vs.status == 1 and int(b1["status"][0]) == int(bs["status"][0]) == 1
    assert vs.contraction == pytest.approx(v1.contraction, rel=1e-8)
    assert float(bs["contraction"][0]) == pytest.approx(float(b1["contraction"][0]), rel=1e-8)
    assert v1.contraction < 0.1
    # σmin(Jx) mixes unitless and m columns: its bound scales like the moment columns
    assert vs.sigma_lower == pytest.approx(v1.sigma_lower * s, rel=1e-6)
