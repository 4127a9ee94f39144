"""κ of the jacobian query states its accuracy (QA 25a F7): under method precise or
certified it printed a float64 SVD beside the tier's radii with no word on its own
accuracy.  Now ``kappa_bounds`` encloses κ over J ± J_error (Weyl's inequality on the
Jordan-Wielandt matrix, distkin.indices.sigma_bounds): a proof from the certified radii.

References: mpmath's SVD at 40 digits of the precise tier's J (an independent route to
σ and κ), and float64 SVDs of matrices sampled in a box (every one inside the
enclosure, which is not much wider than the box's Frobenius radius)."""

from __future__ import annotations

import json

import mpmath
import numpy as np
import pytest

from distkin.indices.isotropy import ST_DEFAULT, condition_number
from distkin.indices.sigma_bounds import kappa_bounds, scaled_sigma_bounds
from distkin.mechanisms.kinematics_tiers import jacobian_tier

ST = np.asarray(ST_DEFAULT)


def _mp_sigma(values, dps=40):
    """σmin, σmax of ST⁻¹Jᵀ by mpmath's SVD of the precise tier's mpf J."""
    with mpmath.workdps(dps):
        L = len(values)
        W = mpmath.matrix(6, L)
        for j in range(L):
            for i in range(6):
                W[i, j] = values[j][i] / ST[i]
        s = mpmath.svd_r(W, compute_uv=False)
        return min(s), max(s)


@pytest.mark.parametrize("name", ["octopod", "hunt"])
def test_certified_enclosure_holds_the_40_digit_kappa(presets, name):
    mech = presets[name]
    X = mech.home[None] + np.array([[0.04, -0.03, 0.03, 0.26, -0.17, 0.35]])
    cert = jacobian_tier(mech, X, "certified")
    (smin_lo, smin_hi), (smax_lo, smax_hi) = scaled_sigma_bounds(cert.J[0], cert.J_error[0])
    smin, smax = _mp_sigma(jacobian_tier(mech, X, "precise", dps=40).values[0])
    assert smin_lo <= smin <= smin_hi and smax_lo <= smax <= smax_hi
    lo, hi = kappa_bounds(cert.J[0], cert.J_error[0])
    with mpmath.workdps(40):
        kappa = smin / smax
    assert lo <= kappa <= hi
    assert hi - lo < 1e-12 * float(kappa)                  # tight: radii ~1e-16
    assert lo <= condition_number(cert.J, ST_DEFAULT)[0] <= hi


@pytest.mark.parametrize("L", [6, 8])
def test_every_matrix_of_the_box_is_inside(L):
    rng = np.random.default_rng(L)
    J = rng.normal(size=(L, 6)) * [3, 3, 3, 0.3, 0.3, 0.3]
    r = np.abs(rng.normal(size=(L, 6))) * 1e-3
    (a, b), (c, d) = scaled_sigma_bounds(J, r)
    for _ in range(300):
        Jp = J + r * rng.choice([-1.0, 1.0], size=J.shape) * rng.uniform(0, 1, J.shape)
        s = np.linalg.svd(Jp.T / ST[:, None], compute_uv=False)
        assert a <= s[-1] <= b and c <= s[0] <= d
    # not much wider than the box: Weyl's ||E||_F with E the radii over ST
    width = np.linalg.norm(r / ST[None, :])
    assert b - a <= 2.01 * width and d - c <= 2.01 * width
    # a box of radius 0: the float decomposition's own error only
    (a, b), (c, d) = scaled_sigma_bounds(J, np.zeros_like(r))
    s = np.linalg.svd(J.T / ST[:, None], compute_uv=False)
    assert a <= s[-1] <= b and b - a < 1e-13 and d - c < 1e-13


def test_repeated_singular_values_and_no_bound_without_finite_radii(presets):
    """The Octopod's home pose is symmetric (σ come in equal pairs, σmin among them): the
    enclosure needs no separated eigenvalues; an infinite radius (the fast tier's J not
    resolved) gives no bound, never a made-up one."""
    mech = presets["octopod"]
    cert = jacobian_tier(mech, mech.home[None], "certified")
    s = np.linalg.svd(cert.J[0].T / ST[:, None], compute_uv=False)
    assert np.isclose(s[-1], s[-2], rtol=1e-9)          # a repeated σmin
    (a, b), (c, d) = scaled_sigma_bounds(cert.J[0], cert.J_error[0])
    assert a <= s[-1] <= b and c <= s[0] <= d and d - c < 1e-12
    r = cert.J_error[0].copy()
    r[0, 0] = np.inf
    assert scaled_sigma_bounds(cert.J[0], r) is None and kappa_bounds(cert.J[0], r) is None


def test_jacobian_query_states_the_tier_of_kappa(tmp_path, capsys):
    from distkin.app.cli import main
    scene = tmp_path / "j.toml"
    scene.write_text('[units]\nlength = "mm"\nangle = "deg"\n[mechanism]\nkind = "rss"\n'
                     'preset = "octopod"\n[[query]]\ntype = "jacobian"\n'
                     'pose = [40, -30, 330, 15, -10, 20]\nmethod = "certified"\n',
                     encoding="utf-8")
    out = tmp_path / "o.json"
    assert main(["run", str(scene), "--no-progress", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    row = json.loads(out.read_text())["queries"][0]["result"]["poses"][0]
    lo, hi = row["kappa_bounds"]
    assert lo <= row["kappa"] <= hi and hi - lo < 1e-12
    line = next(ln for ln in text.splitlines() if "kappa = " in ln)
    assert "a float64 SVD of J; kappa in [" in line
    assert "certified (arb: Weyl's inequality on the certified J's radii)" in line
