"""Outputs never land on the package, on an input, on each other or in a chunk store,
and every such output is refused before any work with one line (exit 2).

QA found: ``distkin codegen S -o <package>/errors.py`` replaced a source file (exit 0);
``distkin demo --json <package>/scenes/certify_hunt.toml`` replaced the built-in scene it
read; ``run --json same --plots same`` ran everything, then lost the JSON;
``sweep --store s --json s/sweep.json`` replaced the store's metadata (the next resume
then said "key None") and ``--json s/chunk_00000.npz`` a chunk; ``--plots`` naming a
file or an unwritable folder ran to the end, then warned; ``--plots ''`` was ignored.
Also the usage errors (one line, not the usage), no command, Ctrl-C (130) and a sweep
of a scene with no chunked query (a warning).

Every test that would write into a package writes into a fake one under ``tmp_path``
(``output_paths.PACKAGE`` monkeypatched): the real checkout is never at risk, even
with the old code.  ``run_scene`` is replaced where the queries themselves do not
matter, so "before any work" is checked by it never being called.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from distkin.app import cli, output_paths
from distkin.app.cli import main
from distkin.app.output_paths import check_output_dir, check_output_path
from distkin.errors import InputError
from distkin.runstore import check_store

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

POINTS = """
[mechanism]
kind = "points"
points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]

[[query]]
type = "cayley_menger"
determinants = ["D(1,2,3,4)"]
"""


@pytest.fixture
def calls(monkeypatch):
    """Replace :func:`cli.run_scene` by a stub recording its calls (no work done)."""
    seen = []

    def fake(scene, **kw):
        seen.append(scene.path)
        return [], [], 0
    monkeypatch.setattr(cli, "run_scene", fake)
    return seen


@pytest.fixture
def scene(tmp_path):
    p = tmp_path / "s.toml"
    p.write_text(POINTS)
    return p


def _one_line(capsys, code, field, *parts):
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, (code, err)
    assert lines[0].startswith(f"distkin: error: {field}: expected "), lines[0]
    for part in parts:
        assert part in lines[0], lines[0]
    return out


# -- 1. the installed package ------------------------------------------------------------

@pytest.fixture
def fake_package(tmp_path, monkeypatch):
    pkg = tmp_path / "site" / "distkin"
    (pkg / "scenes").mkdir(parents=True)
    (pkg / "errors.py").write_text("# source\n")
    monkeypatch.setattr(output_paths, "PACKAGE", pkg)   # fails on the old code: no PACKAGE
    return pkg


def test_codegen_into_the_package_is_refused(tmp_path, monkeypatch, capsys, scene,
                                             fake_package):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "link").symlink_to(fake_package)
    for out in (fake_package / "errors.py", fake_package / "new_kernel.py",
                fake_package / "scenes" / ".." / "errors.py", "site/distkin/errors.py",
                "link/errors.py", tmp_path / "site" / "x" / ".." / "distkin" / "sub" / "k.py"):
        code = main(["codegen", str(scene), "-o", str(out)])
        _one_line(capsys, code, "--output", "outside the installed distkin package",
                  str(fake_package))
    assert (fake_package / "errors.py").read_text() == "# source\n"
    assert not (fake_package / "new_kernel.py").exists() and not (fake_package / "sub").exists()


@pytest.mark.parametrize("option", ["--json", "--plots", "--store"])
def test_run_outputs_into_the_package_are_refused(tmp_path, capsys, scene, fake_package,
                                                  calls, option):
    command = "sweep" if option == "--store" else "run"
    target = fake_package / ("r.json" if option == "--json" else "out")
    code = main([command, str(scene), option, str(target)])
    _one_line(capsys, code, option, "outside the installed distkin package")
    assert calls == [] and not target.exists()


@pytest.mark.parametrize("field", ["--log", "--port-file"])
def test_log_and_port_file_into_the_package_are_refused(fake_package, field):
    with pytest.raises(InputError, match="outside the installed distkin package") as exc:
        check_output_path(fake_package / "run.log", field)
    assert exc.value.field == field and not (fake_package / "run.log").exists()


def test_the_real_package_root_is_the_distkin_folder():
    import distkin
    assert output_paths.PACKAGE == Path(distkin.__file__).resolve().parent
    assert output_paths.GENERATED.parent == output_paths.PACKAGE


# -- 2. demo never over a built-in scene --------------------------------------------------

def test_demo_json_onto_a_builtin_scene_is_refused(tmp_path, monkeypatch, capsys, calls):
    """The inputs rule on its own: the package rule is pointed elsewhere, and the built-in
    scenes are a copy under tmp_path."""
    from importlib import resources
    real = resources.files("distkin.scenes")
    copy = tmp_path / "scenes"
    copy.mkdir()
    for name in cli.DEMO_SCENES:
        (copy / name).write_text(real.joinpath(name).read_text(encoding="utf-8"))
    monkeypatch.setattr(output_paths, "PACKAGE", tmp_path / "elsewhere", raising=False)
    monkeypatch.setattr(cli.resources, "files",
                        lambda pkg: copy if pkg == "distkin.scenes" else real)
    target = copy / "certify_hunt.toml"
    before = target.read_bytes()
    code = main(["demo", "--json", str(target)])
    _one_line(capsys, code, "--json", "other than the input file", "overwrite the input")
    assert target.read_bytes() == before and calls == []


# -- 3. outputs apart from each other and from the store ----------------------------------

@pytest.mark.parametrize("json_, plots, field", [
    ("same", "same", "--json"),               # QA: ran everything, then lost the JSON
    ("p/q0_jacobian.png", "p", "--json"),     # a name a plot may take
    ("j", "j/plots", "--plots"),
])
def test_json_and_plots_apart(tmp_path, monkeypatch, capsys, scene, calls, json_, plots,
                              field):
    monkeypatch.chdir(tmp_path)
    code = main(["run", str(scene), "--json", json_, "--plots", plots])
    _one_line(capsys, code, field)
    assert calls == [] and not Path(json_).is_file()


def test_json_beside_plots_still_works(tmp_path, capsys, scene):
    assert main(["run", str(scene), "--json", str(tmp_path / "p.json"),
                 "--plots", str(tmp_path / "p")]) == 0
    assert (tmp_path / "p.json").is_file()


def test_json_inside_the_plots_folder_still_works(tmp_path, capsys, scene):
    # a query's files are named q{i}_{type}*: a JSON of another name overwrites nothing
    # (tests/mechanisms/test_rss_scene.py writes --plots DIR --json DIR/out.json)
    assert main(["run", str(scene), "--json", str(tmp_path / "p" / "r.json"),
                 "--plots", str(tmp_path / "p")]) == 0
    assert (tmp_path / "p" / "r.json").is_file()


@pytest.mark.parametrize("inside", ["sweep.json", "chunk_00000.npz", "sub/r.json", "."])
def test_json_inside_the_store_is_refused(tmp_path, capsys, scene, calls, inside):
    store = tmp_path / "s8"
    store.mkdir()
    (store / "sweep.json").write_text('{"key": "k", "code": "c"}')
    code = main(["sweep", str(scene), "--store", str(store), "--json", str(store / inside)])
    _one_line(capsys, code, "--json", "outside the --store chunk store")
    assert calls == [] and (store / "sweep.json").read_text() == '{"key": "k", "code": "c"}'
    assert not (store / "chunk_00000.npz").exists()


def test_plots_inside_the_store_is_refused(tmp_path, capsys, scene, calls):
    code = main(["sweep", str(scene), "--store", str(tmp_path / "s"),
                 "--plots", str(tmp_path / "s" / "plots")])
    _one_line(capsys, code, "--plots", "outside the --store chunk store")
    assert calls == []


def test_json_inside_a_query_store_is_refused(tmp_path, capsys, calls):
    """The store a chunked query names in the scene (relative to it) is read back too."""
    s = tmp_path / "hunt.toml"
    s.write_text((EXAMPLES / "certify_hunt.toml").read_text() + 'store = "st"\n')
    code = main(["run", str(s), "--json", str(tmp_path / "st" / "sweep.json")])
    _one_line(capsys, code, "--json", "outside the query[0].store chunk store")
    assert calls == []


def test_check_apart_two_files():
    from distkin.app.output_paths import check_apart
    with pytest.raises(InputError, match="other than the --json file") as exc:
        check_apart(files=[("--json", "a/r.json"), ("--log", "a/../a/r.json")])
    assert exc.value.field == "--log"
    check_apart(files=[("--json", "-"), ("--log", None), ("--port-file", "p")],
                folders=[("--plots", None)], stores=[("--store", "s")])


def test_a_json_result_as_store_metadata_is_named(tmp_path):
    """QA: a --json document written over sweep.json gave "made for key None"."""
    store = tmp_path / "s"
    store.mkdir()
    (store / "sweep.json").write_text(json.dumps({"distkin": "0", "scene": "h.toml",
                                                  "queries": []}))
    with pytest.raises(InputError) as exc:
        check_store(store, {"grid": 3}, 2)
    msg = exc.value.one_line()
    assert "not a store's metadata" in msg and "--json result" in msg
    assert "key None" not in msg


# -- 4. --plots checked up front ------------------------------------------------------------

def test_plots_unwritable_refused_before_the_run(tmp_path, monkeypatch, capsys, scene,
                                                 calls):
    monkeypatch.chdir(tmp_path)
    Path("hunt.txt").write_text("notes\n")
    for plots, part in (("hunt.txt", "a file of that name exists"),
                        ("hunt.txt/pl", "'hunt.txt' is not a folder"),
                        ("", "got an empty string"), ("  ", "got an empty string")):
        code = main(["run", str(scene), "--plots", plots])
        _one_line(capsys, code, "--plots", part)
    if Path("/proc/self").exists():          # a folder that cannot be made
        code = main(["run", str(scene), "--plots", "/proc/pl"])
        _one_line(capsys, code, "--plots", "expected a folder that can be written")
    assert calls == [] and Path("hunt.txt").read_text() == "notes\n"


def test_plots_refused_for_demo_and_store_empty(tmp_path, capsys, scene, calls):
    code = main(["demo", "--plots", ""])
    _one_line(capsys, code, "--plots", "empty string")
    code = main(["sweep", str(scene), "--store", ""])
    _one_line(capsys, code, "--store", "empty string")
    assert calls == []


def test_check_output_dir_makes_a_writable_folder(tmp_path):
    check_output_dir(tmp_path / "a" / "b", "--plots")
    assert (tmp_path / "a" / "b").is_dir()
    f = tmp_path / "f.toml"
    f.write_text("x")
    with pytest.raises(InputError, match="other than the input file"):
        check_output_dir(f, "--plots", inputs=[f])


# -- 5. usage errors, no command, interrupt, sweep without chunked queries ---------------

@pytest.mark.parametrize("argv, part", [
    (["run", "--frobnicate", "s.toml"], "unrecognized arguments: --frobnicate"),
    (["run"], "the following arguments are required: scene (see distkin run --help)"),
    (["sweep", "s.toml", "--workers", "two"], "argument --workers: invalid int value"),
    (["frobnicate"], "invalid choice"),
])
def test_usage_errors_are_one_line(capsys, argv, part):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    out, err = capsys.readouterr()
    assert exc.value.code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("distkin: error: ") and part in lines[0]
    assert "--help" in lines[0]


def test_no_command_is_one_line_on_stderr(capsys):
    assert main([]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.strip() == ("distkin: error: expected a command (run, demo, sim, control, "
                           "codegen, sweep), got none (see distkin --help)")


def test_help_is_unchanged(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0 and capsys.readouterr().out.startswith("usage: distkin")


@pytest.mark.parametrize("command", ["run", "sweep", "demo"])
def test_interrupt_is_130(monkeypatch, capsys, scene, command):
    def interrupted(*a, **kw):
        raise KeyboardInterrupt
    monkeypatch.setattr(cli, "run_scene", interrupted)
    argv = [command] if command == "demo" else [command, str(scene)]
    assert main(argv) == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1] == "distkin: error: interrupted"
    assert all(line.startswith("distkin: warning:") for line in err[:-1])   # sweep


def test_sweep_without_chunked_query_warns(tmp_path, capsys, scene):
    code = main(["sweep", str(scene), "--workers", "2", "--store", str(tmp_path / "zz")])
    err = capsys.readouterr().err
    assert code == 0
    assert "distkin: warning:" in err and "has no chunked query" in err
    assert main(["run", str(scene)]) == 0
    assert "chunked" not in capsys.readouterr().err
