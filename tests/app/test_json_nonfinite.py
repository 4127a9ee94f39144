"""The JSON document is strict JSON (docs/design.md §4): NaN and the infinities, which
JSON lacks, are the strings "nan", "inf" and "-inf"; exact values are strings and arb
balls ``{"mid", "rad"}``.  Checked with the standard library's strict parser, which
refuses the bare ``NaN``/``Infinity`` that ``json.dumps`` writes by default."""

import json
import math
from fractions import Fraction

import numpy as np
import pytest

from distkin.app.report import document, dumps, jsonable


def _strict(text):
    def refuse(token):
        raise ValueError(f"not JSON: {token}")
    return json.loads(text, parse_constant=refuse)


def test_nonfinite_values_are_strings_in_strict_json():
    rec = {"type": "t", "status": "ok", "seconds": 0.0,
           "result": {"a": math.nan, "b": np.array([np.inf, -np.inf, 1.5]),
                      "c": Fraction(99, 5), "d": np.float32("nan")}}
    doc = _strict(dumps(document("s.toml", [rec], "0")))
    r = doc["queries"][0]["result"]
    assert r == {"a": "nan", "b": ["inf", "-inf", 1.5], "c": "99/5", "d": "nan"}


def test_a_bare_nan_never_reaches_the_text():
    with pytest.raises(ValueError):
        dumps({"x": math.nan})          # jsonable is the only way in: allow_nan=False


def test_design_md_documents_it():
    from pathlib import Path
    text = (Path(__file__).resolve().parents[2] / "docs" / "design.md").read_text()
    assert '`"nan"`' in text and '`"-inf"`' in text and jsonable(-math.inf) == "-inf"
