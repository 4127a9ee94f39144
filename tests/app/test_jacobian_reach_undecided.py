"""The jacobian query decides reachability as the inverse_kinematics query does (QA 25b
finding 1): at a Hunt pose where leg 3's reach margin is within rounding of 0 the fast
jacobian said ``reachable: true``, ``singular: true``, kappa 3.6e-18 and "SINGULAR pose:
J has rank 1 of 6", while inverse_kinematics said "undecided (legs [3])" and the
certified tier finds leg 3 not closing (reach margin -7.7e-19 ± 2.1e-36 m²).

Reference: the certified tier's own verdict (arb balls of the reach margins,
``ik_tier(..., "certified")``) at the pose and at its 12 float64 neighbours (one ulp
either way in each coordinate), where it says "does not close" at some and "closes" at
others: the fast query must never call reachable, nor give a κ or a singularity verdict
at, a pose the certified tier does not find reachable, and must say undecided there."""

from __future__ import annotations

import json
import re
import warnings

import numpy as np
import pytest

from distkin.app.cli import main
from distkin.mechanisms import preset
from distkin.mechanisms.kinematics_tiers import ik_tier

X0 = np.array([0.17666779032645294, -0.22122566698793225, 0.33619183073700115,
               -0.024573879650131178, -0.01959130800237457, -0.009331353213514307])


def _neighbours():
    out = [X0]
    for k in range(6):
        for d in (-np.inf, np.inf):
            y = X0.copy()
            y[k] = np.nextafter(y[k], d)
            out.append(y)
    return np.array(out)


def _run(tmp_path, capsys, poses, method):
    rows = ", ".join("[" + ", ".join(repr(float(v)) for v in x) + "]" for x in poses)
    f = tmp_path / "j.toml"
    f.write_text('[units]\nlength = "m"\nangle = "rad"\n[mechanism]\nkind = "rss"\n'
                 'preset = "hunt"\n'
                 f'[[query]]\ntype = "jacobian"\nmethod = "{method}"\nposes = [{rows}]\n'
                 f'[[query]]\ntype = "inverse_kinematics"\nmethod = "{method}"\n'
                 f'poses = [{rows}]\n', encoding="utf-8")
    code = main(["run", str(f), "--no-progress", "--json", str(tmp_path / "o.json")])
    out, err = capsys.readouterr()
    assert code == 0, err
    q = json.loads((tmp_path / "o.json").read_text())["queries"]
    return q[0]["result"]["poses"], q[1]["result"]["poses"], out


def _certified_reachable(X):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = ik_tier(preset("hunt"), X, "certified")
    return (res.certified & res.valid).all(axis=-1), res.infeasible.any(axis=-1)


@pytest.mark.filterwarnings("ignore::distkin.errors.ConditioningWarning")
@pytest.mark.parametrize("method", ["fast", "certified"])
def test_jacobian_reachable_as_the_ik_and_never_beyond_the_certified_tier(
        tmp_path, capsys, method):
    X = _neighbours()
    reach, fails = _certified_reachable(X)
    assert fails.any() and reach.any()          # both verdicts occur among them
    jac, ik, out = _run(tmp_path, capsys, X, method)
    texts = re.split(r"\n  pose \d+: ", out.split("[1] inverse_kinematics")[0])[1:]
    assert len(texts) == len(X)
    for i, (r, k, text) in enumerate(zip(jac, ik, texts)):
        assert r["reachable"] is k["reachable"]          # the IK query's verdict
        assert r["reach_undecided"] == k["reach_undecided"]
        if method == "certified":                       # decided here at every pose
            assert r["reachable"] is bool(reach[i])
            assert r["undecided_legs"] == []
        elif not reach[i]:
            assert r["reachable"] is False
        if not r["reachable"]:
            assert r["kappa"] is None and r["singular"] is None
            assert r["singular_values"] is None and r["kappa_bounds"] is None
            assert "SINGULAR" not in text and "kappa = undefined" in text
            assert r["undecided_legs"] or r["unreachable_legs"] == [3]
        else:
            assert r["kappa"] is not None and r["singular"] is not None
            assert "kappa = undefined" not in text
        if r["undecided_legs"]:
            assert r["undecided_legs"] == [3]
            assert "undecided (legs [3])" in text
            assert 'method = "certified" decides' in text
            assert "kappa = undefined (reachability undecided)" in text
    if method == "fast":          # the QA pose itself: undecided in float64
        assert jac[0]["undecided_legs"] == [3] and jac[0]["reachable"] is False
    else:
        assert jac[0]["unreachable_legs"] == [3]
