"""An output option never names an input file: ``distkin run S.toml --json S.toml``
replaced the scene by its JSON result (QA G 1).  Every command that reads a scene and
writes files (run, sweep, codegen, control, sim) refuses such a path with exit 2 and one
line, before any work, and the input is left byte for byte as it was.

Reference: the input's bytes, read before the command, and the same path under another
spelling (``./``, a symbolic link, a hard link), which :func:`os.path.samefile` sees as
the same file.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

from distkin.app.cli import main
from distkin.app.legs_scene import legs_csv_text, legs_toml_text
from distkin.app.output_paths import check_output_path
from distkin.errors import InputError
from distkin.mechanisms import preset

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

POINTS = """
[mechanism]
kind = "points"
points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]

[[query]]
type = "cayley_menger"
determinants = ["D(1,2,3,4)"]
"""


def _refused(capsys, args, field, source):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, err
    assert lines[0].startswith(f"distkin: error: {field}: expected an output path other "
                               f"than the input file {str(source)!r}, got "), lines[0]
    assert "overwrite the input" in lines[0]
    assert out == ""                                  # nothing ran
    return lines[0]


@pytest.mark.parametrize("command", ["run", "sweep"])
def test_json_onto_the_scene_is_refused(tmp_path, capsys, monkeypatch, command):
    scene = tmp_path / "s.toml"
    scene.write_text(POINTS)
    before = scene.read_bytes()
    _refused(capsys, [command, scene, "--json", scene], "--json", scene)
    assert scene.read_bytes() == before
    # the same file under other names: a relative path with ./, a symlink, a hard link
    monkeypatch.chdir(tmp_path)
    (tmp_path / "link.toml").symlink_to(scene)
    os.link(scene, tmp_path / "hard.toml")
    (tmp_path / "sub").mkdir()
    for alias in ("./s.toml", tmp_path / "sub" / ".." / "s.toml", tmp_path / "link.toml",
                  tmp_path / "hard.toml"):
        _refused(capsys, [command, "s.toml", "--json", alias], "--json", "s.toml")
        assert scene.read_bytes() == before
    # another file still works
    assert main(["run", str(scene), "--json", str(tmp_path / "r.json")]) == 0
    assert scene.read_bytes() == before and (tmp_path / "r.json").is_file()


def test_json_onto_the_legs_csv_is_refused(tmp_path, capsys):
    """The CSV leg table a scene reads is an input too."""
    m = preset("hunt")
    csv = tmp_path / "legs.csv"
    csv.write_text(legs_csv_text(m, length_unit="mm"))
    scene = tmp_path / "s.toml"
    scene.write_text(legs_toml_text(m, length_unit="mm", csv_name="legs.csv")
                     + '\n[[query]]\ntype = "inverse_kinematics"\npose = [0, 0, 300, 0, 0, 0]\n')
    before = csv.read_bytes()
    _refused(capsys, ["run", scene, "--json", csv], "--json", csv)
    assert csv.read_bytes() == before


def test_codegen_output_onto_the_scene_is_refused(tmp_path, capsys):
    """codegen wants a .py output; a scene saved as .py was overwritten by the module."""
    scene = tmp_path / "scene.py"
    scene.write_text(POINTS)
    _refused(capsys, ["codegen", scene, "-o", scene], "--output", scene)
    assert scene.read_text() == POINTS


def test_control_and_sim_outputs_onto_the_scene_are_refused(tmp_path, capsys):
    """--json, --log (PREFIX.cycles.csv, ...) and --port-file never replace the
    controller scene; refused before the simulator starts."""
    scene = tmp_path / "c.toml"
    scene.write_text((EXAMPLES / "control_octo.toml").read_text(encoding="utf-8"))
    before = scene.read_bytes()
    _refused(capsys, ["control", "--sim", "--scene", scene, "--json", scene], "--json", scene)
    log = tmp_path / "run.cycles.csv"
    log.symlink_to(scene)
    _refused(capsys, ["control", "--sim", "--scene", scene, "--log", tmp_path / "run"],
             "--log", scene)
    _refused(capsys, ["sim", "--scene", scene, "--port-file", scene], "--port-file", scene)
    assert scene.read_bytes() == before


def test_control_outputs_onto_the_device_mechanism_scene_are_refused(tmp_path, capsys):
    """The distkin scene named by ``[device] mechanism`` is read too: --json or
    --port-file onto it is refused (it was not among the protected inputs)."""
    import shutil
    for name in ("control_gough6.toml", "gough_stewart_6ups.toml"):
        shutil.copy(EXAMPLES / name, tmp_path / name)
    scene, mech = tmp_path / "control_gough6.toml", tmp_path / "gough_stewart_6ups.toml"
    before = mech.read_bytes()
    _refused(capsys, ["control", "--sim", "--scene", scene, "--json", mech], "--json", mech)
    _refused(capsys, ["sim", "--scene", scene, "--port-file", mech], "--port-file", mech)
    # --plots onto it (a folder named as the file): one line, before the mechanism loads
    code = main(["control", "--scene", str(scene), "--delay-margin", "3", "--plots", str(mech)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and err[0].startswith(
        f"distkin: error: --plots: expected a folder other than the input file {str(mech)!r}")
    assert mech.read_bytes() == before


def test_check_output_path_inputs(tmp_path):
    src = tmp_path / "in.toml"
    src.write_text("x")
    with pytest.raises(InputError) as exc:
        check_output_path(src, "--json", inputs=[None, src])
    assert exc.value.field == "--json" and repr(str(src)) in exc.value.message
    # not yet existing outputs, stdout and no output pass
    check_output_path(tmp_path / "out.json", inputs=[src])
    check_output_path("-", inputs=[src])
    check_output_path(None, inputs=[src])
    # an input that does not exist (yet) is compared by its resolved path
    with pytest.raises(InputError):
        check_output_path(tmp_path / "a" / ".." / "new.json", inputs=[tmp_path / "new.json"])


@pytest.mark.parametrize("args", [["codegen", "{scene}", "-o", "{gen}/rss_hunt.py"],
                                  ["run", "{scene}", "--json", "{gen}/out.json"],
                                  ["run", "{scene}", "--plots", "{gen}/plots"],    # QA W 5
                                  ["sweep", "{scene}", "--store", "{gen}/st"],
                                  ["demo", "--plots", "{gen}/plots"]])
def test_outputs_into_the_generated_kernels_are_refused(tmp_path, capsys, args):
    """QA U 8: ``distkin codegen -o distkin/_generated/rss_hunt.py`` replaced a committed
    kernel (``--check`` then said stale; ``preset('hunt')`` derived it again at run
    time).  Refused before any work, the kernel byte for byte as it was (reference: its
    bytes read before the command)."""
    from distkin.app.output_paths import GENERATED
    kernel = GENERATED / "rss_hunt.py"
    before = kernel.read_bytes()
    scene = tmp_path / "s.toml"
    scene.write_text(POINTS, encoding="utf-8")
    try:
        code = main([a.format(scene=scene, gen=GENERATED) for a in args])
        err = capsys.readouterr().err
        assert code == 2 and "outside distkin's generated kernels" in err, err
        assert kernel.read_bytes() == before
        assert not any((GENERATED / n).exists() for n in ("out.json", "plots", "st"))
    finally:                                # a regression must not leave the tree changed
        if kernel.read_bytes() != before:
            kernel.write_bytes(before)
        (GENERATED / "out.json").unlink(missing_ok=True)
        for n in ("plots", "st"):
            shutil.rmtree(GENERATED / n, ignore_errors=True)
