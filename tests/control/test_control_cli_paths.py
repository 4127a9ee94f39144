"""``distkin control`` output paths: every file ``--log PREFIX`` writes and the ``--plots``
folder are checked before anything starts (exit 2, one line naming the option), and the
summary names every file written (QA 19, 09, 08)."""

from pathlib import Path

import pytest

from control_helpers import robust_scene_text, run_cli


@pytest.mark.parametrize("blocked", ["cycles.csv", "events.jsonl", "device.csv",
                                     "device-events.jsonl"])
def test_each_log_file_blocked_by_a_directory_is_refused_before_the_run(tmp_path, blocked):
    (tmp_path / f"run.{blocked}").mkdir()
    proc = run_cli(["control", "--sim", "--seconds", 0.5, "--log", tmp_path / "run"], tmp_path)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("distkin: error: --log: ")
    assert f"run.{blocked}" in lines[0]
    # nothing ran: no other log file was started
    assert sorted(p.name for p in tmp_path.iterdir()) == [f"run.{blocked}"]


def test_plots_below_a_file_is_refused_before_the_run(tmp_path):
    (tmp_path / "notadir").write_text("x")
    proc = run_cli(["control", "--sim", "--seconds", 1, "--plots", tmp_path / "notadir",
                    "--log", tmp_path / "run"], tmp_path)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("distkin: error: --plots: ")
    assert "expected a folder" in lines[0] and "a file of that name exists" in lines[0]
    assert not (tmp_path / "run.cycles.csv").exists()


def test_summary_and_help_name_every_file_the_log_writes(control_run):
    proc, s, prefix = control_run(robust_scene_text(), 0.3)
    assert proc.returncode == 0, proc.stderr
    want = {"cycles": "cycles.csv", "events": "events.jsonl", "device": "device.csv",
            "device_events": "device-events.jsonl"}
    assert s["log"] == {k: f"{prefix}.{v}" for k, v in want.items()}
    assert all(Path(p).is_file() for p in s["log"].values())
    written = sorted(p.name for p in Path(prefix).parent.iterdir() if p.name.startswith("run."))
    assert written == sorted(f"run.{v}" for v in want.values())
    assert f"{prefix}.device-events.jsonl" in proc.stderr          # the summary's log line
    help_text = run_cli(["control", "--help"], Path(prefix).parent).stdout
    assert "PREFIX.device-events.jsonl" in " ".join(help_text.split())
