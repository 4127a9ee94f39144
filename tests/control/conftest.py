"""Fixtures of the control tests (helpers in control_helpers.py)."""

import json

import pytest
from control_helpers import run_cli


@pytest.fixture
def control_run(tmp_path):
    """Run ``distkin control --sim`` on a scene text; returns (proc, summary, prefix)."""

    def _run(text, seconds, faults=None, extra=()):
        scene = tmp_path / "scene.toml"
        scene.write_text(text, encoding="utf-8")
        prefix = tmp_path / "run"
        args = ["control", "--sim", "--scene", scene, "--seconds", seconds, "--log", prefix,
                "--json", "-", "--wall-limit", 60, *extra]
        if faults:
            args += ["--faults", faults]
        proc = run_cli(args, tmp_path)
        assert "Traceback" not in proc.stderr and "Traceback" not in proc.stdout, proc.stderr
        summary = json.loads(proc.stdout) if proc.stdout.strip() else None
        return proc, summary, prefix

    return _run
