"""Scene files with ``kind = "rss"``: parsing, units, queries and the CLI."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from distkin.app.cli import run_scene
from distkin.errors import InputError
from distkin.mechanisms import preset
from distkin.app.scene import load_scene, loads_scene

ROOT = Path(__file__).resolve().parents[2]

BASE = """
[units]
length = "mm"
angle = "deg"

[mechanism]
kind = "rss"
preset = "octo"
{extra}

[[query]]
{query}
"""


def _scene(extra="", query='type = "inverse_kinematics"\npose = [0, 0, 300, 0, 0, 0]'):
    return loads_scene(BASE.format(extra=extra, query=query))


def test_units_and_overrides():
    s = _scene('l0 = "170"\ngamma = 10\nmass = "0.2"')
    m = s.mechanism
    assert m.l0 == pytest.approx(0.170, rel=1e-15) and m.gamma == pytest.approx(math.radians(10))
    assert m.mass == 0.2 and m.l2 == pytest.approx(0.0256)
    assert m == preset("octo", l0=0.170, gamma=math.radians(10), mass=0.2)


def test_queries_match_api():
    s = load_scene(ROOT / "examples" / "rss_octopod.toml")
    records, texts, worst = run_scene(s)
    assert worst == 0, records
    m = preset("octopod")
    ik = records[0]["result"]["poses"]
    P = np.array([r["pose"] for r in ik])
    np.testing.assert_allclose(P[1], [0.040, -0.030, 0.330] + list(np.radians([15, -10, 20])),
                               rtol=1e-15)
    q, valid = m.inverse_kinematics(P)
    np.testing.assert_array_equal(np.array([r["q"] for r in ik]), q)
    assert [r["reachable"] for r in ik] == list(valid.all(axis=1))
    jac = records[1]["result"]["poses"][0]
    np.testing.assert_array_equal(np.array(jac["J"]), m.jacobian(P[1]))
    assert np.array(jac["Mq"]).shape == (8, 8)
    fk = records[2]["result"]
    assert fk["converged"] and fk["residual"] < 1e-5       # angles rounded to 0.01 deg
    np.testing.assert_allclose(fk["pose"][:3], [0.025, -0.015, 0.320], atol=1e-4)
    # the pose whose IK the scene's angles are (its comment), to first order in the
    # rounding: |(dp, dw)| <= |dq| / sigma_min(J) with |dq_i| <= 0.005 deg
    from distkin.spatial import pose_error
    target = np.array([0.025, -0.015, 0.320, *np.radians([10, -5, 15])])
    bound = np.sqrt(8) * np.radians(0.005) / np.linalg.svd(m.jacobian(target),
                                                           compute_uv=False)[-1]
    dp, dw = pose_error(np.array(fk["pose"]), target)
    assert np.hypot(dp, dw) <= bound
    assert " mm" in texts[0] and " deg" in texts[0] and "kappa" in texts[1]


@pytest.mark.parametrize("extra, query, field", [
    ('l9 = 3', 'type = "inverse_kinematics"\npose = [0, 0, 300, 0, 0, 0]', "mechanism"),
    ('legs = 7', 'type = "inverse_kinematics"\npose = [0, 0, 300, 0, 0, 0]', "mechanism.legs"),
    ('l1 = -5', 'type = "inverse_kinematics"\npose = [0, 0, 300, 0, 0, 0]', "mechanism.l1"),
    ('', 'type = "inverse_kinematics"\npose = [0, 0, 300, 0, 0]', "query[0].pose"),
    ('', 'type = "inverse_kinematics"\nposes = [[0, 0, 300, 0, 0, "x"]]', "query[0].poses[0][5]"),
    ('', 'type = "jacobian"\npose = [0, 0, 300, 0, 0, 0]\nmass_matrix = 1', "query[0].mass_matrix"),
    ('', 'type = "forward_kinematics"\nangles = [0, 0, 0]', "query[0].angles"),
    ('', 'type = "forward_kinematics"\nangle = [0, 0, 0]', "query[0]"),
    ('', 'type = "cayley_menger"\ndeterminants = ["D(1,2,3)"]', "query[0].type"),
])
def test_bad_fields(extra, query, field):
    with pytest.raises(InputError) as info:
        _scene(extra, query)
    assert info.value.field.startswith(field), info.value.field
    assert any(w in info.value.message for w in ("expected", "unknown", "needs"))


def test_unitless_and_unknown_preset():
    with pytest.raises(InputError, match="physical length unit"):
        loads_scene('[units]\nlength = "none"\n[mechanism]\nkind = "rss"\npreset = "hexa"\n'
                    '[[query]]\ntype = "jacobian"\npose = [0, 0, 0.3, 0, 0, 0]')
    with pytest.raises(InputError, match="expected one of"):
        loads_scene('[mechanism]\nkind = "rss"\npreset = "tripod"\n'
                    '[[query]]\ntype = "jacobian"\npose = [0, 0, 0.3, 0, 0, 0]')


def test_fk_failure_is_an_error_record():
    s = _scene(query='type = "forward_kinematics"\nangles = [80, -80, 80, -80, 80, -80, 80, -80]'
               '\nmax_iter = 3')
    records, _, worst = run_scene(s)
    assert worst == 2 and records[0]["status"] == "error"
    assert records[0]["error"]["kind"] == "not_found"         # local: from home, no proof
    assert "not a proof that none exists" in records[0]["error"]["message"]


def test_cli_run_and_plots(tmp_path):
    import os
    env = dict(os.environ, DISTKIN_CACHE=str(tmp_path / "cache"))
    r = subprocess.run([sys.executable, "-m", "distkin", "run", "examples/rss_octo_custom.toml",
                        "--plots", str(tmp_path), "--json", str(tmp_path / "out.json")],
                       capture_output=True, text=True, cwd=ROOT, timeout=300, env=env)
    assert r.returncode == 0, r.stderr
    assert len(list(tmp_path.glob("*.png"))) == 2
    r = subprocess.run([sys.executable, "-m", "distkin", "run", "-"], capture_output=True,
                       text=True, cwd=ROOT, timeout=600)
    assert r.returncode == 2
