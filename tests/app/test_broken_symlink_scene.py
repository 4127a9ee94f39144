"""A scene that is a broken symbolic link says so (QA pkg 9): five examples are links
into distkin/scenes and distkin/control, ``cp -a examples copy`` copies the links, and
``distkin run copy/rss_octopod.toml`` said "got a path that does not exist"."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from distkin.app.cli import main
from distkin.app.control_scene_files import scene_and_inputs
from distkin.app.scene import load_scene
from distkin.errors import InputError

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _copied_link(tmp_path, name, folder="scenes"):
    """What ``cp -a`` makes of the example ``name`` in ``tmp_path/copy``: the relative
    link into the package (written out: in an sdist the examples are files)."""
    (tmp_path / "copy").mkdir()
    dst = tmp_path / "copy" / name
    target = f"../distkin/{folder}/{name}"
    os.symlink(target, dst)
    return dst, target


def test_the_examples_are_such_links_in_a_checkout():
    """The premise (where the examples are links, a git checkout; files in an sdist)."""
    for name, folder in (("rss_octopod.toml", "scenes"), ("control_octo.toml", "control")):
        src = EXAMPLES / name
        if src.is_symlink():
            assert os.readlink(src) == f"../distkin/{folder}/{name}"


def test_run_names_the_broken_link_and_its_target(tmp_path, capsys):
    dst, target = _copied_link(tmp_path, "rss_octopod.toml")
    assert main(["run", str(dst)]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert lines == [
        f"distkin: error: scene: expected a scene file, got {str(dst)!r}, a broken symbolic "
        f"link to {target!r} ({str(dst.parent / target)!r} does not exist) (hint: copy the "
        "files the links point to (cp -L), or run the original)"]


def test_a_missing_file_is_still_a_missing_file(tmp_path):
    with pytest.raises(InputError, match="got a path that does not exist"):
        load_scene(tmp_path / "nothere.toml")


def test_a_controller_scene_link_says_so_too(tmp_path):
    dst, target = _copied_link(tmp_path, "control_octo.toml", "control")
    with pytest.raises(InputError) as info:
        scene_and_inputs(dst)
    assert info.value.field == "--scene"
    assert f"a broken symbolic link to {target!r}" in info.value.message
