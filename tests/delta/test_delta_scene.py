"""Scene queries ``delta_transform`` and ``singularity``: JSON contract, bad input in
the API and in the CLI (exit 2, one line, no traceback).

Reference values: Rojas et al., Sec. VI (docs/design.md §5).
"""

import json
import subprocess
import sys
import textwrap

import pytest
import sympy as sp

from distkin.app.cli import main, run_scene
from distkin.errors import DegenerateGeometryError, InfeasibleError
from distkin.app.scene import loads_scene

from delta_printed import printed_det

HEAD = textwrap.dedent("""
    [units]
    length = "none"
    angle = "deg"

    [mechanism]
    kind = "octahedral"
    base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
    platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
""")
M_LEGS = ('["6/25*sqrt(6170)", "6/5*sqrt(221)", "1/5*sqrt(7349)", "1/50*sqrt(674605)", '
          '"1/25*sqrt(136210)", "1/5*sqrt(8153)"]')


def _scene(body):
    return HEAD + textwrap.dedent(body)


def test_symbolic_offsets_json():
    scene = loads_scene(_scene("""
        [[query]]
        type = "delta_transform"
        offsets = ["Delta1", "Delta2", "Delta1", "Delta2", "Delta1", "Delta2"]
    """))
    records, _texts, worst = run_scene(scene)
    assert worst == 0
    res = records[0]["result"]
    assert len(res["A"]) == 6 and all(len(r) == 6 and all(isinstance(x, str) for x in r)
                                      for r in res["A"])
    D1, D2 = sp.symbols("Delta1 Delta2")
    assert sp.sympify(res["A"][0][1]) == D1 / 12
    assert sp.expand(sp.sympify(res["b"][1]) - D2 * (6 - D2)) == 0
    det = sp.sympify(res["det"])
    const = sp.sympify(res["det_constant"])
    prod = sp.prod([sp.sympify(f) ** k for f, k in zip(res["det_factors"],
                                                       res["det_multiplicities"])])
    assert sp.expand(const * prod - det) == 0
    assert "Delta1 + 2*Delta2 - 12" in res["det_factors"]
    assert "mapped_legs" not in res


def test_numeric_offsets_map_legs_exactly():
    scene = loads_scene(_scene(f"""
        [[query]]
        type = "delta_transform"
        offsets = ["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]
        m_legs = {M_LEGS}
        solve = false
    """))
    records, texts, worst = run_scene(scene)
    assert worst == 0, records
    res = records[0]["result"]
    assert res["mapped_legs"] == ["99/5", "18", "18", "17", "149/10", "89/5"]
    # det A: Sec. VI's printed polynomial at Δ1 = 12/5, Δ2 = 6/5 (819/3125)
    assert res["det"] == str(printed_det(sp.Rational(12, 5), sp.Rational(6, 5))) == "819/3125"
    assert res["det_factors"] == []
    assert "l1 = 99/5" in texts[0]


@pytest.mark.parametrize("offsets", ['["Delta1", "Delta2", "Delta1", "Delta2", "Delta1", '
                                     '"Delta2"]', '["12/5", "6/5", "12/5", "6/5", "12/5", '
                                     '"6/5"]'])
def test_report_states_the_singular_line_against_the_papers_sentence(offsets):
    """README: the finding that the singular line of the family is Delta1 + 2 Delta2 =
    12, not the paper's Delta1 + Delta2 = 12, is stated in the report (QA: only the
    plot's legend drew it).  Reference: Sec. VI's printed det(A) polynomial, zero at
    points of Delta1 + 2 Delta2 = 12 and not along Delta1 + Delta2 = 12."""
    scene = loads_scene(_scene(f"""
        [[query]]
        type = "delta_transform"
        offsets = {offsets}
    """))
    records, texts, worst = run_scene(scene)
    assert worst == 0, records
    fam = records[0]["result"]["family"]
    assert fam["singular_lines"] == ["Delta1 + 2*Delta2 - 12 = 0"]
    assert fam["paper_line_singular"] is False
    for d2 in (1, 2, 5):
        assert printed_det(12 - 2 * sp.Integer(d2), sp.Integer(d2)) == 0
    assert any(printed_det(12 - sp.Integer(d2), sp.Integer(d2)) != 0 for d2 in (1, 2, 5))
    assert "Delta1 + 2*Delta2 - 12 = 0; the paper's sentence Delta1 + Delta2 = 12" in texts[0]


def test_singular_offsets_api_and_cli(tmp_path):
    body = """
        [[query]]
        type = "delta_transform"
        offsets = [6, 3, 6, 3, 6, 3]
    """
    with pytest.raises(DegenerateGeometryError, match=r"delta1 \+ 2\*delta2 - 12"):
        loads_scene(_scene(body))
    f = tmp_path / "singular.toml"
    f.write_text(_scene(body))
    r = subprocess.run([sys.executable, "-m", "distkin", "run", str(f)], capture_output=True,
                       text=True, timeout=600)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in r.stderr
    assert "delta1 + 2*delta2 - 12" in lines[0] and "query[0].offsets" in lines[0]


def test_infeasible_m_legs_api_and_cli(tmp_path, capsys):
    """m-legs whose exact inverse map (eq. (8)) has a negative squared l-leg: no
    octahedral manipulator, hence no 6-6 pose, has them.  Proved exactly, so an answer
    (docs/design.md §4), as the platform66 forward kinematics gives it: mapped_legs
    null, the reason, 0 poses (it was exit 2 "infeasible").  Reference: the exact solve
    A l^2 = m^2 + b by sympy's LU, with a negative entry."""
    import sympy as sp
    body = """
        [[query]]
        type = "delta_transform"
        offsets = ["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]
        m_legs = [1, 1, 1, 1, 1, 30]
    """
    scene = loads_scene(_scene(body))
    p = scene.queries[0].params
    l_sq = p.transform.A.LUsolve(sp.Matrix([1, 1, 1, 1, 1, 900]) + sp.Matrix(p.transform.b))
    assert min(l_sq) < 0
    from distkin.app.queries.delta import DeltaTransformQuery
    res = DeltaTransformQuery.run(p, scene, None).result
    assert res["mapped_legs"] is None and "non-negative squared l-legs" in res["reason"]
    fk = res["forward_kinematics"]
    assert fk["count"] == 0 and fk["poses"] == [] and fk["certified"] is True
    f = tmp_path / "infeasible.toml"
    f.write_text(_scene(body))
    assert main(["run", str(f), "--json", str(tmp_path / "out.json")]) == 0
    out = capsys.readouterr().out
    assert "m-legs -> l-legs: none real; cannot be assembled" in out
    doc = json.loads((tmp_path / "out.json").read_text())
    assert doc["queries"][0]["status"] == "ok"
    assert doc["queries"][0]["result"]["forward_kinematics"]["reason"] == res["reason"]


def test_bad_fields_are_rejected_at_load_time():
    from distkin.errors import InputError
    with pytest.raises(InputError, match="offsets"):
        loads_scene(_scene("""
            [[query]]
            type = "delta_transform"
            offsets = [1, 2, 3]
        """))
    with pytest.raises(InputError, match="solve"):
        loads_scene(_scene("""
            [[query]]
            type = "delta_transform"
            offsets = ["Delta1", "Delta2", "Delta1", "Delta2", "Delta1", "Delta2"]
            solve = true
        """))
    with pytest.raises(InputError, match="unknown field"):
        loads_scene(_scene("""
            [[query]]
            type = "delta_transform"
            offset = [1, 1, 1, 1, 1, 1]
        """))
    with pytest.raises(InputError, match="exactly one of"):
        loads_scene(_scene("""
            [[query]]
            type = "singularity"
        """))


def test_singularity_query_path_and_pose(tmp_path):
    scene = loads_scene(_scene("""
        [[query]]
        type = "singularity"
        offsets = ["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]
        method = "certified"
        [query.path]
        samples = 30
        [query.path.from]
        translation = [3, "sqrt(3)", 10]
        rotation = ["90*sqrt(3)", 90, 0]
        [query.path.to]
        translation = [6, 0, 10]
        rotation = [90, "90*sqrt(3)", 0]

        [[query]]
        type = "singularity"
        pose = { translation = [3, "sqrt(27)", 10], rotation = [180, 0, 0] }
        offsets = ["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]
    """))
    records, texts, worst = run_scene(scene, plots_dir=tmp_path)
    assert worst == 0, records
    path = records[0]["result"]
    assert len(path["crossings"]) == 1
    c = path["crossings"][0]
    assert c["all_fire"] and all(c["fires"].values())
    assert c["certified"]["signs"][0] == -c["certified"]["signs"][1]
    assert c["platform66"]["identity_error"] < 1e-10
    assert all(d["converged"] and d["distance"] > 0 for d in path["nearest_singularity"])
    assert records[0]["plots"] and all(p.endswith(".png") for p in records[0]["plots"])
    pose = records[1]["result"]
    # the home pose is regular although the paper's CM form vanishes there
    assert abs(pose["det_J"]) > 1 and abs(pose["cm_condition_relative"]) < 1e-12
    assert pose["nearest_singularity"]["converged"]
    # eq. (6) on the built 6-6 joints against det(A) det(J): both values in the text, as
    # in the JSON (the text printed only the second under the first's name; QA W 13)
    p66 = pose["platform66"]
    assert p66["det_J66_hat"] == pytest.approx(p66["det_A_det_Jhat"], rel=1e-9)
    assert (f"{p66['det_J66_hat']:.6e} from the 6-6 joints" in texts[1]
            and f"{p66['det_A_det_Jhat']:.6e} from det(A) det(Jhat)" in texts[1])
    assert "Traceback" not in "".join(texts)


def test_demo_scene_runs_from_the_cli(tmp_path):
    # the shipped example (a symlink to the package scene) with plots and JSON
    from pathlib import Path
    root = Path(__file__).resolve().parents[2]
    ex = root / "examples" / "delta_griffis_duffy.toml"
    assert ex.is_symlink() and ex.resolve() == (root / "distkin" / "scenes" /
                                                "delta_griffis_duffy.toml").resolve()
    out = tmp_path / "out.json"
    r = subprocess.run([sys.executable, "-m", "distkin", "run", str(ex), "--json", str(out),
                        "--plots", str(tmp_path / "plots")], capture_output=True, text=True,
                       timeout=300, cwd=root)
    assert r.returncode == 0, r.stderr
    doc = json.loads(out.read_text())
    q = doc["queries"]
    assert [x["status"] for x in q] == ["ok"] * 4
    fk = q[1]["result"]["forward_kinematics"]
    assert fk["count"] == 12 and fk["max_leg_error"] < 1e-12
    assert q[1]["result"]["mapped_legs"] == ["99/5", "18", "18", "17", "149/10", "89/5"]
    assert q[2]["result"]["crossings"][0]["all_fire"]
    assert len(list((tmp_path / "plots").glob("*.png"))) >= 3


P66 = textwrap.dedent("""
    [units]
    length = "none"

    [mechanism]
    kind = "platform66"
    base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
    platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
    offsets = OFFSETS
""")


def test_platform66_kind_forward_kinematics():
    scene = loads_scene(P66.replace("OFFSETS", '["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]')
                        + textwrap.dedent(f"""
        [[query]]
        type = "forward_kinematics"
        legs = {M_LEGS}
        method = "fast"

        [[query]]
        type = "delta_transform"
    """))
    records, _texts, worst = run_scene(scene)
    assert worst == 0, records
    fk = records[0]["result"]
    assert fk["mapped_legs"] == ["99/5", "18", "18", "17", "149/10", "89/5"]
    assert fk["count"] == 12 and fk["max_leg_error"] < 1e-12
    det = printed_det(sp.Rational(12, 5), sp.Rational(6, 5))       # Sec. VI, printed
    assert records[1]["result"]["det"] == str(det)


def test_platform66_kind_rejects_singular_offsets_in_cli(tmp_path):
    f = tmp_path / "p66.toml"
    f.write_text(P66.replace("OFFSETS", "[6, 3, 6, 3, 6, 3]") + textwrap.dedent("""
        [[query]]
        type = "delta_transform"
    """))
    r = subprocess.run([sys.executable, "-m", "distkin", "run", str(f)], capture_output=True,
                       text=True, timeout=600)
    assert r.returncode == 2 and "Traceback" not in r.stderr
    line, = r.stderr.strip().splitlines()
    assert line.startswith("distkin: error: mechanism.offsets") and "delta1 + 2*delta2 - 12" in line


def test_derivation_script_checks_every_step():
    from pathlib import Path
    root = Path(__file__).resolve().parents[2]
    r = subprocess.run([sys.executable, str(root / "derivations" / "delta_transform.py")],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    assert r.stdout.count("ok:") >= 25 and "all checks passed" in r.stdout


def test_irrational_sides_regular_verdict_and_singular_curve():
    """QA J 3: sides with sqrt(34), det A = 0.2464 != 0: the verdict is "not
    architecturally singular" (not a factor list of a constant), and the family's
    singular locus, a curve, is named by a point on it.  Reference: the closed form
    det A = (prod(d - delta) - prod(delta)) / prod(d) in floats, and brentq along it."""
    import math

    from scipy.optimize import brentq
    scene = loads_scene(textwrap.dedent("""
        [units]
        length = "mm"
        [mechanism]
        kind = "octahedral"
        base = [[0, 0, 0], [6, 10, 0], [12, 0, 0]]
        platform = [[0, 0, 0], [6, 0, 0], [3, 5, 0]]
        [[query]]
        type = "delta_transform"
        offsets = ["12/5", "6/5", "5/2", "13/10", "13/5", "11/10"]
    """))
    records, texts, worst = run_scene(scene)
    assert worst == 0, records
    res = records[0]["result"]
    d = [float(sp.sympify(x)) for x in res["sides"].values()]
    offs = [2.4, 1.2, 2.5, 1.3, 2.6, 1.1]

    def det(o):
        return (math.prod(di - oi for di, oi in zip(d, o)) - math.prod(o)) / math.prod(d)

    assert float(sp.sympify(res["det"])) == pytest.approx(det(offs), rel=1e-12)
    assert "not architecturally singular" in texts[0]
    assert "architecturally singular where a factor vanishes" not in texts[0]
    (curve,) = res["family"]["singular_curves"]
    x, y = curve["point"]
    fam = lambda a: det([a, y, a, y, a, y])                                      # noqa: E731
    assert brentq(fam, x - 0.01, x + 0.01) == pytest.approx(x, abs=1e-5)
    assert "a curve of degree" in texts[0] and "no line" not in texts[0]
