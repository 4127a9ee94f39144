"""The scene modules of ``distkin codegen`` that several test files read (the fixture
``mods`` of this folder's conftest): the example scenes written through the CLI into a
fresh cache, batched and scalar flavours (``--flavour both``)."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
EX = ROOT / "examples"
#: the scenes and the key of the module each one is written to
SCENES = {"gd": "octahedral_griffis_duffy.toml", "cm": "points_banana.toml",
          "op": "rss_octopod.toml", "gs": "gough_stewart_6ups.toml",
          "ru": "rus8_device.toml"}


def load_module(path):
    """A generated module from its file (not added to ``sys.modules``)."""
    spec = importlib.util.spec_from_file_location(path.stem, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def write_modules(tmp):
    """{key: module} of :data:`SCENES`, written by ``python -m distkin codegen`` into the
    folder ``tmp`` (its own fresh cache)."""
    env = dict(os.environ, DISTKIN_CACHE=str(tmp / "cache"),
               PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    out = {}
    for key, scene in SCENES.items():
        path = tmp / f"{key}_kernels.py"
        r = subprocess.run([sys.executable, "-m", "distkin", "codegen", str(EX / scene), "-o",
                            str(path), "--flavour", "both"], capture_output=True, text=True,
                           env=env, timeout=600)
        assert r.returncode == 0, (scene, r.stderr)
        out[key] = load_module(path)
    return out
