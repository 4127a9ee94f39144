"""Scene input of the ``delta_transform`` query: offsets outside their edges refused at
load time as ``kind = "platform66"`` refuses them (QA V 3), and a message about a huge
mapped squared leg that shows its value, not ``-inf`` and not its 400 digits (QA V 4).

References: the definition of the offsets, 0 < delta_i < d_i (Rojas, Borràs, Thomas,
*The Octahedral Manipulator Revisited*, Sec. V, Fig. 6), with the sides measured here
from the points; the exact mapped squared legs by a second route (sympy's LU solve of
eq. (8), m^2 = A l^2 - b).
"""

import math

import mpmath
import pytest
import sympy as sp

from distkin.app.cli import main
from distkin.app.scene import loads_scene
from distkin.errors import DegenerateGeometryError, InfeasibleError, InputError

HEAD = ('[units]\nlength = "none"\n[mechanism]\nkind = "octahedral"\n'
        'base = [[0,0,0], [6,"sqrt(108)",0], [12,0,0]]\n'
        'platform = [[0,0,0], [6,0,0], [3,"sqrt(27)",0]]\n')
D12 = math.dist((0, 0, 0), (6, math.sqrt(108), 0))       # P1 P2: delta1's edge
D45 = math.dist((0, 0, 0), (6, 0, 0))                    # P4 P5: delta2's edge


def _query(offsets, extra=""):
    return HEAD + f'[[query]]\ntype = "delta_transform"\noffsets = {offsets}\n{extra}'


@pytest.mark.parametrize("delta1, cls", [(13, InputError), (-1, InputError),
                                         (0, DegenerateGeometryError),
                                         (12, DegenerateGeometryError)])
def test_offsets_outside_the_edge_are_refused_at_load(delta1, cls, tmp_path, capsys):
    """delta1 outside 0 < delta1 < d12 = 12: refused when the scene loads (the m_legs
    solve refused it only when run), with the message of kind = "platform66"; exit 2."""
    assert D12 == pytest.approx(12) and not 0 < delta1 < round(D12)
    want = (f"expected 0 < delta1 < d12 = 12 (length units) so that every joint is single "
            f"and on its edge, got delta1 = {delta1} (length units)")
    for text in (_query(f"[{delta1}, 3, 6, 3, 6, 3]"),
                 _query(f"[{delta1}, 3, 6, 3, 6, 3]", "solve = false\n")):
        with pytest.raises(cls) as err:
            loads_scene(text)
        assert want in str(err.value) and err.value.field == "query[0].offsets[0]"
    p66 = HEAD.replace('"octahedral"', '"platform66"') + \
        f'offsets = [{delta1}, 3, 6, 3, 6, 3]\n[[query]]\ntype = "forward_kinematics"\n' \
        'legs = [18, 18, 18, 18, 18, 18]\n'
    with pytest.raises(cls, match=want.replace("(", r"\(").replace(")", r"\)")):
        loads_scene(p66)
    f = tmp_path / "s.toml"
    f.write_text(_query(f"[{delta1}, 3, 6, 3, 6, 3]"))
    assert main(["run", str(f)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and want in err[0]


def test_symbolic_offsets_pass_and_numeric_ones_beside_them_are_checked():
    """A symbol is a parameter (no bound to check); a number next to it is checked."""
    assert D45 == pytest.approx(6)
    ok = loads_scene(_query('["Delta1", 3, "Delta1", 3, "Delta1", 3]'))
    assert ok.queries[0].params.transform.free_symbols
    with pytest.raises(InputError, match=r"0 < delta2 < d45 = 6 .*, got delta2 = 7"):
        loads_scene(_query('["Delta1", 7, "Delta1", 3, "Delta1", 3]'))


def test_a_huge_negative_squared_leg_is_shown_by_its_value():
    """m1 = 1e200: the most negative mapped l_i^2 (about -3e399) is said with 6
    significant digits and its exponent: not "-inf", not its 466 digits."""
    scene = loads_scene(_query('["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]',
                               'm_legs = [1e200, 18, 18, 17, 14.9, 17.8]\n'))
    p = scene.queries[0].params
    m = [sp.Integer(int(1e200))] + [sp.Rational(x) for x in (18.0, 18.0, 17.0, 14.9, 17.8)]
    l_sq = p.transform.A.LUsolve(sp.Matrix([x ** 2 for x in m]) + sp.Matrix(p.transform.b))
    i, worst = min(enumerate(l_sq), key=lambda t: t[1])
    assert worst < 0 and len(str(worst)) > 400
    from distkin.app.queries.delta import DeltaTransformQuery
    with pytest.raises(InfeasibleError) as err:
        p.transform.map_legs(p.m_legs, field="m_legs")
    msg = err.value.message
    want = mpmath.nstr(mpmath.mpf(sp.Float(sp.N(worst, 20))), 6)
    assert f"got l{i + 1}^2 = {want} " in msg
    assert "e+399" in want and "inf" not in msg and len(msg) < 300
    assert msg in DeltaTransformQuery.run(p, scene, None).result["reason"]   # the answer
