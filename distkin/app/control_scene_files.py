"""The controller scene of ``distkin sim`` and ``distkin control`` and the files it is
read from (:mod:`.control_commands`): the scene file, the distkin scene of ``[device]
mechanism`` and the ``legs_csv`` that one names, which no output option may name."""

from __future__ import annotations

import sys
from pathlib import Path

from ..errors import InputError

__all__ = ["builtin_scene", "scene_and_inputs"]


def builtin_scene():
    """The built-in controller scene (:func:`distkin.control.config.builtin_scene`).

    Imported when called: this module is imported to build the command line parser,
    and ``distkin.control`` (numpy, the numba cache) only when a command runs, inside
    :func:`distkin.app.cli.main`'s handling of Ctrl-C (QA X1 D6: an interrupt while
    the parser was being built printed a traceback, exit -2, instead of one line and
    130)."""
    from ..control.config import builtin_scene as scene
    return scene()


def scene_and_inputs(path, outputs=()):
    """The controller scene at ``path`` (the built-in one without), and the files it
    was read from: itself, and the distkin scene of ``[device] mechanism`` with the
    ``legs_csv`` that one names (no output option may name any of them).

    ``outputs``: (field, path) of the command's output files, or (field, path, what)
    with ``what`` the kind in the message ("a folder"), refused as soon as a file they
    name is about to be read (before the device's mechanism is loaded, whose kernels may
    be derived first: the refusal is one line, before any work); the caller checks them
    all again against the returned inputs."""
    from ..control.config import loads_control_scene
    from .output_paths import check_not_input
    from .scene import broken_link_error, input_files, load_scene, toml_text

    def guard(p):
        for fld, out, *what in outputs:
            check_not_input(out, fld, [p], *what)
    if path and not Path(path).is_file():
        p = Path(path)
        broken = broken_link_error(p, "--scene", "a controller scene")
        if broken is not None:
            raise broken
        what = ("a directory" if p.is_dir() else
                "not a regular file: a device, pipe or socket" if p.exists() else
                "no such file")
        raise InputError(f"expected a controller scene file, got {str(path)!r} ({what})",
                         field="--scene")
    if not path:
        return builtin_scene(), []
    read = [Path(path)]
    guard(read[0])

    def mechanism(p):              # the loader of [device] mechanism: notes its files
        s = load_scene(p)
        read.extend(input_files(s))
        return s.mechanism
    text = toml_text(path, "--scene", "controller scene")     # not UTF-8, a TOML error
    if outputs:                    # the device's mechanism scene, before it is loaded
        import tomllib
        try:
            rel = tomllib.loads(text).get("device", {}).get("mechanism")
        except (tomllib.TOMLDecodeError, AttributeError):
            rel = None                  # the scene's loader names what is wrong
        if isinstance(rel, str) and rel:
            guard(Path(path).parent / rel)
    scene = loads_control_scene(text, str(path), mechanism_loader=mechanism)
    for fld, message in scene.warnings:        # loads, but looks wrong: one line each
        print(f"distkin: warning: {fld}: {message}", file=sys.stderr)
    return scene, read
