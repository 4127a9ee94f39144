"""Mistakes users make, as they make them: each is refused with one line on stderr that
names the field (anchored in the scene), the expected and the received value with its
unit, exit code 2 and no traceback; an unwritable ``--json`` is refused before the run.

The expected texts are written from the scene (the field a user typed, the value in the
scene's units and in SI), not copied from the program's output.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from distkin.app.cli import build_parser, main
from distkin.app.output_paths import check_output_path, write_json
from distkin.app.scene import loads_scene
from distkin.errors import InputError

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

OCTA = """
[mechanism]
kind = "octahedral"
base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]

[[query]]
type = "forward_kinematics"
legs = ["19.8", "18", "18", "17", "14.9", "17.8"]
method = "precise"
dps = "x"
"""

RSS = """
[units]
length = "mm"
angle = "deg"

[mechanism]
kind = "rss"
preset = "octo"
{extra}

[[query]]
type = "inverse_kinematics"
{query}
"""

POINTS = """
[mechanism]
kind = "points"
points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]

[[query]]
type = "cayley_menger"
determinants = ["D(1,2,3,4)"]
method = "certified"
"""


def _cli(capsys, args):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


def _one_line_error(code, err):
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("distkin: error: "), err
    assert "Traceback" not in err
    return lines[0]


def test_dps_error_names_the_query_field(tmp_path, capsys):
    """A query's dps used to be reported as a bare 'dps:' (no query named)."""
    f = tmp_path / "s.toml"
    f.write_text(OCTA)
    line = _one_line_error(*_cli(capsys, ["run", f])[::2])
    assert "query[0].dps: expected dps as an integer 5..1233" in line and "got 'x'" in line


def test_rss_override_error_carries_units_both_ways(tmp_path, capsys):
    """l1 = -5 in a mm scene: the message gives the SI value with its unit (-0.005 m:
    -5 mm / 1000) and the value as the scene wrote it (-5 mm); it used to print a bare
    -0.005."""
    f = tmp_path / "s.toml"
    f.write_text(RSS.format(extra="l1 = -5", query="poses = [[0, 0, 300, 0, 0, 0]]"))
    line = _one_line_error(*_cli(capsys, ["run", f])[::2])
    assert "mechanism.l1:" in line
    assert "got -0.005 m" in line and "l1 = -5 mm" in line
    f.write_text(RSS.format(extra="gamma = -3", query="poses = [[0, 0, 300, 0, 0, 0]]"))
    line = _one_line_error(*_cli(capsys, ["run", f])[::2])
    assert "mechanism.gamma:" in line and " rad" in line and "gamma = -3 deg" in line
    with pytest.raises(InputError, match="got -3.0 kg"):
        loads_scene(RSS.format(extra="mass = -3", query="poses = [[0, 0, 300, 0, 0, 0]]"))


def test_leg_table_errors_carry_units():
    """A reversed stroke [550, 350] mm: (0.55, 0.35) m; a negative payload mass: kg."""
    text = (EXAMPLES / "gough_stewart_6ups.toml").read_text(encoding="utf-8")
    bad = text.replace("range = [350, 550]", "range = [550, 350]", 1)
    with pytest.raises(InputError) as exc:
        loads_scene(bad)
    assert exc.value.field == "mechanism.leg[0].range"
    assert "got (0.55, 0.35) m" in exc.value.message
    bad = text.replace("mass = 10", "mass = -10", 1)
    with pytest.raises(InputError) as exc:
        loads_scene(bad)
    assert exc.value.field == "mechanism.mass" and "got -10.0 kg" in exc.value.message


def test_one_pose_without_its_outer_brackets(tmp_path, capsys):
    """poses = [0, 0, 300, 0, 0, 0] (a single pose, brackets forgotten) used to read
    'query[0].poses[0]: expected a list of 6 numbers, got 0'."""
    f = tmp_path / "s.toml"
    f.write_text(RSS.format(extra="", query="poses = [0, 0, 300, 0, 0, 0]"))
    line = _one_line_error(*_cli(capsys, ["run", f])[::2])
    assert "query[0].poses: expected a list of poses" in line
    assert "flat list of 6 values" in line and "pose = [...]" in line
    # the singularity query of a legs mechanism reads its poses the same way
    text = (EXAMPLES / "gough_stewart_6ups.toml").read_text(encoding="utf-8")
    text += '\n[[query]]\ntype = "singularity"\nposes = [0, 0, 400, 0, 0, 0]\n'
    with pytest.raises(InputError, match="flat list of 6 values") as exc:
        loads_scene(text)
    assert exc.value.field.endswith("].poses")


@pytest.mark.parametrize("kind", ["directory", "under a file"])
def test_unwritable_json_is_refused_before_the_run(tmp_path, capsys, kind):
    """--json at a directory, or below a file, used to fail after the whole run as an
    'internal failure' (exit 1) and lose the JSON."""
    f = tmp_path / "s.toml"
    f.write_text(POINTS)
    (tmp_path / "plain").write_text("")
    target = tmp_path if kind == "directory" else tmp_path / "plain" / "out.json"
    code, out, err = _cli(capsys, ["run", f, "--json", target])
    line = _one_line_error(code, err)
    assert "--json: expected a" in line and str(target) in line
    assert out == ""                              # refused before the scene ran
    code, out, err = _cli(capsys, ["demo", "--json", target])
    _one_line_error(code, err)
    assert out == ""


def test_json_goes_into_new_folders(tmp_path, capsys):
    f = tmp_path / "s.toml"
    f.write_text(POINTS)
    target = tmp_path / "new" / "deeper" / "r.json"
    code, out, _ = _cli(capsys, ["run", f, "--json", target])
    assert code == 0 and f"JSON written to {target}" in out
    doc = json.loads(target.read_text())
    # D(1,2,3,4) of the unit corner = 288 V^2 = 288 / 36 = 8
    assert doc["queries"][0]["result"]["determinants"][0]["value"] == "8"
    write_json(tmp_path / "a" / "b.json", "{}")
    assert (tmp_path / "a" / "b.json").read_text() == "{}\n"
    check_output_path("-")
    check_output_path(None)


def test_every_option_of_run_demo_and_sweep_says_what_it_does():
    """``distkin demo --help`` listed --json, --plots and --no-progress without a word."""
    sub = next(a for a in build_parser()._actions if a.dest == "command")
    for name in ("run", "demo", "sweep"):
        for action in sub.choices[name]._actions:
            if action.dest != "help" and action.option_strings:
                assert action.help, f"distkin {name} {action.option_strings[0]}: no help"
    # the sweep runs every chunked query (docs/design.md §4 "Run store")
    sweep_help = next(a.help for a in sub._choices_actions if a.dest == "sweep")
    for q in ("performance", "design_sweep", "certify_workspace"):
        assert q in sweep_help


def test_python_api_refuses_text_with_an_input_error():
    """preset("octo").jacobian("abc") and forward_kinematics(q, guess="abc") used to
    raise numpy's bare ValueError ('could not convert string to float')."""
    from distkin.mechanisms import preset
    m = preset("octo")
    q, ok = m.inverse_kinematics(m.home)
    assert ok.all()
    with pytest.raises(InputError) as exc:
        m.jacobian([0, "a", 0.3, 0, 0, 0])
    assert exc.value.field == "poses" and "m and rad" in exc.value.message
    with pytest.raises(InputError) as exc:
        m.forward_kinematics("abc", m.home)
    assert exc.value.field == "q" and "8 joint coordinates" in exc.value.message
    with pytest.raises(InputError) as exc:
        m.forward_kinematics(q, "abc")
    assert exc.value.field == "guess"
    # the same pose as numbers is accepted, and FK from its own IK returns it
    fk = m.forward_kinematics(q, m.home)
    assert fk.ok and np.allclose(fk.pose, m.home, atol=1e-9)


def test_unusable_chunk_store_is_bad_input(tmp_path, capsys):
    """A store below a file used to end as 'NotADirectoryError' (exit 1); as --store it is
    refused before the run, as a scene's store field it names the query's field."""
    from distkin.runstore import make_store, run_chunks
    (tmp_path / "plain").write_text("")
    bad = tmp_path / "plain" / "chunks"
    scene = EXAMPLES / "certify_hunt.toml"
    line = _one_line_error(*_cli(capsys, ["sweep", scene, "--store", bad])[::2])
    assert "--store: expected a directory for the chunks" in line and str(bad) in line
    with pytest.raises(InputError) as exc:
        run_chunks(abs, [1.0], bad, progress=False)
    assert exc.value.field == "store" and "(Not a directory)" in exc.value.message
    assert make_store(tmp_path / "a" / "b").is_dir()


def test_simulator_and_controller_options_refused_before_they_start(tmp_path, capsys,
                                                                     monkeypatch):
    """distkin sim --tcp -5 / 99999, a busy port, an unwritable --port-file or --log and a
    missing --scene used to end as internal failures (OverflowError, OSError,
    NotADirectoryError: exit 1) or name the path instead of the option."""
    import socket
    (tmp_path / "plain").write_text("")
    below_file = tmp_path / "plain" / "x"
    for port in ("-5", "99999"):
        with pytest.raises(SystemExit) as stop:
            main(["sim", "--tcp", port])
        assert stop.value.code == 2
        assert f"--tcp: expected a TCP port in 0..65535, got '{port}'" in capsys.readouterr().err
    from distkin.control import kinematics
    from distkin.control.simulator import TcpTransport
    monkeypatch.setattr(kinematics, "model_of", lambda scene: None)   # no compiling
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen(1)
        port = busy.getsockname()[1]
        with pytest.raises(InputError, match="Address already in use") as exc:
            TcpTransport(port)
        assert exc.value.field == "tcp_port"
        line = _one_line_error(*_cli(capsys, ["sim", "--tcp", port, "--idle-timeout", 1])[::2])
    assert f"--tcp: expected a free TCP port in 0..65535 on 127.0.0.1, got {port}" in line
    cases = [(["sim", "--port-file", below_file], "--port-file: expected a writable file"),
             (["sim", "--log", below_file], "--log: expected a writable file"),
             (["sim", "--scene", tmp_path / "nope.toml"], "--scene: expected a controller "
                                                          "scene file"),
             (["control", "--sim", "--scene", tmp_path], "(a directory)"),
             (["control", "--sim", "--log", below_file], "x.cycles.csv"),
             (["control", "--sim", "--json", tmp_path], "--json: expected a file path")]
    for args, expected in cases:
        assert expected in _one_line_error(*_cli(capsys, args)[::2]), args


def test_codegen_output_checked_before_deriving(tmp_path, capsys):
    """distkin codegen -o below a file used to end as FileExistsError (exit 1) after the
    derivation; a name 'import' cannot load is written with a warning naming a module
    name that can."""
    scene = EXAMPLES / "rss_octopod.toml"
    (tmp_path / "plain").write_text("")
    line = _one_line_error(*_cli(capsys, ["codegen", scene, "-o",
                                          tmp_path / "plain" / "k.py"])[::2])
    assert "--output: expected a writable file path" in line and "is not a folder" in line
    out = tmp_path / "my-kernels.py"
    code, _, err = _cli(capsys, ["codegen", scene, "-o", out])
    assert code == 0 and out.is_file()
    assert "'my-kernels' is not a Python module name" in err and "my_kernels.py" in err
    import importlib.util
    spec = importlib.util.spec_from_file_location("my_kernels", out)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert mod.L == 8                          # the Octopod's eight legs


def test_reversed_region_names_its_units():
    """lower > upper in a mm/deg scene: the refused bounds are the scene's numbers, so the
    message says they are mm and deg (they had no unit)."""
    text = (EXAMPLES / "certify_hunt.toml").read_text(encoding="utf-8")
    bad = text.replace("lower = [-75, -75, 225", "lower = [80, -75, 225", 1)
    with pytest.raises(InputError) as exc:
        loads_scene(bad)
    assert exc.value.field == "query[0].region"
    assert "lower=[80.0, -75.0, 225.0" in exc.value.message
    assert "(x, y, z in mm, rx, ry, rz in deg)" in exc.value.message


def test_single_bracket_query_table(tmp_path, capsys):
    """[query] instead of [[query]] used to read 'expected at least one [[query]] table'
    although a query was there."""
    f = tmp_path / "s.toml"
    f.write_text(POINTS.replace("[[query]]", "[query]"))
    line = _one_line_error(*_cli(capsys, ["run", f])[::2])
    assert "query: expected [[query]] tables" in line and "got one [query] table" in line


def test_scene_given_to_the_wrong_command(capsys):
    """A controller scene given to 'distkin run' (and a run scene to 'distkin control')
    used to list six unknown fields; it is now named for what it is, with the command."""
    line = _one_line_error(*_cli(capsys, ["run", EXAMPLES / "control_octo.toml"])[::2])
    assert "got a controller scene" in line and "distkin control --sim --scene" in line
    line = _one_line_error(*_cli(capsys, ["control", "--sim", "--scene",
                                          EXAMPLES / "rss_octopod.toml"])[::2])
    assert "got a distkin run scene" in line and "'distkin run'" in line


def test_forward_kinematics_report_states_units(tmp_path, capsys):
    """Every number of the rss forward-kinematics text carries a unit or says it is
    dimensionless (the closure Jacobian's σmin and condition had neither).  The angles
    are the IK of the guess itself, so the pose found is the guess (0, 0, 300) mm."""
    from distkin.mechanisms import preset
    q, ok = preset("octopod").inverse_kinematics([0, 0, 0.3, 0, 0, 0])
    angles = ", ".join(f"{v:.12f}" for v in np.degrees(q))
    f = tmp_path / "s.toml"
    f.write_text(RSS.format(extra="", query="").replace('preset = "octo"', 'preset = "octopod"')
                 .replace('type = "inverse_kinematics"', 'type = "forward_kinematics"')
                 + f"angles = [{angles}]\nguess = [0, 0, 300, 0, 0, 0]\n")
    code, out, err = _cli(capsys, ["run", f, "--json", "-"])
    assert code == 0 and ok.all()
    pose = json.loads(out)["queries"][0]["result"]["pose"]
    assert np.allclose(pose, [0, 0, 0.3, 0, 0, 0], atol=1e-12)     # m, rad (SI in JSON)
    assert "closure Jacobian (angular columns x length scale, dimensionless)" in err


@pytest.mark.parametrize("old, new, field", [
    ('legs = ["19.8"', 'legs = ["1e400"', "query[0].legs[0]"),
    ('legs = ["19.8"', 'legs = ["2**2000"', "query[0].legs[0]"),
    ('[6, "sqrt(108)", 0]', '[6, "sqrt(10**700)", 0]', "mechanism.base[1][1]"),
])
def test_exact_values_beyond_float64_are_bad_input(tmp_path, capsys, old, new, field):
    """'1e400' is within the 4096-bit bound of an exact value but not a float64: it
    used to end as 'internal failure: OverflowError' (exit 1)."""
    f = tmp_path / "s.toml"
    f.write_text(OCTA.replace('dps = "x"', "").replace(old, new, 1))
    line = _one_line_error(*_cli(capsys, ["run", f])[::2])
    assert f"{field}: expected a number within the float64 range" in line


def test_rss_and_legs_values_beyond_float64_name_their_field():
    text = (EXAMPLES / "gough_stewart_6ups.toml").read_text(encoding="utf-8")
    cases = [(text.replace("range = [350, 550]", 'range = [350, "1e400"]', 1),
              "mechanism.leg[0].range[1]"),
             (text.replace("mass = 10", 'mass = "1e400"', 1), "mechanism.mass"),
             (RSS.format(extra='l1 = "1e400"', query="poses = [[0, 0, 300, 0, 0, 0]]"),
              "mechanism.l1"),
             (RSS.format(extra="", query='poses = [[0, 0, "1e400", 0, 0, 0]]'),
              "query[0].poses[0][2]")]
    for scene, field in cases:
        with pytest.raises(InputError, match="float64 range") as exc:
            loads_scene(scene)
        assert exc.value.field == field
    from distkin.exact import parse_exact
    with pytest.raises(InputError, match="float64 range"):
        float(parse_exact("1e400"))
    assert float(parse_exact("1e308")) == 1e308        # the largest decade still fits


def test_debug_after_the_subcommand(tmp_path, capsys, monkeypatch):
    """'run with --debug for the traceback' made users append --debug, which argparse
    refused ('unrecognized arguments'); it now works after the subcommand too."""
    from distkin.app import cli
    f = tmp_path / "s.toml"
    f.write_text(POINTS)

    def broken(*args, **kwargs):
        raise RuntimeError("a bug")
    monkeypatch.setattr(cli, "run_scene", broken)
    code, _, err = _cli(capsys, ["run", f])
    assert code == 1 and "internal failure: RuntimeError: a bug" in err
    assert "Traceback" not in err and "--debug" in err
    for args in (["run", f, "--debug"], ["--debug", "run", f]):
        code, _, err = _cli(capsys, args)
        assert code == 1 and "Traceback" in err and "RuntimeError: a bug" in err


def test_poses_in_the_wrong_unit_get_a_pointer(tmp_path, capsys):
    """z = 0.3 written in a mm scene (metres meant): every leg fails and the report used
    to say only 'NOT reachable'; it now shows the home pose in the scene's units, 300 mm
    for the Octo (z0 = 0.30 m, docs/design.md §5), next to the [units] in force."""
    f = tmp_path / "s.toml"
    f.write_text(RSS.format(extra="", query="poses = [[0, 0, 0.3, 0, 0, 0]]"))
    code, out, _ = _cli(capsys, ["run", f])
    assert code == 0 and "NOT reachable (legs [1, 2, 3, 4, 5, 6, 7, 8])" in out
    assert "home is (0, 0, 300) mm, (0, 0, 0) deg" in out and 'length = "mm"' in out
    f.write_text(RSS.format(extra="", query="poses = [[0, 0, 300, 0, 0, 0]]"))
    code, out, _ = _cli(capsys, ["run", f])
    assert code == 0 and "-> reachable" in out and "home is" not in out


def _import_fails_or_is_local(name, folder):
    """Whether ``import name`` in a fresh interpreter working in ``folder`` fails or
    loads ``folder``'s file instead of the real module."""
    import subprocess
    import sys
    res = subprocess.run([sys.executable, "-c", f"import {name}; print({name})"],
                         cwd=folder, capture_output=True, text=True)
    return res.returncode != 0 or str(folder) in res.stdout


@pytest.mark.parametrize("stem", ["class"])
def test_codegen_warns_of_module_names_import_cannot_use(tmp_path, capsys, stem):
    """A keyword cannot be imported (checked in a fresh interpreter with the file in its
    working directory); the warning names a module name that works.  A name that hides
    a module (json, numpy) is refused: tests/app/test_codegen_output.py."""
    from distkin.app.codegen_command import _module_name
    out = tmp_path / f"{stem}.py"
    code, _, err = _cli(capsys, ["codegen", EXAMPLES / "rss_octopod.toml", "-o", out])
    assert code == 0 and out.is_file()
    good = _module_name(stem)
    assert f"--output: '{stem}' is" in err and f"{good}.py" in err
    assert _import_fails_or_is_local(stem, tmp_path)
    out.rename(tmp_path / f"{good}.py")
    if stem != "class":                            # the real module is back
        assert not _import_fails_or_is_local(stem, tmp_path)
    import importlib.util
    spec = importlib.util.spec_from_file_location(good, tmp_path / f"{good}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert mod.L == 8                              # the Octopod's eight legs


def test_codegen_refuses_exactly_when_a_module_is_hidden(tmp_path, capsys):
    """A module built into this interpreter (``time``) is found before the path and is
    written; ``math`` is an extension module here, hidden by a math.py: refused (exit 2,
    QA 10: it only warned)."""
    for name in ("time", "math", "my_kernels"):
        capsys.readouterr()
        code, _, err = _cli(capsys, ["codegen", EXAMPLES / "rss_octopod.toml", "-o",
                                     tmp_path / f"{name}.py"])
        # hidden: a real module of that name exists and an empty name.py replaces it
        (tmp_path / f"{name}.py").write_text("", encoding="utf-8")
        local = _import_fails_or_is_local(name, tmp_path)
        (tmp_path / f"{name}.py").unlink()
        hidden = local and not _import_fails_or_is_local(name, tmp_path)
        assert (code == 2) == hidden and "warning" not in err, name


def test_a_refused_scene_still_gives_its_json(tmp_path, capsys):
    """A field refused at load (here query[0].dps = "x") stops the run before any work;
    with ``--json -`` stdout was empty while a query's own error gave a document, so a
    pipeline got nothing to parse (QA R 9).  Now the document comes out, no query run and
    the one-line reason (the same as on stderr) in ``error``; a file named by --json
    gets it too, and an existing non-JSON file is never overwritten."""
    scene = tmp_path / "s.toml"
    scene.write_text(OCTA, encoding="utf-8")
    code = main(["run", str(scene), "--json", "-", "--no-progress"])
    out, err = capsys.readouterr()
    assert code == 2 and err.count("\n") == 1 and "query[0].dps" in err
    doc = json.loads(out)
    assert doc["queries"] == [] and doc["scene"] == str(scene) and "distkin" in doc
    assert doc["error"]["kind"] == "input" and doc["error"]["message"] in err
    target = tmp_path / "out.json"
    assert main(["run", str(scene), "--json", str(target), "--no-progress"]) == 2
    assert json.loads(target.read_text())["error"] == doc["error"]
    keep = tmp_path / "legs.csv"
    keep.write_text("1,2,3\n", encoding="utf-8")
    assert main(["run", str(scene), "--json", str(keep), "--no-progress"]) == 2
    assert keep.read_text() == "1,2,3\n"


def test_output_paths_are_named_as_typed(tmp_path, capsys):
    """An empty --json was "the directory ''" and ``-o t/`` was shown as 't' (QA R 10)."""
    scene = tmp_path / "s.toml"
    scene.write_text(OCTA.replace('method = "precise"\ndps = "x"\n', ''), encoding="utf-8")
    with pytest.raises(InputError, match="got an empty string"):
        check_output_path("", "--json")
    (tmp_path / "t").mkdir()
    assert main(["codegen", str(scene), "-o", str(tmp_path / "t") + "/"]) == 2
    err = capsys.readouterr().err
    assert f"got '{tmp_path / 't'}/'" in err


def test_poses_that_differ_in_their_seventh_digit_read_apart(tmp_path, capsys):
    """QA 2026-11-29: z = 300.0004, 300.00045 and 300.0004549 mm all read 300 (6
    significant digits), one reachable and one not in QA's scene, and nobody could tell
    the rows apart; each pose now reads as the scene wrote it."""
    f = tmp_path / "s.toml"
    zs = ("300.0004", "300.00045", "300.0004549", "-12.5e-3")
    f.write_text(RSS.format(extra="", query="poses = [" + ", ".join(
        f"[0, 0, {z}, 0, 0, 0]" for z in zs) + "]"))
    code, out, _ = _cli(capsys, ["run", f])
    assert code == 0
    for i, z in enumerate(zs):
        assert f"pose {i}: (0, 0, {float(z)!r}) mm, (0, 0, 0) deg" in out
