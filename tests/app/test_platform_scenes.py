"""The platforms of Rojas et al. as ``kind = "legs"`` scenes (app/platform_scene.py), the
Octopod paper's indices on them, and the singularity query on leg mechanisms
(app/queries/leg_singularity.py), each checked against an independent route:
capabilities against linear programs (scipy.optimize.linprog), the certified region
against sampled poses, the Cayley-Menger and four-planes tests against the Plücker
determinant of the generated kernels."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import linprog

from distkin.app.queries.leg_singularity import applicability, singularity_tests_at
from distkin.app.scene import load_scene, loads_scene
from distkin.errors import InputError

EX = Path(__file__).resolve().parents[2] / "examples"
#: the Griffis-Duffy octahedral table of Sec. VI as a legs scene (cm), before its extras
GD_HEAD = """
[units]
length = "cm"
[mechanism]
kind = "legs"
octahedral = { base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]] }
"""


def _gd():
    return load_scene(EX / "griffis_duffy_indices.toml").mechanism


def _delta66():
    return load_scene(EX / "delta66_indices.toml").mechanism


def test_scene_builds_the_sec6_mechanisms_in_si():
    gd, d66 = _gd(), _delta66()
    assert gd.octahedral() is not None and d66.octahedral() is None
    assert np.allclose(gd.home, [0.06, 0.02 * np.sqrt(3), 0.17, 0, 0, 0], atol=1e-15)
    for m in (gd, d66):
        assert m.L == 6 and all(leg.type == "SPS" and leg.limit == (-50.0, 50.0)
                                and leg.range == pytest.approx((0.14, 0.22))
                                for leg in m.leg_table)
        assert m.mass == 0.17 and m.inertia == 3e-4


def _force_by_lp(J, fmax, d):
    """Largest t with J^T tau = (t d, 0, 0, 0), |tau| <= fmax (linprog)."""
    L = J.shape[0]
    A = np.hstack([J.T, -np.concatenate([d, np.zeros(3)])[:, None]])
    res = linprog(np.r_[np.zeros(L), -1.0], A_eq=A, b_eq=np.zeros(6),
                  bounds=[(-fmax, fmax)] * L + [(0, None)], method="highs")
    assert res.status == 0
    return res.x[-1]


def test_worst_case_force_is_the_smallest_lp_force():
    """The continuous force of the study (zonotope, eqs. (6), (14)-(15)) at a pose of each
    mechanism: no direction gives less (linprog along 400 directions), and the nearest
    one gives it to 2 %."""
    from distkin.indices import worst_case_output
    rng = np.random.default_rng(3)
    dirs = rng.normal(size=(400, 3))
    dirs /= np.linalg.norm(dirs, axis=1)[:, None]
    for m in (_gd(), _delta66()):
        x = m.home + [0.01, -0.01, 0.005, 0.1, -0.05, 0.1]
        J = m.jacobian(x)
        fmax = m.leg_table[0].limit[1]                     # N: prismatic legs
        wc = float(worst_case_output(J.T[None], -fmax, fmax, keep=[0, 1, 2])[0])
        lp = np.array([_force_by_lp(J, fmax, d) for d in dirs])
        assert lp.min() >= wc * (1 - 1e-9)
        assert lp.min() <= wc * 1.02
        assert 10 < wc < 100                               # N, a few tenths of 4 x 50 N


def test_certified_region_holds_on_sampled_poses():
    """certify_workspace proves the 6-D box regular with sigma_min(Jx) >= a bound: on 300
    sampled poses inside, every leg closes within its stroke, det J keeps the certified
    sign and sigma_min(Jx) is above the bound."""
    from distkin.certify import certify_workspace
    m = _gd()
    lo = m.home - [0.02, 0.02, 0.02, 0.17, 0.17, 0.17]
    hi = m.home + [0.02, 0.02, 0.02, 0.17, 0.17, 0.17]
    cert = certify_workspace(m, lo, hi, [0.01] * 3 + [0.09] * 3)
    summ = cert.summary()
    assert summ["counts"]["regular"] == len(cert.status) and summ["regular_fraction"] > 1 - 1e-12
    bound = summ["sigma_lower_min"]
    assert bound > 0
    X = lo + np.random.default_rng(5).uniform(size=(300, 6)) * (hi - lo)
    assert m.reachable(X).all()
    Jq, Jx = m.jq_jx(X)
    det = np.linalg.det(Jx)
    assert np.all(np.sign(det) == np.sign(det[0]))
    assert set(summ["det_signs"]) == {int(np.sign(det[0]))}
    assert np.linalg.svd(Jx, compute_uv=False)[:, -1].min() >= bound


def test_singularity_tests_agree_with_the_kernel_determinant():
    """Along a twist of the Griffis-Duffy platform about the vertical, det J of the
    generated kernels (q̇ = J ẋ) vanishes at 90 deg; there the Plücker determinant, the
    paper's and the signed Cayley-Menger conditions and the four planes vanish too, and
    away from it none does.  The Δ 6-6 platform (same base frame and end-effector origin)
    is singular at the same twist: det(AJ) = det(A) det(J) (Rojas et al. Sec. IV)."""
    from scipy.optimize import brentq
    gd, d66 = _gd(), _delta66()

    def det_kernel(m, rz):
        x = m.home.copy()
        x[5] = rz
        return np.linalg.det(m.jacobian(x))
    for m in (gd, d66):
        rz = brentq(lambda t: det_kernel(m, t), np.radians(60), np.radians(120), xtol=1e-14)
        assert abs(rz - np.pi / 2) < 1e-9
    x = gd.home.copy()
    x[5] = np.pi / 2
    at = singularity_tests_at(gd, x, "fast")
    assert abs(at["det_J"]) < 1e-12 and at["sigma_min"] < 1e-12
    assert abs(at["signed_cm_relative"]) < 1e-9 and abs(at["four_planes_relative"]) < 1e-9
    # at the singularity float64 cannot resolve F's sign, and says so (QA 24)
    assert at["four_planes_sign_resolved"] is False
    x[5] = np.radians(30.0)
    assert singularity_tests_at(gd, x, "fast")["four_planes_sign_resolved"] is True
    for rz in np.radians([0.0, 30.0, 75.0, 105.0]):
        x[5] = rz
        off = singularity_tests_at(gd, x, "certified")
        assert abs(off["det_J"]) > 0.1 and abs(off["four_planes_relative"]) > 0.05
        # the Plücker determinant and the kernel's differ only by the leg normalisation
        # and the moment scaling: same sign everywhere, both zero together
        assert np.sign(off["det_J"]) == np.sign(det_kernel(gd, rz))
        assert off["det_sign_certified"] == np.sign(off["det_J"])


def test_where_the_tests_apply():
    from distkin.mechanisms import preset
    from distkin.mechanisms.kinematics import LegMechanism
    assert applicability(_gd())["cm"] is True
    a = applicability(_delta66())
    assert a["det"] and not a["cm"] and "Δ-transform" in a["reason"]
    hunt = LegMechanism.from_description(preset("hunt").leg_description())
    assert not applicability(hunt)["cm"] and "revolute" in applicability(hunt)["reason"]
    octo = LegMechanism.from_description(preset("octo").leg_description())
    assert not applicability(octo)["det"] and "L = 8" in applicability(octo)["reason"]
    r = singularity_tests_at(octo, octo.home)
    assert "det_J" not in r and r["sigma_min"] > 0


@pytest.mark.parametrize("extra, field", [
    ('offsets = [1, 2]', "mechanism.offsets"),
    ('approximation = { kind = "nope", delta = 1 }', "mechanism.approximation.kind"),
    ('approximation = { kind = "standard", delta = -1 }', "mechanism.approximation.delta"),
    ('approximation = { kind = "griffis_duffy", delta = 0 }', "mechanism.approximation.delta"),
    ('offsets = ["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]\n'
     'approximation = { kind = "standard", delta = 1 }', "mechanism"),
    ('stroke = [14]', "mechanism.stroke"),
    ('leg_type = "RSS"', "mechanism.leg_type"),
])
def test_bad_platform_fields_are_named(extra, field):
    text = GD_HEAD + f"""height = 17
{extra}
[[query]]
type = "inverse_kinematics"
poses = [[6, 3.46, 17, 0, 0, 0]]
"""
    with pytest.raises(InputError) as exc:
        loads_scene(text)
    assert exc.value.field == field


def test_unitless_scene_is_refused():
    text = """
[units]
length = "none"
[mechanism]
kind = "legs"
octahedral = { base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]] }
height = 17
[[query]]
type = "inverse_kinematics"
poses = [[6, 3.46, 17, 0, 0, 0]]
"""
    with pytest.raises(InputError) as exc:
        loads_scene(text)
    assert exc.value.field == "units.length" and "legs" in str(exc.value)


def _run(args, tmp_path):
    import subprocess
    import sys
    return subprocess.run([sys.executable, "-m", "distkin", "run", *args], cwd=tmp_path,
                          capture_output=True, text=True, timeout=600)


def test_singularity_query_through_the_cli(tmp_path):
    """A legs scene's singularity query, JSON contract: the crossing at 90 deg, the tests
    that apply and their values there."""
    import json
    scene = tmp_path / "s.toml"
    text = (EX / "griffis_duffy_indices.toml").read_text()
    head = text[:text.index("[[query]]")]
    scene.write_text(head + """
[[query]]
type = "singularity"
path = { from = [6, "sqrt(12)", 17, 0, 0, 0], to = [6, "sqrt(12)", 17, 0, 0, 135], samples = 40 }
method = "certified"
""")
    r = _run([str(scene), "--json", "-"], tmp_path)
    assert r.returncode == 0, r.stderr
    q = json.loads(r.stdout)["queries"][0]["result"]
    assert q["applicability"]["cm"] is True and len(q["poses"]) == 40
    (c,) = q["crossings"]
    assert abs(np.degrees(c["pose"][5]) - 90) < 1e-9
    assert abs(c["signed_cm_relative"]) < 1e-9 and c["sigma_min"] < 1e-9
    bad = tmp_path / "bad.toml"
    bad.write_text(head + '[[query]]\ntype = "singularity"\nposes = [[1, 2, 3]]\n')
    r = _run([str(bad)], tmp_path)
    assert r.returncode == 2 and "query[0].poses[0]" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


@pytest.mark.slow
@pytest.mark.parametrize("name", ["griffis_duffy_indices.toml", "delta66_indices.toml"])
def test_example_scenes_run_with_plots(name, tmp_path):
    """The two example scenes end to end (about 15 s each): every query ok, forces in N,
    plots written."""
    import json
    r = _run([str(EX / name), "--json", str(tmp_path / "out.json"), "--plots",
              str(tmp_path / "plots")], tmp_path)
    assert r.returncode == 0, r.stderr
    res = json.loads((tmp_path / "out.json").read_text())
    assert all(q["status"] == "ok" for q in res["queries"])
    assert len(list((tmp_path / "plots").glob("*.png"))) >= 6


def test_scene_device_beside_a_preset_with_units_per_actuator_type(tmp_path):
    """devices = the scene's legs mechanism (no preset) beside the Hunt-type preset: each
    on its own grid about its home, the definitions print each device's limits in its
    units (N for the prismatic legs, N·m for the revolute ones), never N·m for a force;
    a legs scene's certify_workspace needs a region."""
    import json
    text = (EX / "griffis_duffy_indices.toml").read_text()
    head = text[:text.index("[[query]]")]
    scene = tmp_path / "s.toml"
    scene.write_text(head + """
[[query]]
type = "performance"
devices = [{ label = "GD", rotation = 10 }, { label = "Hunt", preset = "hunt", rotation = 10 }]
grid = { half = 1, step = 1, rotation = 10, rotation_step = 10 }
actuators = { stall_force = 100, speed = 1, nominal_torque = "2.5", stall_torque = "34.2", velocity = 51 }
workers = 1
store = "store"
""")
    r = _run([str(scene), "--json", "-"], tmp_path)
    assert r.returncode == 0, r.stderr
    res = json.loads(r.stdout)["queries"][0]["result"]
    text = json.dumps(res, ensure_ascii=False)
    assert "|τ| <= 50 N (GD) / 2.5 N·m (Hunt)" in text
    devs = {d["label"]: d for d in res["devices"]}
    assert devs["GD"]["actuator_limits"]["text"]["rate"] == "1 m/s"
    assert devs["Hunt"]["actuator_limits"]["text"]["rate"] == "51 rad/s"
    # the sensitivities' JSON units follow each device's actuators (they were the
    # revolute ones, m/rad and N/(N·m), for the prismatic legs too)
    want = {"GD": ("m/m", "rad/m", "N/N", "(N·m)/N"),
            "Hunt": ("m/rad", "rad/rad", "N/(N·m)", "(N·m)/(N·m)")}
    for label, units in want.items():
        got = tuple(devs[label]["table"][q]["unit"] for q in
                    ("sens_translational", "sens_rotational", "sens_force", "sens_torque"))
        assert got == units, label
    # the σ × τnom reading scales by each device's own nominal limit: 50 N, 2.5 N·m
    for label, tau in (("GD", 50.0), ("Hunt", 2.5)):
        rd = devs[label]["isotropy"]["readings"]
        for k in ("sigma_min", "sigma_max"):
            assert rd["wrench_nominal"][k] == pytest.approx(tau * rd["wrench"][k], rel=1e-15)
    bad = tmp_path / "bad.toml"
    bad.write_text(head + '[[query]]\ntype = "performance"\nactuators = { speed = 1 }\n')
    r = _run([str(bad)], tmp_path)
    assert r.returncode == 2 and "query[0].actuators.stall_force" in r.stderr
    bad.write_text(head + '[[query]]\ntype = "certify_workspace"\n')
    r = _run([str(bad)], tmp_path)
    assert r.returncode == 2 and "query[0].region" in r.stderr


@pytest.mark.parametrize("kind", ["standard", "stoughton_arai", "griffis_duffy"])
def test_fig2_approximation_scene_legs_match_the_delta_module(kind):
    """``approximation = { kind, delta }``: our IK at a pose equals the leg lengths of
    distkin.delta.offset_study.leg_lengths on the same Platform66 (its own frame), in cm."""
    from distkin.delta import approximation
    from distkin.delta.offset_study import leg_lengths
    from distkin.spatial import rotation_matrix
    text = GD_HEAD + f"""approximation = {{ kind = "{kind}", delta = "1/2" }}
origin = [0, 0, 0]
height = 17
[[query]]
type = "inverse_kinematics"
poses = [[6, 3.46, 17, 0, 0, 0]]
"""
    m = loads_scene(text).mechanism
    assert m.octahedral() is None and len({leg.platform for leg in m.leg_table}) == 6
    plat = approximation(([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]],
                          [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]), kind, "1/2")
    x = m.home + [0.004, -0.003, 0.01, 0.1, -0.05, 0.2]
    # our frame is the platform frame turned over (180 deg about x), origin at P4
    R = rotation_matrix(x[3:]) @ np.diag([1.0, -1.0, -1.0])
    want = np.asarray(leg_lengths(plat, R, x[:3] / 0.01), dtype=float) * 0.01
    q, _ = m.inverse_kinematics(x)
    assert np.max(np.abs(q - want)) < 1e-14


def test_table3_bar_titles_use_the_devices_units(tmp_path, monkeypatch):
    """The Table III bar chart titled every sensitivity with the revolute units (m/rad,
    N/(N·m)) even for prismatic legs; it now prints the units the devices' tables carry,
    both where a study mixes actuator types."""
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from distkin.indices.plots import plot_table3_bars
    from distkin.indices.study import CAPABILITIES, SENSITIVITIES
    titles = []
    save = Figure.savefig

    def capture(fig, *args, **kwargs):
        titles.extend(ax.get_title() for ax in fig.axes)
        return save(fig, *args, **kwargs)
    monkeypatch.setattr(Figure, "savefig", capture)
    rows = [c[:3] for c in CAPABILITIES] + [s[:3] for s in SENSITIVITIES]

    def summary(label, sens_units):
        units = dict(zip([s[0] for s in SENSITIVITIES], sens_units))
        return {"label": label, "table": {q: {"min": 1.0, "max": 2.0,
                                              "unit": units.get(q, unit)}
                                          for q, _, unit in rows}}
    plot_table3_bars(tmp_path / "t", [summary("GD", ("m/m", "rad/m", "N/N", "(N·m)/N"))])
    assert "Max. translational sensitivity [m/m]" in titles
    assert "Max. force sensitivity [N/N]" in titles and "Continuous force [N]" in titles
    titles.clear()
    plot_table3_bars(tmp_path / "u", [summary("GD", ("m/m", "rad/m", "N/N", "(N·m)/N")),
                                      summary("Hunt", ("m/rad", "rad/rad", "N/(N·m)",
                                                       "(N·m)/(N·m)"))])
    assert "Max. translational sensitivity [m/m | m/rad]" in titles


def test_table4_bar_title_gives_the_studied_orientations(tmp_path, monkeypatch):
    """The Table IV chart said '±20°' whatever range the study used (±10° in the
    examples of [1]'s platforms)."""
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from distkin.indices.plots import plot_table4_bars
    titles = []
    save = Figure.savefig

    def capture(fig, *args, **kwargs):
        titles.append(fig._suptitle.get_text())
        return save(fig, *args, **kwargs)
    monkeypatch.setattr(Figure, "savefig", capture)
    iso = {"gii": 0.15, "sigma_min": 0.02, "sigma_max": 0.16, "rotation_deg": 10.0}
    plot_table4_bars(tmp_path / "t", [{"label": "GD", "isotropy": iso}])
    # no paper value for GD: the title names the device and its range, not the paper's
    # ±20° (QA: "drop paper entries when absent; titles from the actual devices")
    assert "GD (orientations ±10°)" in titles[0] and "(±20°)" not in titles[0]
