"""A home pose just beyond a leg's stroke end (QA): the warning printed the length and
the range with 4 digits, so a length 1 µm beyond 0.4 m read "0.4 m outside its range
[0.35, 0.4] m".  Now both print with the digits that tell them apart
(:func:`distkin.numfmt.apart`).  Reference: the leg length computed here with numpy from
the joints of the leg table at home, and the stroke set from it."""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import numpy as np
import pytest

from distkin.app.scene import load_scene
from distkin.errors import GeometryWarning
from distkin.mechanisms.legs import LegsDescription
from distkin.spatial import rotation_matrix

ROOT = Path(__file__).resolve().parents[2]


def test_home_just_beyond_a_stroke_prints_the_length_outside():
    mech = load_scene(ROOT / "examples" / "gough_stewart_6ups.toml").mechanism
    legs = list(mech.leg_table)
    X = np.array(mech.home_pose)
    n = float(np.linalg.norm(X[:3] + rotation_matrix(X[3:]) @ np.array(legs[0].platform)
                             - np.array(legs[0].base)))
    hi = n - 1e-6                                  # 1 µm short of the home length
    legs[0] = dataclasses.replace(legs[0], range=(legs[0].range[0], hi))
    with pytest.warns(GeometryWarning) as rec:
        LegsDescription("slip", legs, tuple(X))
    msg = " ".join(str(w.message) for w in rec)
    got = re.search(r"leg 1 length (\S+) m outside its range \[(\S+), (\S+)\] m", msg)
    assert got, msg
    shown, top = float(got.group(1)), float(got.group(3))
    assert shown > top                          # visibly outside, as the comparison said
    assert shown == pytest.approx(n, rel=1e-6) and top == pytest.approx(hi, rel=1e-6)
