"""The ``cayley_menger`` query says what each tier can vouch for (QA X3 D1): the fast
value of a determinant that is exactly 0 carried no flag (the API's CancellationWarning
was swallowed), and the precise tier printed 20 digits of noise for it with no error
estimate.  Reference: the certified tier's exact value (fmpq) of the same determinants
of six rational points: D(1..6) of six points in 3-D is exactly 0, the others are
not."""

from __future__ import annotations

import json

import pytest

from distkin.app.cli import main

SCENE = """
[units]
length = "mm"
[mechanism]
kind = "points"
points = [[0, 0, 0], [6, 0, 0], [2, 5, 0], [1, 1, 4], [3, -2, "5/2"], ["-1/2", 3, 2]]
[[query]]
type = "cayley_menger"
determinants = ["D(1,2,3,4,5,6)", "D(1,2,3,4)", "D(5,4,1,2;5,4,1,6)"]
method = "{method}"
"""


def _run(tmp_path, capsys, method):
    f = tmp_path / f"{method}.toml"
    f.write_text(SCENE.format(method=method), encoding="utf-8")
    out = tmp_path / f"{method}.json"
    assert main(["run", str(f), "--no-progress", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    return json.loads(out.read_text())["queries"][0]["result"]["determinants"], text


@pytest.mark.parametrize("method", ["fast", "precise"])
def test_a_value_the_tier_cannot_tell_from_0_is_flagged(tmp_path, capsys, method):
    exact, _ = _run(tmp_path, capsys, "certified")
    got, text = _run(tmp_path, capsys, method)
    for ref, entry in zip(exact, got):
        zero = ref["value"] == "0"
        assert ("cannot_vouch" in entry) == zero, entry
        # the estimate is of the error: it covers the distance to the exact value
        assert abs(float(entry["value"]) - float(ref["value"])) <= entry["error_estimate"]
        assert entry["unit"] == ref["unit"]
    assert exact[0]["value"] == "0" and "WARNING" in text and "D(1,2,3,4,5,6)" in text
    assert text.count("WARNING") == 1 and "error estimate" in text


def test_certified_has_no_estimate_only_its_exact_value(tmp_path, capsys):
    exact, text = _run(tmp_path, capsys, "certified")
    assert all("error_estimate" not in e and "cannot_vouch" not in e for e in exact)
    assert "WARNING" not in text
