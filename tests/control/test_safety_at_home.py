"""Unit-slipped or impossible ``[safety]`` values are refused or warned about at load
(QA: ``workspace_m = 75``, ``workspace_rad = 30``, ``workspace_m = 1e300`` and
``sigma_min = 50`` loaded silently; with the last the device was held the whole run,
reported ``completed``).  The bounds are checked against the device's Jacobian at home
from the mechanism's own numpy route (:meth:`preset(...).jacobian`), not the
controller's kernels the loader uses, and against π."""

import math

import numpy as np
import pytest

from distkin.app.control_commands import _scene_and_inputs
from distkin.control.config import loads_control_scene
from distkin.control.scene_checks import WORKSPACE_SIZE_FACTOR
from distkin.errors import InputError
from distkin.mechanisms import preset

from control_helpers import scene_text

S = np.array([15.0, 15.0, 15.0, 1.0, 1.0, 1.0])


@pytest.fixture(scope="module")
def octo_home():
    m = preset("octo")
    sv = np.linalg.svd(np.asarray(m.jacobian(m.home)).reshape(-1, 6) / S, compute_uv=False)
    return sv[-1], sv[0] / sv[-1], float(np.linalg.norm(m.home[:3]))


def _load(**kw):
    return loads_control_scene(scene_text(**kw), "s.toml")


def test_workspace_rad_beyond_pi_is_refused():
    with pytest.raises(InputError, match=r"30 rad") as ei:
        _load(workspace_rad=30)
    assert ei.value.field == "safety.workspace_rad"
    assert _load(workspace_rad=math.pi).safety.workspace_rad == math.pi
    with pytest.raises(InputError):
        _load(workspace_rad=math.nextafter(math.pi, 4.0))


def test_sigma_min_above_the_device_at_home_is_refused(octo_home):
    lo, cond, _ = octo_home
    assert _load(sigma_min=lo * 0.999).safety.sigma_min == pytest.approx(lo * 0.999)
    for bad in (lo * 1.001, 50):
        with pytest.raises(InputError) as ei:
            _load(sigma_min=bad)
        assert ei.value.field == "safety.sigma_min"
        assert f"{lo:.4g} rad" in str(ei.value) and f"{bad:g} rad" in str(ei.value)


def test_max_condition_below_the_device_at_home_is_refused(octo_home):
    _, cond, _ = octo_home
    cond = float(cond)
    text = scene_text().replace("[safety]\n", "[safety]\nmax_condition = %r\n")
    assert loads_control_scene(text % (cond * 1.001), "s").safety.max_condition > cond
    with pytest.raises(InputError) as ei:
        loads_control_scene(text % (cond * 0.999), "s")
    assert ei.value.field == "safety.max_condition" and f"{cond:.4g}" in str(ei.value)


@pytest.mark.parametrize("value", [75, 1e300])
def test_a_workspace_far_beyond_the_device_warns_once(octo_home, tmp_path, monkeypatch,
                                                      capsys, value):
    size = max(octo_home[2], preset("octo").length_scale)
    assert value > WORKSPACE_SIZE_FACTOR * size
    s = _load(workspace_m=value)
    assert [f for f, _ in s.warnings] == ["safety.workspace_m"]
    # the commands print it as one line (distkin control and distkin sim load it so)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text(scene_text(workspace_m=value), encoding="utf-8")
    _scene_and_inputs("s.toml")
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("distkin: warning: safety.workspace_m: ")
    assert f"{value:g} m" in err[0]


def test_the_examples_and_a_plausible_workspace_load_without_warnings(octo_home):
    size = max(octo_home[2], preset("octo").length_scale)
    assert _load(workspace_m=WORKSPACE_SIZE_FACTOR * size * 0.99).warnings == ()
    assert _load().warnings == ()
