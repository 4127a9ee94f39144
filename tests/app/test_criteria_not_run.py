"""Design criterion 4 without a certificate said "certificate None" (QA IX 6: a Python
None in the report, in every ``performance`` run without ``certify = true`` and in the
rus8_device example).  It says "not run" and how to run it; the JSON keeps null.  The
reference is the JSON record of the same run (the criterion's own value) and the scene,
which asks for no certificate."""

from __future__ import annotations

import re

SCENE = """title = "no certificate"
[units]
length = "mm"
angle = "deg"
[mechanism]
kind = "rss"
preset = "hunt"
[[query]]
type = "performance"
grid = { half = 25, step = 25, rotation = 10, rotation_step = 10 }
"""


def test_criterion_4_without_certificate_says_not_run(tmp_path):
    from distkin.app.cli import run_scene
    from distkin.app.scene import loads_scene
    scene = loads_scene(SCENE, str(tmp_path / "s.toml"))
    records, texts, worst = run_scene(scene, progress=False)
    assert worst == 0, records[0].get("error")
    c4 = records[0]["result"]["devices"][0]["criteria"][3]
    assert c4["number"] == 4 and c4["value"]["certificate_zero_rotation"] is None
    text = texts[0]
    assert "certificate not run (certify = true in the performance query runs it)" in text
    assert not re.search(r"\bNone\b", text), [ln for ln in text.splitlines()
                                               if re.search(r"\bNone\b", ln)]
    # and no Python True / False either: the criteria's flags in words, as in the JSON
    c1 = records[0]["result"]["devices"][0]["criteria"][0]["value"]
    assert not re.search(r"\b(True|False)\b", text)
    words = {True: "yes", False: "no"}
    assert (f"all reachable {words[c1['all_reachable']]}, det sign changes "
            f"{words[c1['det_sign_changes']]}") in text
