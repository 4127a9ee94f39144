"""``distkin codegen SCENE.toml -o MODULE.py``: write an importable kernel module.

The module holds only the kernels that the scene's queries need, derived with the
scene's parameters substituted before differentiation and CSE (docs/design.md §1), and it
imports only ``math`` and ``numpy`` (neither sympy nor distkin).  Derivations go through
the cache (:mod:`.cache`), so a second run of the same scene does no algebra.

Mechanism kinds that can be generated are listed in :data:`CODEGEN_KINDS`
(kind -> ``"module:function(scene, flavours) -> (source, cache_hit)"``).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

from ..errors import InputError

__all__ = ["add_parser", "CODEGEN_KINDS", "scene_module_source"]

def _rss_module(scene, flavours):
    from ..codegen.rss import scene_module
    return scene_module(scene, flavours)


#: mechanism kind -> function(scene, flavours) -> (source text, cache hit)
CODEGEN_KINDS: dict = {
    "rss": _rss_module,
    "legs": _rss_module,          # the same generator, from the leg table
}

_FLAVOURS = {"batched": ("batched",), "scalar": ("scalar",), "both": ("batched", "scalar")}


def scene_module_source(scene, flavour: str = "both"):
    """(source, cache_hit) of the kernel module of a loaded scene."""
    kind = scene.mechanism.kind
    if kind not in CODEGEN_KINDS:
        raise InputError(f"expected a mechanism kind with generated kernels "
                         f"({', '.join(map(repr, CODEGEN_KINDS))}), got {kind!r}",
                         field="mechanism.kind")
    return CODEGEN_KINDS[kind](scene, _FLAVOURS[flavour])


def _module_name(stem: str) -> str:
    """A module name like ``stem``: ``"my-kernels"`` -> ``"my_kernels"``."""
    name = re.sub(r"\W", "_", stem)
    return name if name[:1].isalpha() or name[:1] == "_" else f"kernels_{name}"


def _run(args) -> int:
    from .output_paths import check_output_path, write_text
    from .scene import load_scene
    scene = load_scene(args.scene)
    out = Path(args.output)
    if out.suffix != ".py":
        raise InputError(f"expected an output file ending in .py, got {str(out)!r}",
                         field="--output")
    check_output_path(out, "--output")     # before deriving (seconds for a new table)
    if not out.stem.isidentifier():
        print(f"distkin: warning: --output: {out.stem!r} is not a Python module name, so "
              f"'import' cannot load it (importlib can; {_module_name(out.stem)}.py could be "
              "imported)", file=sys.stderr)
    src, hit = scene_module_source(scene, args.flavour)
    write_text(out, src, "--output")
    names = [line.split("(")[0][4:] for line in src.splitlines() if line.startswith("def ")]
    print(f"wrote {out} ({len(src.splitlines())} lines; kernels: {', '.join(names)}; "
          f"{'from the derivation cache' if hit else 'derived'})", file=sys.stderr)
    return 0


def add_parser(subparsers) -> None:
    """Register ``distkin codegen`` (called by :func:`distkin.app.cli.build_parser`)."""
    p = subparsers.add_parser("codegen", help="write a kernel module for a scene's queries")
    p.add_argument("scene", help="scene TOML file")
    p.add_argument("-o", "--output", required=True, metavar="MODULE.py",
                   help="the module to write")
    p.add_argument("--flavour", choices=sorted(_FLAVOURS), default="both",
                   help="batched numpy kernels, scalar float kernels, or both (default)")
    p.set_defaults(func=_run)
