"""QA R 1, R 3, R 7, R 8, R 10 through `distkin run`: exit 2 with one line naming the
field for meaningless joint values and poses, the singularity query on kind rss, a
warning for a likely unit slip in a preset override, and the FK refusal in the scene's
units."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from distkin.app.cli import main

ROOT = Path(__file__).resolve().parents[2]

RSS = """[units]
length = "mm"
angle = "{angle}"
[mechanism]
kind = "rss"
preset = "{preset}"
{extra}
[[query]]
{query}
"""


def _run(tmp_path, capsys, text, *extra):
    f = tmp_path / "s.toml"
    f.write_text(text)
    code = main(["run", str(f), *extra])
    out, err = capsys.readouterr()
    return code, out, err


def _one_line(code, err):
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("distkin: error: "), err
    return lines[0]


def _gough(query: str) -> str:
    """The README's 6-UPS example (mm) with its queries replaced by ``query``."""
    text = (ROOT / "examples" / "gough_stewart_6ups.toml").read_text()
    return text[:text.index("[[query]]")] + "[[query]]\n" + query


@pytest.mark.parametrize("angles, leg, shown", [("[0, 0, 400, 0, 0, 0]", 0, "0"),
                                                ("[451, 451, 451, 451, 451, 0]", 5, "0"),
                                                ("[-451, 451, 451, 451, 451, 451]", 0, "-451")])
def test_fk_nonpositive_prismatic_length_is_bad_input(tmp_path, capsys, angles, leg, shown):
    """Was exit 1 'ZeroDivisionError: float division by zero' (0) or a not_found (-451)."""
    line = _one_line(*_run(tmp_path, capsys, _gough(
        f'type = "forward_kinematics"\nangles = {angles}\n'))[::2])
    assert f"query[0].angles[{leg}]: expected a positive leg length" in line
    assert f"mm), got {shown}" in line and "hint:" in line


@pytest.mark.parametrize("qtype", ["inverse_kinematics", "jacobian"])
def test_far_pose_is_bad_input_in_scene_units(tmp_path, capsys, qtype):
    """pose z = 1e300 mm: q was NaN (exit 0) after 82 lines of RuntimeWarnings."""
    line = _one_line(*_run(tmp_path, capsys, RSS.format(
        angle="deg", preset="octopod", extra="",
        query=f'type = "{qtype}"\npose = [0, 0, 1e300, 0, 0, 0]'))[::2])
    assert "query[0].pose[2]: expected a translation component" in line
    assert "got 1e+300 mm" in line and '[units] length is "mm"' in line


def test_meaningless_rotation_refused_moderate_rad_kept(tmp_path, capsys):
    """rx = 1e20 deg was 'reachable' with definite angles; 15 rad is a legitimate angle
    (no word about it), and the same q as 15 - 4π rad."""
    line = _one_line(*_run(tmp_path, capsys, RSS.format(
        angle="deg", preset="octopod", extra="",
        query='type = "inverse_kinematics"\npose = [0, 0, 300, 1e20, 0, 0]'))[::2])
    assert "query[0].pose[3]: expected a rotation component" in line and "1e+20 deg" in line
    qs = []
    for rx in (15, 15 - 4 * math.pi):
        code, out, err = _run(tmp_path, capsys, RSS.format(
            angle="rad", preset="octopod", extra="",
            query=f'type = "inverse_kinematics"\npose = [0, 0, 300, {rx!r}, 0, 0]'),
            "--json", "-")
        assert code == 0 and "warning" not in err
        qs.append(json.loads(out[out.index("{"):])["queries"][0]["result"]["poses"][0]["q"])
    assert np.allclose(qs[0], qs[1], atol=1e-12)


def test_singularity_on_kind_rss_matches_its_leg_table(tmp_path, capsys):
    """Was exit 2 'needs a mechanism of kind legs ...'.  Second route: the same geometry
    as a leg table on the numpy kernels (no generated code)."""
    from distkin.app.queries.leg_singularity import singularity_tests_at
    from distkin.mechanisms import LegMechanism, preset
    code, out, err = _run(tmp_path, capsys, RSS.format(
        angle="deg", preset="hunt", extra="",
        query='type = "singularity"\npose = [10, 0, 300, 5, 0, 0]'), "--json", "-")
    assert code == 0, err
    row = json.loads(out[out.index("{"):])["queries"][0]["result"]["poses"][0]
    legs = LegMechanism.from_description(preset("hunt"), route="numpy")
    ref = singularity_tests_at(legs, [0.01, 0, 0.3, math.radians(5), 0, 0])
    assert row["det_J"] == pytest.approx(ref["det_J"], rel=1e-12)
    assert row["sigma_min"] == pytest.approx(ref["sigma_min"], rel=1e-12)


@pytest.mark.parametrize("extra, warned", [("l0 = 0.152", "mechanism.l0"),
                                           ("mass = 170", "mechanism.mass"),
                                           ("l0 = 160", None)])
def test_override_unit_slip_is_one_warning_line(tmp_path, capsys, extra, warned):
    """l0 = 0.152 in a mm scene (0.152 mm, 1/1000 of the preset's 152 mm) ran without a
    word."""
    code, out, err = _run(tmp_path, capsys, RSS.format(
        angle="deg", preset="octopod", extra=extra,
        query='type = "inverse_kinematics"\npose = [0, 0, 300, 0, 0, 0]'))
    assert code == 0
    lines = [ln for ln in err.splitlines() if ln.startswith("distkin: warning:")]
    if warned is None:
        assert not lines
        return
    assert len(lines) == 1 and lines[0].startswith(f"distkin: warning: {warned}: ")
    assert ('[units] length is "mm"' in lines[0]) == (warned == "mechanism.l0")


def test_fk_refusal_in_scene_units(tmp_path, capsys):
    """'misses them by up to 2.28 (rad or m ...)' in a degree scene: now in deg.  Second
    route: the library's q_mismatch (rad) in degrees."""
    from distkin.mechanisms import preset
    line = _one_line(*_run(tmp_path, capsys, RSS.format(
        angle="deg", preset="octopod", extra="",
        query='type = "forward_kinematics"\nangles = [170, 170, 170, 170, 170, 170, 170, 170]'
              '\nguess = [0, 0, 300, 0, 0, 0]'))[::2])
    m = preset("octopod")
    ref = m.forward_kinematics(np.radians([170.0] * 8), m.home,
                               warn=False).q_mismatch      # (the flags, no warning)
    assert "rad or m" not in line
    shown = float(re.search(r"misses them by up to ([0-9.e+-]+) deg", line).group(1))
    assert shown == pytest.approx(math.degrees(ref), rel=5e-3)
