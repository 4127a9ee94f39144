"""QA X1 D2: the outputs of ``distkin control`` and ``distkin sim`` must not collide with
each other (``--json run.cycles.csv`` beside ``--log run`` replaced the cycle log with
the summary, exit 0, and the report still listed the log).  Each collision is refused
before anything runs: exit 2, one line ``distkin: error: --json: ...`` (README,
docs/design.md §4: an output never overwrites an input or another output)."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _cli(args, cwd):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1",
               PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run([sys.executable, "-m", "distkin", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd, env=env, timeout=300)


def _refused(proc, field):
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"distkin: error: {field}: expected"), \
        proc.stderr
    assert "Traceback" not in proc.stderr and proc.stdout == ""
    return lines[0]


@pytest.mark.parametrize("json_name", ["run.cycles.csv", "run.events.jsonl",
                                       "run.device.csv", "run.device-events.jsonl"])
def test_json_onto_a_log_file_is_refused_before_the_run(tmp_path, json_name):
    target = tmp_path / json_name
    target.write_text("keep\n", encoding="utf-8")        # an earlier run's log
    proc = _cli(["control", "--sim", "--seconds", 0.3, "--log", "run", "--json", json_name],
                tmp_path)
    line = _refused(proc, "--json")
    assert json_name in line and "--log" in line
    assert target.read_text(encoding="utf-8") == "keep\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == [json_name]   # nothing ran


def test_json_onto_the_plot_is_refused(tmp_path):
    proc = _cli(["control", "--sim", "--seconds", 0.3, "--plots", "pl", "--json",
                 "pl/control.png"], tmp_path)
    assert "--plots" in _refused(proc, "--json")
    assert not (tmp_path / "pl" / "control.png").exists()


def test_json_onto_the_delay_margin_plot_is_refused(tmp_path):
    proc = _cli(["control", "--delay-margin", 1, "--plots", "pl", "--json",
                 "pl/delay_margin.png"], tmp_path)
    assert "--plots" in _refused(proc, "--json")


def test_a_link_to_a_log_file_is_the_same_file(tmp_path):
    (tmp_path / "run.events.jsonl").write_text("keep\n", encoding="utf-8")
    (tmp_path / "summary.json").symlink_to(tmp_path / "run.events.jsonl")
    proc = _cli(["control", "--sim", "--seconds", 0.3, "--log", "run", "--json",
                 "summary.json"], tmp_path)
    _refused(proc, "--json")
    assert (tmp_path / "run.events.jsonl").read_text(encoding="utf-8") == "keep\n"


def test_sim_port_file_onto_its_log_is_refused(tmp_path):
    proc = _cli(["sim", "--port-file", "s.device.csv", "--log", "s", "--seconds", 0.1],
                tmp_path)
    assert "--log" in _refused(proc, "--port-file")


@pytest.mark.parametrize("extra", [["--sim", "--seconds", "0.2"], ["--delay-margin", "1"]])
@pytest.mark.parametrize("plots, words", [("", "got an empty string"),
                                          ("FILE", "a file of that name exists")])
def test_control_plots_folder_is_checked_before_the_run(tmp_path, capsys, extra, plots,
                                                        words):
    """QA X4 (noticed by the fix): ``control --plots ''`` was ignored silently, and a
    file given as the plots folder failed only after the run.  Reference: the rule
    ``run`` and ``demo`` follow (output_paths.check_output_dir)."""
    from distkin.app.cli import main
    if plots == "FILE":
        plots = str(tmp_path / "f.txt")
        Path(plots).write_text("keep", encoding="utf-8")
    code = main(["control", *extra, "--plots", plots])
    err = capsys.readouterr().err
    assert code == 2 and "--plots" in err and words in err
    if plots.endswith("f.txt"):
        assert Path(plots).read_text(encoding="utf-8") == "keep"
