"""Scenes with ``kind = "legs"``: presets written out as legs (TOML and CSV) give the
same kernels and numbers, errors name the leg and the field, the example scenes run
through ``distkin run`` and ``distkin codegen``."""

from __future__ import annotations

import importlib
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from distkin.app.cli import run_scene
from distkin.app.legs_scene import legs_csv_text, legs_toml_text
from distkin.app.scene import load_scene, loads_scene
from distkin.errors import InputError
from distkin.mechanisms import preset

ROOT = Path(__file__).resolve().parents[2]
PRESETS = ("hunt", "hexa", "ergin", "octopod", "octo")
QUERY = '\n[[query]]\ntype = "inverse_kinematics"\npose = [0, 0, 0.3, 0, 0, 0]\n'


def _written(name, how, tmp_path):
    m = preset(name)
    if how == "csv":
        (tmp_path / "legs.csv").write_text(legs_csv_text(m, length_unit="mm"))
        text = legs_toml_text(m, length_unit="mm", csv_name="legs.csv")
    else:
        text = legs_toml_text(m, length_unit=how)
    text = text.replace("[[query]]", "") + QUERY.replace("0.3", "300" if how != "m" else "0.3")
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return m, load_scene(path).mechanism


@pytest.mark.parametrize("how", ["mm", "m", "csv"])
@pytest.mark.parametrize("name", PRESETS)
def test_preset_written_as_legs_round_trips(name, how, tmp_path):
    """The five presets as [[mechanism.leg]] tables (in mm and in m) and as a CSV leg
    table: the same leg table, the committed module (same source hash) and bit-identical
    IK, J, Jq/Jx and FK."""
    m, lm = _written(name, how, tmp_path)
    assert lm.key() == m.leg_description().key()
    mod = importlib.import_module(f"distkin._generated.rss_{name}")
    assert lm.kernels().module is mod and lm.kernels("scalar").module is mod
    rng = np.random.default_rng(11)
    X = m.home + np.hstack([rng.uniform(-0.03, 0.03, (20, 3)), rng.uniform(-0.2, 0.2, (20, 3))])
    for a, b in ((m.inverse_kinematics(X), lm.inverse_kinematics(X)),
                 (m.jq_jx(X), lm.jq_jx(X)), ((m.jacobian(X),), (lm.jacobian(X),))):
        for x, y in zip(a, b):
            assert np.array_equal(x, y)
    q = m.inverse_kinematics(X[3])[0]
    assert np.array_equal(m.forward_kinematics(q).pose, lm.forward_kinematics(q).pose)
    assert np.array_equal(m.forward_kinematics(q[None]).pose, lm.forward_kinematics(q[None]).pose)


LEG = """
[[mechanism.leg]]
type = "RSS"
base = [100, 0, 0]
platform = [50, 0, 0]
axis = [0, 1, 0]
crank0 = [1, 0, 0]
crank90 = [0, 0, 1]
crank = 50
distal = 300
"""


def _legs_scene(bad_leg="", extra=""):
    legs = [LEG] * 6
    if bad_leg:
        legs[3] = bad_leg
    return ('[units]\nlength = "mm"\nangle = "deg"\n[mechanism]\nkind = "legs"\n'
            f'home = [0, 0, 300, 0, 0, 0]\n{extra}\n' + "".join(legs) + QUERY)


@pytest.mark.parametrize("change, field, words", [
    (("axis = [0, 1, 0]", "axis = [0, 2, 0]"), "mechanism.leg[3].axis", "unit vector"),
    (("crank = 50", "crank = -50"), "mechanism.leg[3].crank", "got -50 (mm)"),
    (("crank = 50", 'crank = "x"'), "mechanism.leg[3].crank", "cannot parse"),
    (("base = [100, 0, 0]", "base = [100, 0]"), "mechanism.leg[3].base", "3 numbers"),
    (("distal = 300", "distal = 300\ncolour = 1"), "mechanism.leg[3]", "colour"),
    (('type = "RSS"', 'type = "SPS"'), "mechanism.leg[3].axis", "prismatic"),
])
def test_bad_leg_fields_are_named(change, field, words):
    with pytest.raises(InputError) as exc:
        loads_scene(_legs_scene(LEG.replace(*change)))
    assert exc.value.field == field and words in exc.value.message, exc.value.one_line()


def test_bad_csv_is_named_and_cli_exits_2(tmp_path):
    m = preset("hunt")
    text = legs_csv_text(m, length_unit="mm").splitlines()
    row = text[3].split(",")
    row[7] = "2"                                            # axis_x of leg[2]: not unit
    text[3] = ",".join(row)
    (tmp_path / "legs.csv").write_text("\n".join(text))
    scene = tmp_path / "s.toml"
    scene.write_text(legs_toml_text(m, csv_name="legs.csv") + QUERY.replace("0.3", "300"))
    with pytest.raises(InputError) as exc:
        load_scene(scene)
    assert exc.value.field == "mechanism.legs_csv[2].axis"
    r = subprocess.run([sys.executable, "-m", "distkin", "run", str(scene)],
                       capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1
    assert "mechanism.legs_csv[2].axis" in r.stderr and "unit vector" in r.stderr
    assert "line 4 of legs.csv" in r.stderr
    scene.write_text(legs_toml_text(m, csv_name="nope.csv") + QUERY.replace("0.3", "300"))
    with pytest.raises(InputError, match="readable CSV"):
        load_scene(scene)


def test_both_or_neither_leg_sources_refused():
    with pytest.raises(InputError, match="exactly one"):
        loads_scene(_legs_scene(extra='legs_csv = "x.csv"'))


@pytest.mark.parametrize("example, types", [("gough_stewart_6ups.toml", {"UPS"}),
                                            ("rus8_device.toml", {"RUS"})])
def test_example_scenes_run(example, types):
    """The two user-defined examples: every query ok; IK and J against the API; FK back
    to the pose whose joint values the scene lists (rounded to 1e-6 mm / deg)."""
    s = load_scene(ROOT / "examples" / example)
    m = s.mechanism
    assert {leg.type for leg in m.leg_table} == types
    records, texts, worst = run_scene(s)
    assert worst == 0, records
    P = np.array([r["pose"] for r in records[0]["result"]["poses"]])
    q, valid = m.inverse_kinematics(P)
    assert np.array_equal(np.array([r["q"] for r in records[0]["result"]["poses"]]), q)
    assert [r["reachable"] for r in records[0]["result"]["poses"]] == [True, True, False]
    fk = records[2]["result"]
    target = np.array([0.010, 0.005, 0.21 if m.L == 8 else 0.41,
                       0.05, -0.05, 0.08])
    assert fk["converged"] and np.abs(np.array(fk["pose"]) - target).max() < 1e-6
    cert = records[-1]["result"]
    assert records[-1]["type"] == "certify_workspace" and cert["regular_fraction"] > 0.5
    if m.L == 8:
        # the study's worst continuous force (compiled route) against the zonotope of
        # distkin.indices.capability at that pose from the mechanism's own Jacobian
        from distkin.indices.capability import worst_case_output
        dev = records[3]["result"]["devices"][0]
        J = m.jacobian(np.array(dev["worst_force_pose"]))
        tau = records[3]["result"]["actuators"]["nominal_torque"]
        f = worst_case_output(J.T, -tau, tau, keep=[0, 1, 2])
        assert f == pytest.approx(dev["table"]["force"]["min"], rel=1e-9)


def test_codegen_of_a_legs_scene_imports_numpy_only(tmp_path):
    """``distkin codegen`` on the 6-UPS example: the module's imports are math and numpy,
    it runs with sympy and distkin blocked, and gives the mechanism's IK and J."""
    env = dict(os.environ)
    out = tmp_path / "gough.py"
    r = subprocess.run([sys.executable, "-m", "distkin", "codegen",
                        str(ROOT / "examples" / "gough_stewart_6ups.toml"), "-o", str(out)],
                       capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    src = out.read_text()
    imports = [ln for ln in src.splitlines() if ln.startswith(("import ", "from "))]
    assert imports == ["import math", "import numpy"]
    code = ("import sys; sys.modules['sympy'] = None; sys.modules['distkin'] = None\n"
            "import json, numpy, gough\n"
            "x = numpy.array([0.01, 0.005, 0.41, 0.05, -0.05, 0.08])\n"
            "print(json.dumps([gough.ik(x).tolist(), gough.jacobian(x).tolist()]))")
    r2 = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                        cwd=tmp_path)
    assert r2.returncode == 0, r2.stderr
    import json
    q, J = json.loads(r2.stdout)
    m = load_scene(ROOT / "examples" / "gough_stewart_6ups.toml").mechanism
    x = np.array([0.01, 0.005, 0.41, 0.05, -0.05, 0.08])
    assert np.array_equal(q, m.inverse_kinematics(x)[0]) and np.array_equal(J, m.jacobian(x))


def test_arb_module_of_a_legs_mechanism_imports_flint_only(tmp_path):
    """The arb flavour of the 6-UPS example (prismatic legs: a square root in every
    kernel): imports math and python-flint only, runs with numpy and sympy blocked, its
    outputs are all balls, and they contain the float kernels' values."""
    from distkin.codegen.rss import module_text
    from distkin.mechanisms.kernel_names import ARB_KERNELS
    m = load_scene(ROOT / "examples" / "gough_stewart_6ups.toml").mechanism
    src = module_text(m, ARB_KERNELS, ("arb",))
    imports = [ln for ln in src.splitlines() if ln.startswith(("import ", "from "))]
    assert imports == ["import math", "from flint import arb as _A"]
    (tmp_path / "gough_arb.py").write_text(src)
    x = [0.01, 0.005, 0.41, 0.05, -0.05, 0.08]
    code = ("import sys; sys.modules['numpy'] = None; sys.modules['sympy'] = None\n"
            "import json, flint, gough_arb\n"
            f"x = [flint.arb(v) for v in {x!r}]\n"
            "rows = [gough_arb.reach_arb(x), gough_arb.jq_jx_arb(x)]\n"
            "flat = lambda r: [v for e in r for v in (e if isinstance(e, list) else [e])]\n"
            # every output is a ball, the constant Jq = -1 of a prismatic leg included
            "assert all(isinstance(v, flint.arb) for r in rows for v in flat(r))\n"
            "print(json.dumps([[[float(v.mid()), float(v.rad())] for v in flat(r)] "
            "for r in rows]))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    import json
    reach, jqjx = (np.array(v) for v in json.loads(r.stdout))
    X = np.array(x)
    for balls, ref in ((reach, m.reach_margin(X).ravel()),
                       (jqjx, np.hstack([m.jq_jx(X)[0][:, None], m.jq_jx(X)[1]]).ravel())):
        assert len(balls) == len(ref)
        assert np.all(np.abs(balls[:, 0] - ref) <= balls[:, 1] + 4e-16 * np.maximum(1, abs(ref)))


@pytest.mark.parametrize("name", ["octo", "hunt"])
def test_csv_and_toml_written_with_the_defaults_round_trip(name, tmp_path):
    """legs_csv_text and legs_toml_text(csv_name=...) with their defaults describe the
    preset itself (QA: the CSV was in m, the scene in mm, a mechanism 1000x too small
    that loaded silently): the same leg table and, against the preset's own IK, the
    same crank angles at home, every leg reachable, also through ``distkin run``."""
    m = preset(name)
    (tmp_path / "o.csv").write_text(legs_csv_text(m))
    text = legs_toml_text(m, csv_name="o.csv")
    assert "lengths in mm" in text and 'length = "mm"' in text    # the CSV's unit named
    scene = tmp_path / "o.toml"
    scene.write_text(text + QUERY.replace("0.3", "300"))
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        lm = load_scene(scene).mechanism
    assert lm.key() == m.leg_description().key()
    q, valid = lm.inverse_kinematics(m.home)
    q0, valid0 = m.inverse_kinematics(m.home)
    assert valid.all() and valid0.all() and np.array_equal(q, q0)
    r = subprocess.run([sys.executable, "-m", "distkin", "run", str(scene)],
                       capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 0 and "NOT reachable" not in r.stdout and "-> reachable" in r.stdout


def test_scene_whose_home_its_branched_legs_miss_warns(tmp_path):
    """A CSV in m read by a mm scene (every leg has its branch, so the home check that
    chooses branches did not run): the legs, 1000x too small, do not reach home; a
    GeometryWarning names home and the legs, with their margins computed independently
    (the preset's own leg table scaled by 1e-3)."""
    from distkin.mechanisms import GeometryWarning
    m = preset("octo")
    (tmp_path / "o.csv").write_text(legs_csv_text(m, length_unit="m"))
    scene = tmp_path / "o.toml"
    scene.write_text(legs_toml_text(m, length_unit="mm", csv_name="o.csv")
                     + QUERY.replace("0.3", "300"))
    with pytest.warns(GeometryWarning, match=r"home: expected a home pose that every leg "
                                             r"reaches.*8 of 8 legs.*leg 1 margin") as rec:
        lm = load_scene(scene).mechanism
    assert not lm.reachable(m.home)
    leg = lm.leg_table[0]
    assert leg.crank == pytest.approx(m.l1 * 1e-3, rel=1e-15)
    d = m.leg_description().leg_table[0]
    w = np.array([0, 0, 0.3]) + np.array(d.platform) * 1e-3 - (np.array(d.base)
                                                              + np.array(d.offset)) * 1e-3
    A, B = w @ np.array(d.crank0), w @ np.array(d.crank90)
    C = (w @ w + (d.crank * 1e-3) ** 2 - (d.distal * 1e-3) ** 2) / (2 * d.crank * 1e-3)
    assert f"leg 1 margin {A * A + B * B - C * C:.3g} m^2" in str(rec[0].message)


def test_csv_with_a_byte_order_mark_loads(tmp_path):
    """Excel's "CSV UTF-8" starts with a byte-order mark: read as the same table as the
    file without it (QA: refused, "got ['\\ufefftype']")."""
    m = preset("hunt")
    text = legs_csv_text(m)
    (tmp_path / "plain.csv").write_text(text, encoding="utf-8")
    (tmp_path / "bom.csv").write_text(text, encoding="utf-8-sig")
    assert (tmp_path / "bom.csv").read_bytes()[:3] == b"\xef\xbb\xbf"
    mechs = []
    for f in ("plain.csv", "bom.csv"):
        scene = tmp_path / f"{f}.toml"
        scene.write_text(legs_toml_text(m, csv_name=f) + QUERY.replace("0.3", "300"))
        mechs.append(load_scene(scene).mechanism)
    assert mechs[0].key() == mechs[1].key() == m.leg_description().key()


def test_duplicate_leg_message_gives_units():
    """A duplicated leg in a mm scene (the 8-RUS example with its last leg a copy of
    its first): the points are printed with their unit (m, the description's) and the
    hint says the scene's unit (QA: metres without a unit)."""
    head, *legs = (ROOT / "examples" / "rus8_device.toml").read_text().split(
        "[[mechanism.leg]]")
    last, _, queries = legs[-1].partition("[[query]]")
    legs[-1] = legs[0]
    with pytest.raises(InputError) as exc:
        loads_scene(head + "[[mechanism.leg]]".join([""] + legs) + "[[query]]" + queries)
    assert exc.value.field == "mechanism.leg[7]"
    assert (f"base ({0.115911099:.6g}, {-0.031058285:.6g}, 0) m, platform "
            f"({0.046984631:.6g}, {-0.017101007:.6g}, 0) m") in exc.value.message
    assert "the scene's in mm" in exc.value.hint
