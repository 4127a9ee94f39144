"""The ``singularity`` path query near a tangency with the Griffis-Duffy singular locus
(QA path24): a sign change of the float64 det J shown only by values within its
rounding-error estimate is "possibly round-off", not counted in a count called a lower
bound, and arb's evidence of one sign on both sides keeps it out under ``certified``;
each counted root carries an error estimate ``s_error`` that its distance to the exact
root respects (Brent's 1e-14 is on the float function only).

Independent reference: det J of the same rational path (exact ends, exact sqrt(108),
sqrt(27)) in mpmath at 50 digits, rows (u/|u|, b x u/(|u| L)) written here (Rojas et
al., eq. (5)), not from the package's kernels.  The paths are the QA's: a secant line
through a point of the locus, along the locus' tangent plane, shifted along the normal
by delta (det J >= about 2.4e-10 (times the legs' product) for delta = 1e-8, two roots
3.2e-6 apart for -1e-8, two roots 3.2e-3 apart for -0.01)."""

from __future__ import annotations

import json
from fractions import Fraction

import mpmath as mp
import pytest

from distkin.app.cli import main

TANGENT_ABOVE = (
    (("373972003588576823082/82152584544663924833", "52476758467268214331/61778344774852190297",
      "774601642051086269251/77258122627688744211"),
     ("4318384752271293751603/35165815973686815722", "307331428105141725473/2497850000806245754",
      "8128976749825313308/93612548886616666231")),
    (("235235044608936233497/52768548985185100267", "42549388142947466254/48526663924461247009",
      "283811259514020392549/28455541459925407430"),
     ("4035306731464636330177/32843767493493513785", "3785614641642531366359/30760743545276854436",
      "-7128838146270703953/82095044679133179982")))
TANGENT_BELOW = (
    (("385463916552642269352/84677079272346626993", "77574170319290834695/91324311553989318938",
      "5162641879104879587/514917601158946443"),
     ("2792774157061412237948/22742341800747467417", "8734534431380720240911/70990321331544617899",
      "7128838146270703953/82095044679133179982")),
    (("82526704502087986504/18512609191984703347", "52005385912388635765/59311026423083478058",
      "914166527052505434588/91656347800864933823"),
     ("3934333716393817437491/32021937964589446297", "12135867124254734640387/98612334230296236583",
      "-8128976749825313308/93612548886616666231")))
SECANT = (
    (("426470614964901678891/93685256948466535805", "78927287305720749196/92917270559184554993",
      "458348552597339833628/45715302886619950435"),
     ("1087441652237601128192/8855341804424999201", "7423209244980469296316/60332466917054982035",
      "685907174951377948/7898843965075658039")),
    (("252090141859596727859/56549529088949281456", "67784433099335437597/77306691026370996557",
      "146799265107386973855/14718417379594346966"),
     ("9849994358083925823203/80170095121597249637", "11388937262037979183533/92543011251117735394",
      "-4305350988599795195/49580026161285879726")))

LEGS = ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6))


def _scene(path, method):
    vec = lambda v: "[" + ", ".join(f'"{x}"' for x in v) + "]"  # noqa: E731
    (t0, w0), (t1, w1) = path
    return ('[units]\nlength = "none"\nangle = "deg"\n[mechanism]\nkind = "octahedral"\n'
            'base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]\n'
            'platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]\n'
            f'[[query]]\ntype = "singularity"\nmethod = "{method}"\n[query.path]\n'
            f'samples = 60\n[query.path.from]\ntranslation = {vec(t0)}\nrotation = {vec(w0)}\n'
            f'[query.path.to]\ntranslation = {vec(t1)}\nrotation = {vec(w1)}\n')


def _run(tmp_path, capsys, path, method):
    f = tmp_path / "s.toml"
    f.write_text(_scene(path, method), encoding="utf-8")
    code = main(["run", str(f), "--no-progress", "--json", str(tmp_path / "o.json")])
    out, err = capsys.readouterr()
    assert code == 0, err
    return json.loads((tmp_path / "o.json").read_text())["queries"][0]["result"], out


def _mp_det(path):
    """s -> det J of the rational path at 50 digits (moments over L = sqrt(12))."""
    q = lambda x: mp.mpf(Fraction(x).numerator) / Fraction(x).denominator  # noqa: E731

    def f(s):
        with mp.workdps(50):          # the ends converted at 50 digits too
            (t0, w0), (t1, w1) = ([q(x) for x in v] for v in path[0]), \
                ([q(x) for x in v] for v in path[1])
            s = mp.mpf(s)
            t = [a + s * (b - a) for a, b in zip(t0, t1)]
            w = [(a + s * (b - a)) * mp.pi / 180 for a, b in zip(w0, w1)]
            th = mp.sqrt(sum(x * x for x in w))
            k = [x / th for x in w]
            K = mp.matrix([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
            R = mp.eye(3) + mp.sin(th) * K + (1 - mp.cos(th)) * K * K
            base = [mp.matrix([0, 0, 0]), mp.matrix([6, mp.sqrt(108), 0]), mp.matrix([12, 0, 0])]
            plat = [mp.matrix([0, 0, 0]), mp.matrix([6, 0, 0]), mp.matrix([3, mp.sqrt(27), 0])]
            P = base + [R * p + mp.matrix(t) for p in plat]
            L, rows = mp.sqrt(12), []
            for i, j in LEGS:
                b, u = P[i - 1], P[j - 1] - P[i - 1]
                u = u / mp.norm(u)
                rows.append([u[0], u[1], u[2], (b[1] * u[2] - b[2] * u[1]) / L,
                             (b[2] * u[0] - b[0] * u[2]) / L, (b[0] * u[1] - b[1] * u[0]) / L])
            return mp.det(mp.matrix(rows))
    return f


def _mp_minimum(F, start=0.5):
    with mp.workdps(50):
        u = mp.findroot(lambda x: mp.diff(F, x), mp.mpf(start))
        return u, F(u)


@pytest.mark.parametrize("method", ["fast", "certified"])
def test_tangent_path_off_the_locus_has_no_crossing(tmp_path, capsys, method):
    """delta = 1e-8: the query said "2 crossing(s) of det J = 0 found" (found = 2, a
    lower bound) at s 0.4999987176 and 0.4999987238; mpmath: det J > 0 all along."""
    F = _mp_det(TANGENT_ABOVE)
    um, fmin = _mp_minimum(F)
    assert fmin > 0 and F(0) > 0 and F(1) > 0        # the truth: no zero at all
    r, out = _run(tmp_path, capsys, TANGENT_ABOVE, method)
    cc = r["crossing_count"]
    assert cc["found"] == 0 == len(r["crossings"]) and cc["is_lower_bound"]
    assert cc["possibly_round_off"] == len(r["possible_crossings"]) == 2
    for c in r["possible_crossings"]:
        assert F(c["s"]) > 0                           # mpmath: no root there
        sc = c["sign_change"]                          # a value within its estimate
        assert any(abs(v) <= e for v, e in zip(sc["det_J"], sc["det_J_error"]))
        if method == "certified":
            assert "arb proves det J > 0" in c["reason"] and c["certified"]["bracket"] is None
    assert "0 crossing(s) of det J = 0 found" in out
    assert out.count("(possibly round-off, not counted)") == 2
    if method == "certified":
        assert cc["certified_crossings"] == 0


def test_tangent_path_through_the_locus_counts_no_phantom(tmp_path, capsys):
    """delta = -1e-8: mpmath roots 0.4999984 and 0.5000016 (det J -6.8e-17 between
    them, at its minimum; these moments over L and unit u); the fast query put two
    roots near 0.5000033 (2e-6 - 5e-6 off) and counted them.  Now no root it cannot
    resolve is counted (0 <= 2: still a lower bound), and any counted root lies within
    its s_error of a true one."""
    F = _mp_det(TANGENT_BELOW)
    um, fmin = _mp_minimum(F)
    assert fmin < 0
    with mp.workdps(50):
        h = mp.mpf("1e-6")
        d = mp.sqrt(-fmin * h * h / (F(um + h) + F(um - h) - 2 * fmin))
        true = [mp.findroot(F, um - d), mp.findroot(F, um + d)]
    r, out = _run(tmp_path, capsys, TANGENT_BELOW, "fast")
    assert r["crossing_count"]["found"] == len(r["crossings"]) <= 2
    for c in r["crossings"]:
        assert min(abs(c["s"] - x) for x in true) <= c["s_error"]
    assert r["crossing_count"]["found"] + r["crossing_count"]["possibly_round_off"] == 2


@pytest.mark.parametrize("method", ["fast", "certified"])
def test_crossing_s_error_covers_the_distance_to_the_exact_root(tmp_path, capsys, method):
    """delta = -0.01: the fast roots 0.49840186659266444 and 0.5015981284597 are 4e-9
    and 2e-9 from mpmath's (the docstring said |ds| <= 1e-14).  Fast: the estimate
    covers the error; certified: the root is polished at 30 digits and certified in a
    bracket of 2e-12, whose half-width is its s_error."""
    F = _mp_det(SECANT)
    r, out = _run(tmp_path, capsys, SECANT, method)
    assert r["crossing_count"]["found"] == len(r["crossings"]) == 2
    for c in r["crossings"]:
        with mp.workdps(50):
            root = mp.findroot(F, mp.mpf(c["s"]))
        assert abs(c["s"] - root) <= c["s_error"]
        if method == "certified":
            assert c["status"] == "certified" and c["polished"]
            assert c["s_error"] <= 2e-12 and c["s_error_kind"].startswith("certified")
            assert abs(c["s"] - root) < 1e-15            # polished
            lo, hi = c["certified"]["bracket"]
            lo, hi = (float(Fraction(x)) if isinstance(x, str) else x for x in (lo, hi))
            assert lo < root < hi
        else:
            assert c["status"] == "crossing" and c["s_error"] > 1e-14
            assert c["s_error_kind"].startswith("estimate")
        # the text prints s with the digits the error supports, and the error
        from distkin.app.queries.singularity_roots import format_s
        assert f"crossing at s = {format_s(c['s'], c['s_error'])}" in out
