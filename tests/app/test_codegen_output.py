"""``distkin codegen -o`` (QA 10): an existing file that distkin codegen did not write
was overwritten silently, and ``-o numpy.py`` only warned, then broke every later
``python -m distkin`` run from that folder.  Now the first is refused unless
``--force``, the second always (exit 2, one line naming the path).  References: a
fresh interpreter's imports (is a module hidden?) and a module written to a new file."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from distkin.app.cli import main

SCENE = Path(__file__).resolve().parents[2] / "examples" / "rss_octopod.toml"


def _cli(capsys, *args):
    capsys.readouterr()
    code = main(["codegen", str(SCENE), "--flavour", "scalar", *map(str, args)])
    return code, capsys.readouterr().err


def _hides_a_module(name, folder) -> bool:
    """A fresh interpreter in ``folder`` imports a real module ``name``, and with an
    empty ``name.py`` there imports that file instead."""
    def origin():
        r = subprocess.run([sys.executable, "-c", f"import {name}; print({name}.__file__)"],
                           cwd=folder, capture_output=True, text=True)
        return r.stdout.strip() if r.returncode == 0 else None
    real = origin()
    (folder / f"{name}.py").write_text("", encoding="utf-8")
    try:
        return real is not None and str(folder) in (origin() or "")
    finally:
        (folder / f"{name}.py").unlink()


def test_a_file_not_written_by_codegen_is_kept_unless_forced(tmp_path, capsys):
    fresh = tmp_path / "fresh.py"
    assert _cli(capsys, "-o", fresh)[0] == 0
    mine = tmp_path / "mine.py"
    mine.write_text("x = 1  # my own work\n", encoding="utf-8")
    code, err = _cli(capsys, "-o", mine)
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert str(mine) in err and "x = 1" in err and "--force" in err
    assert mine.read_text(encoding="utf-8") == "x = 1  # my own work\n"
    assert _cli(capsys, "-o", mine, "--force")[0] == 0
    assert mine.read_bytes() == fresh.read_bytes()
    # a module codegen wrote is replaced without --force (a second run of the scene)
    code, err = _cli(capsys, "-o", fresh)
    assert code == 0 and "from the derivation cache" in err


@pytest.mark.parametrize("stem", ["numpy", "json", "sympy", "flint", "distkin"])
def test_a_name_that_hides_a_module_is_refused(tmp_path, capsys, stem):
    assert _hides_a_module(stem, tmp_path)
    code, err = _cli(capsys, "-o", tmp_path / f"{stem}.py", "--force")
    assert code == 2 and err.count("\n") == 1 and f"{stem}.py" in err
    assert f"{stem}_kernels.py" in err                   # the hint: a name that works
    assert not (tmp_path / f"{stem}.py").exists()


def test_a_name_that_hides_nothing_is_written(tmp_path, capsys):
    assert not _hides_a_module("distkin_qa10_kernels", tmp_path)
    code, _ = _cli(capsys, "-o", tmp_path / "distkin_qa10_kernels.py")
    assert code == 0 and (tmp_path / "distkin_qa10_kernels.py").is_file()
