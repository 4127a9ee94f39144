"""Forward kinematics: a local failure names the start, and the stopping test is scale
invariant (QA report M, findings 3 and 6).

* From a bad guess Gauss-Newton lands on another crank branch.  That is no proof that no
  pose exists (the pose the angles came from is one: the independent reference), so the
  error is ``not_found`` naming ``guess``, not ``infeasible`` naming ``angles``.
* The hunt leg table scaled by 1e-9 and 1e6: the pose the angles came from (the
  analytic reference, scaled) is found to ~1e-14 relative, converged and verified, with
  the iterations of the unscaled table.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from distkin.app.cli import main
from distkin.errors import NotFoundError
from distkin.mechanisms import LegMechanism, preset
from distkin.mechanisms.forward_tiers import forward_tier

POSE = np.array([0.06, 0.06, 0.36, 0.4, 0.4, 0.4])


def test_bad_guess_is_not_found_naming_guess(tmp_path, capsys):
    m = preset("hunt")
    q, valid = m.inverse_kinematics(POSE)
    assert valid.all()                                     # a pose with these angles exists
    with pytest.raises(NotFoundError, match="not a proof") as exc:
        forward_tier(m, q, np.zeros(6), method="fast")
    assert exc.value.field == "guess" and "another guess" in exc.value.hint
    good = forward_tier(m, q, POSE + 0.003, method="fast")
    assert np.abs(good.pose - POSE).max() < 1e-12
    angles = ", ".join(f'"{v:.17g}"' for v in q)
    f = tmp_path / "s.toml"
    f.write_text(f'[units]\nlength = "mm"\nangle = "rad"\n[mechanism]\nkind = "rss"\n'
                 f'preset = "hunt"\n[[query]]\ntype = "forward_kinematics"\n'
                 f'angles = [{angles}]\nguess = [0, 0, 0, 0, 0, 0]\n')
    assert main(["run", str(f), "--json", str(tmp_path / "o.json")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("distkin: error: query[0].guess: ")
    assert "not a proof that no such pose exists" in err[0]
    rec = json.loads((tmp_path / "o.json").read_text())["queries"][0]
    assert rec["error"]["kind"] == "not_found"


def _scaled_hunt(s):
    legs = []
    for leg in preset("hunt").leg_description().leg_table:
        d = leg.as_dict()
        for k in ("base", "platform", "offset"):
            d[k] = tuple(np.array(d[k]) * s)
        d["crank"], d["distal"] = d["crank"] * s, d["distal"] * s
        d.pop("range", None), d.pop("limit", None)
        legs.append(d)
    return LegMechanism(f"hunt{s:g}", tuple(legs), (0, 0, 0.3 * s, 0, 0, 0), route="numpy")


@pytest.mark.parametrize("s", [1e-9, 1e6])
def test_fk_scale_invariant(s):
    X = np.array([0.01, -0.02, 0.32, 0.1, -0.05, 0.08])
    one, big = _scaled_hunt(1.0), _scaled_hunt(s)
    Xs = np.r_[X[:3] * s, X[3:]]
    fk1 = one.forward_kinematics(one.inverse_kinematics(X)[0])
    fks = big.forward_kinematics(big.inverse_kinematics(Xs)[0])
    assert fk1.ok and fks.ok, fks.message
    rel = np.r_[(fks.pose[:3] - Xs[:3]) / s, fks.pose[3:] - X[3:]]
    assert np.abs(rel).max() < 1e-13
    assert abs(fks.iterations - fk1.iterations) <= 1
    est = forward_tier(big, big.inverse_kinematics(Xs)[0], method="fast").error
    assert np.all(est[:3] / s < 1e-12)                     # the estimate scales too
