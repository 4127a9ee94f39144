"""Every σmin of ST⁻¹Jᵀ the performance study prints carries its unit (QA 25b F3): the
design-criteria lines ("HEXA: 1) held [σmin 0.0522, ...]"), Table III's reasons ("the
worst case follows σmin of Jᵀ (ours 0.0522)", "(ours 0.00218 over ±20°, ST⁻¹Jᵀ; ...)",
"(our σmin 0.00218)") printed it bare, and the JSON's unit block had no entry for
``devices[].diagnostics.sigma_min`` and ``devices[].criteria[].value.sigma_min``.

Reference: the dimensional analysis of Kühne et al. (f = Jᵀτ, eq. (3); ST in N and N·m,
Sec. III-B-2): W = ST⁻¹Jᵀ maps an actuator torque (N·m, the presets' revolute cranks)
or force (N, prismatic legs) to the wrench in units of ST, so its σ are in 1/(N·m) or
1/N, written here as literals (tests/indices/test_sigma_units.py checks the scaling
numerically).  The numbers themselves are the JSON's (unchanged by the unit)."""

from __future__ import annotations

import re

import pytest

from distkin.numfmt import fixed

RSS = """title = "sigma units, revolute"
[units]
length = "mm"
angle = "deg"
[mechanism]
kind = "rss"
preset = "octopod"
[[query]]
type = "performance"
devices = [{ label = "HEXA", preset = "hexa", rotation = 20 },
           { label = "Hunt-type", preset = "hunt", rotation = 20 }]
grid = { half = 25, step = 50, rotation = 20, rotation_step = 20 }
route = "numpy"
workers = 1
"""

PRISMATIC = """title = "sigma units, prismatic"
[units]
length = "cm"
angle = "deg"
[mechanism]
kind = "legs"
name = "griffis_duffy"
octahedral = { base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]] }
height = 17
stroke = [14, 22]
force = 50
mass = "0.17"
inertia = "3e-4"
[[query]]
type = "performance"
grid = { half = 1, step = 2, rotation = 10, rotation_step = 10 }
actuators = { stall_force = 100, speed = 1 }
thresholds = { velocity = "0.5", acceleration = "9.81", force = 0 }
route = "numpy"
workers = 1
"""

NUM = r"(\d+(?:\.\d+)?(?:e[+-]?\d+)?)"
#: every form in which the study prints a σmin of ST⁻¹Jᵀ as a number
FORMS = {"criterion / sensitivity reason": r"σmin " + NUM,
         "wrench reason (no Table IV column)": r"σmin of Jᵀ \(ours " + NUM,
         "wrench reason (beside Table IV)": r"Table IV's \(ours " + NUM}


def _run(tmp, text):
    from distkin.app.cli import run_scene
    from distkin.app.scene import loads_scene
    mp = pytest.MonkeyPatch()
    mp.setenv("DISTKIN_CACHE", str(tmp / "cache"))
    try:
        records, texts, worst = run_scene(loads_scene(text, str(tmp / "s.toml")),
                                          progress=False)
    finally:
        mp.undo()
    assert worst == 0, records[0].get("error")
    return records[0]["result"], texts[0]


@pytest.fixture(scope="module")
def revolute(tmp_path_factory):
    return _run(tmp_path_factory.mktemp("rev"), RSS)


@pytest.fixture(scope="module")
def prismatic(tmp_path_factory):
    return _run(tmp_path_factory.mktemp("pri"), PRISMATIC)


def _bare(text, unit):
    """(form, number, what follows) of every printed σmin not followed by ``unit``."""
    return [(form, m.group(1), text[m.end():m.end() + 12]) for form, rx in FORMS.items()
            for m in re.finditer(rx, text) if not text[m.end():].startswith(f" {unit}")]


def test_every_sigma_min_of_the_revolute_study_has_its_unit(revolute):
    result, text = revolute
    for form, rx in FORMS.items():                     # the premise: each form is printed
        assert re.search(rx, text), form
    assert _bare(text, "1/(N·m)") == []
    assert _bare(result["markdown"], "1/(N·m)") == []  # the JSON's copy of the tables
    for s in result["devices"]:                         # the numbers are the JSON's
        line = next(ln for ln in text.splitlines() if ln.startswith(f"  {s['label']}: 1) "))
        assert f"[σmin {fixed(s['diagnostics']['sigma_min'])} 1/(N·m), all reachable" in line
    hexa = next(s for s in result["devices"] if s["label"] == "HEXA")
    assert (f"the worst case follows σmin of Jᵀ (ours {hexa['diagnostics']['sigma_min']:.3g} "
            "1/(N·m))") in text
    hunt = next(s for s in result["devices"] if s["label"] == "Hunt-type")
    assert f"(ours {hunt['isotropy']['sigma_min']:.3g} 1/(N·m) over ±20°, ST⁻¹Jᵀ" in text


def test_the_json_unit_block_names_the_sigma_min_unit(revolute, prismatic):
    for (result, _), unit in ((revolute, "1/(N·m)"), (prismatic, "1/N")):
        for key in ("devices[].diagnostics.sigma_min", "devices[].criteria[].value.sigma_min"):
            assert result["unit"][key].startswith(f"{unit} (the smallest σ of ST⁻¹Jᵀ"), key
        assert all("sigma_min" in s["diagnostics"] for s in result["devices"])


def test_prismatic_legs_print_sigma_min_per_newton(prismatic):
    result, text = prismatic
    assert re.search(FORMS["criterion / sensitivity reason"], text)
    assert _bare(text, "1/N") == []
    assert "1/(N·m)" not in text.split("Design criteria")[1]
    s = result["devices"][0]
    assert f"[σmin {fixed(s['diagnostics']['sigma_min'])} 1/N, all reachable" in text


def test_devices_of_both_actuator_types_get_their_own_unit_in_the_json():
    """Like Table IV's header (one unit when the devices share it, else by device)."""
    from distkin.app.study_report import _criteria_text, _units_block
    from distkin.indices.study import ACTUATORS
    rev = {"label": "R", "actuator_limits": {"prismatic": [False] * 6}}
    pri = {"label": "P", "actuator_limits": {"prismatic": [True] * 6}}
    got = _units_block(ACTUATORS, [rev, pri])["devices[].diagnostics.sigma_min"]
    assert got.startswith("by device: R 1/(N·m), P 1/N (")
    c = {"number": 1, "held": None, "value": {"sigma_min": None, "all_reachable": None,
                                              "det_sign_changes": None, "note": None}}
    assert "[σmin —, all reachable" in _criteria_text(c, "mm", "1/N")   # no number, no unit
