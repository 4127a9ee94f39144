"""The octahedral and points scene modules name the scene's length unit (QA: a
``length = "mm"`` octahedral scene's module was the unitless one's, its inputs "squared
length units" and SIDES2 in mm^2 unsaid).  A unitless scene keeps the generic words.

The stated powers of the unit are checked against the kernels themselves: scaling every
length by 2 (every squared input by 4) scales a determinant stated in mm^n by 2^n."""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest
import sympy

from distkin.codegen.cayley_menger_scene import module_text as cm_text
from distkin.codegen.octahedral_scene import module_text as oct_text
from distkin.octahedral.banana import SIDE_PAIRS

SIDES = {p: sympy.Integer(144) for p in SIDE_PAIRS}
DETS = [("D123", (1, 2, 3), (1, 2, 3)), ("D1234", (1, 2, 3, 4), (1, 2, 3, 4))]


def _load(src, tmp_path, name):
    path = tmp_path / f"{name}.py"
    path.write_text(src)
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("unit", ["mm", "cm", "m"])
def test_octahedral_module_names_its_unit(unit, tmp_path):
    src = oct_text(SIDES, ["octic", "s15_interval"], ("batched", "scalar"), generator="g",
                   title="T", length_unit=unit)
    mod = _load(src, tmp_path, f"oct_{unit}")
    assert mod.LENGTH_UNIT == unit
    assert f"in {unit}^2" in mod.__doc__ and "SIDES2" in mod.__doc__
    for k in ("octic", "s15_interval", "octic_scalar", "s15_interval_scalar"):
        doc = getattr(mod, k).__doc__
        assert f"{unit}^2 (the scene's unit)" in doc and "squared length units" not in doc


@pytest.mark.parametrize("unit", [None, "none"])
def test_unitless_octahedral_module_keeps_the_generic_words(unit, tmp_path):
    src = oct_text(SIDES, ["octic"], ("batched",), generator="g", title="T", length_unit=unit)
    mod = _load(src, tmp_path, "oct_none")
    assert mod.LENGTH_UNIT is None
    assert "squared length units" in mod.octic.__doc__ and "unitless" in mod.__doc__
    assert "mm" not in src


def test_unit_changes_the_module_only_in_its_words(tmp_path):
    mm = oct_text(SIDES, ["octic"], ("batched",), generator="g", title="T", length_unit="mm")
    bare = oct_text(SIDES, ["octic"], ("batched",), generator="g", title="T")
    assert mm != bare
    a, b = _load(mm, tmp_path, "a"), _load(bare, tmp_path, "b")
    legs2 = np.array([400.0, 324, 324, 289, 225, 324])
    assert np.array_equal(a.octic(legs2), b.octic(legs2))


def test_points_module_names_its_unit_and_the_determinants_powers(tmp_path):
    mod = _load(cm_text(DETS, ("batched",), generator="g", title="T", length_unit="mm"),
                tmp_path, "cm_mm")
    assert mod.LENGTH_UNIT == "mm" and "in mm^2" in mod.__doc__
    doc = mod.determinants.__doc__
    assert "in mm^2, the scene's unit" in doc and "D123: mm^4" in doc and "D1234: mm^6" in doc
    # the kernels: lengths x 2 multiply D123 by 2^4 and D1234 by 2^6
    P = np.array([[0, 0, 0], [3, 0, 0], [0, 4, 0], [1, 1, 5.0]])
    sq = np.array([np.sum((P[i - 1] - P[j - 1]) ** 2) for i, j in mod.PAIRS])
    d1, d2 = mod.determinants(sq), mod.determinants(4 * sq)
    assert d2 / d1 == pytest.approx([2.0 ** 4, 2.0 ** 6])
    bare = cm_text(DETS, ("batched",), generator="g", title="T")
    assert "squared length units" in bare and "mm" not in bare
    assert _load(bare, tmp_path, "cm_bare").LENGTH_UNIT is None


@pytest.mark.parametrize("scene_file, unit, power", [("points_banana.toml", "m", "m^2"),
                                                      ("octahedral_griffis_duffy.toml", "mm",
                                                       "mm^2")])
def test_the_codegen_command_names_the_scenes_unit(tmp_path, scene_file, unit, power):
    """QA X4 6, end to end: ``distkin codegen`` passes the scene's [units] length to the
    generators (they took it, the command did not).  Reference: the scene file itself,
    its length unit set here."""
    import re
    from pathlib import Path

    from distkin.app.cli import main
    root = Path(__file__).resolve().parents[2]
    text = (root / "examples" / scene_file).read_text(encoding="utf-8")
    text = re.sub(r'length = "[^"]*"', f'length = "{unit}"', text, count=1)
    if "[units]" not in text:
        text = f'[units]\nlength = "{unit}"\n' + text
    scene = tmp_path / scene_file
    scene.write_text(text, encoding="utf-8")
    out = tmp_path / "m.py"
    assert main(["codegen", str(scene), "-o", str(out)]) == 0
    src = out.read_text(encoding="utf-8")
    assert f"LENGTH_UNIT = '{unit}'" in src and power in src
