"""``distkin codegen SCENE.toml -o MODULE.py``: write an importable kernel module.

The module holds only the kernels that the scene's queries need, derived with the
scene's parameters substituted before differentiation and CSE (docs/design.md §1), and it
imports only ``math`` and ``numpy`` (neither sympy nor distkin).  Derivations go through
the cache (:mod:`.cache`), so a second run of the same scene does no algebra.

Mechanism kinds that can be generated are listed in :data:`CODEGEN_KINDS`
(kind -> ``function(scene, flavours) -> (source, cache_hit, note)``; ``note`` names the
queries that got no kernel, for the stderr line):

* ``rss``, ``legs``: :func:`distkin.codegen.rss.scene_module` (IK, Jacobians, closures);
* ``octahedral``: :mod:`distkin.codegen.octahedral_scene`, the octic of eq. (3) in the
  squared legs with the scene's exact sides substituted, the quadratic parts and the
  feasible interval of s15;
* ``platform66``: the same kernels in the squared m-legs (eq. (8) composed exactly),
  and the map to the squared l-legs;
* ``points``: :mod:`distkin.codegen.cayley_menger_scene`, the scene's requested
  Cayley-Menger determinants as polynomials in the squared distances.
"""

from __future__ import annotations

import keyword
import re
import sys
from pathlib import Path

from ..errors import InputError

__all__ = ["add_parser", "CODEGEN_KINDS", "scene_module_source"]

def _rss_module(scene, flavours):
    from ..codegen.rss import QUERY_KERNELS, scene_module
    _, note = _without_kernel(scene, QUERY_KERNELS)
    return (*scene_module(scene, flavours), note)


#: why a query of an octahedral or 6-6 scene has no kernel
_NO_KERNEL = {
    "delta_transform": "its result is exact algebra (A, det A, mapped legs), not a kernel; "
                       "a kind = \"platform66\" scene composes the map into the octic",
    "singularity": "its tests depend on the pose, not on the legs alone",
    "cayley_menger": "it is a kind = \"points\" query",
    "certify_workspace": "it runs in interval arithmetic on the mechanism's arb kernels "
                         "(distkin.certify), not on float kernels",
}


def _without_kernel(scene, kernels: dict):
    """The scene's query types that get no kernel (sorted), and a note saying why."""
    without = sorted({q.type for q in scene.queries if q.type not in kernels})
    why = "; ".join(f"{t} ({_NO_KERNEL.get(t, 'no generator for it')})" for t in without)
    return without, f"no kernel for the queries: {why}" if without else ""


def _exact_texts(rows):
    return [[str(x) for x in row] for row in rows]


def _check_triangles(mech):
    """Refuse collinear or coincident base or platform points, as the solver does
    (:func:`distkin.octahedral.problem.check_triangle` on the float squared sides; no
    sympy, so a cached module still costs no algebra)."""
    from ..octahedral.problem import check_triangle
    for name, rows, labels in (("base", mech.base, "P1 P2 P3"),
                               ("platform", mech.platform, "P4 P5 P6")):
        P = [[float(x) for x in row] for row in rows]
        check_triangle([sum((p - q) ** 2 for p, q in zip(P[i], P[j]))
                        for i, j in ((0, 1), (0, 2), (1, 2))], labels, f"mechanism.{name}")


def _octahedral_module(scene, flavours):
    from ..codegen.octahedral_scene import KERNELS, QUERY_KERNELS, scene_module
    mech = scene.mechanism
    names = sorted({k for q in scene.queries for k in QUERY_KERNELS.get(q.type, ())},
                   key=KERNELS.index)
    if not names:
        raise InputError(f"expected a query with generated kernels in a kind = "
                         f"{mech.kind!r} scene ({', '.join(QUERY_KERNELS)}), got "
                         f"{[q.type for q in scene.queries]}", field="query")
    _check_triangles(mech)
    _, note = _without_kernel(scene, QUERY_KERNELS)
    key = [mech.kind, _exact_texts(mech.base), _exact_texts(mech.platform)]
    leg_map, constants, note66 = None, {}, ""
    if mech.kind == "platform66":
        names = ["l_squared", *names]
        note66 = ("Offsets delta1..delta6 = OFFSETS.  m-legs with a negative squared l-leg "
                  "(l_squared) belong to no octahedral manipulator: no pose, and "
                  "s15_interval is NaN (batched) or raises ValueError (scalar) there.")
        key.append([str(x) for x in mech.offsets])
        constants["OFFSETS"] = tuple(str(x) for x in mech.offsets)

        def leg_map():
            from ..delta import delta_transform
            return delta_transform(mech, mech.offsets, field="mechanism.offsets").inverse()

    def sides2():
        from ..delta.transform import ROWS, side_lengths
        d = side_lengths(mech.base, mech.platform)
        return {tuple(sorted(r.edge)): x ** 2 for r, x in zip(ROWS, d)}

    notes = "\n\n".join(t for t in (note66, note) if t)
    src, hit = scene_module(key, sides2, names, flavours, leg_map=leg_map,
                            scene_name=Path(scene.path).name, notes=notes,
                            constants=constants, length_unit=scene.units.length)
    return src, hit, note


def _points_module(scene, flavours):
    from ..codegen.cayley_menger_scene import scene_module
    dets = {}
    for q in scene.queries:
        if q.type == "cayley_menger":
            for name, (rows, cols) in zip(q.params.determinants, q.params.labels):
                dets.setdefault(name, (name, tuple(rows), tuple(cols)))
    if not dets:
        raise InputError(f"expected a cayley_menger query in a 'points' scene (its kernels "
                         f"are the requested determinants), got "
                         f"{[q.type for q in scene.queries]}", field="query")
    _, note = _without_kernel(scene, {"cayley_menger": ()})
    src, hit = scene_module(tuple(dets.values()), flavours, scene_name=Path(scene.path).name,
                            length_unit=scene.units.length)
    return src, hit, note


#: mechanism kind -> function(scene, flavours) -> (source text, cache hit, note)
CODEGEN_KINDS: dict = {
    "rss": _rss_module,
    "legs": _rss_module,          # the same generator, from the leg table
    "octahedral": _octahedral_module,
    "platform66": _octahedral_module,   # the same kernels in the m-legs (eq. (8))
    "points": _points_module,
}

_FLAVOURS = {"batched": ("batched",), "scalar": ("scalar",), "both": ("batched", "scalar")}


def scene_module_source(scene, flavour: str = "both"):
    """(source, cache_hit, note) of the kernel module of a loaded scene (``note``: the
    queries without a kernel, or "")."""
    kind = scene.mechanism.kind
    if kind not in CODEGEN_KINDS:
        raise InputError(f"expected a mechanism kind with generated kernels "
                         f"({', '.join(map(repr, CODEGEN_KINDS))}), got {kind!r}",
                         field="mechanism.kind")
    return CODEGEN_KINDS[kind](scene, _FLAVOURS[flavour])


def _module_name(stem: str) -> str:
    """A module name like ``stem``: ``"my-kernels"`` -> ``"my_kernels"``, ``"class"``
    -> ``"class_"``, ``"json"`` -> ``"json_kernels"``."""
    name = re.sub(r"\W", "_", stem)
    name = name if name[:1].isalpha() or name[:1] == "_" else f"kernels_{name}"
    if keyword.iskeyword(name):
        return f"{name}_"
    return f"{name}_kernels" if _shadows(name) else name


def _shadows(name: str) -> bool:
    """Whether a module ``name`` would hide a module the kernels (or their users) import:
    the standard library's, numpy, mpmath, flint, sympy, scipy or distkin."""
    return ((name in sys.stdlib_module_names and name not in sys.builtin_module_names)
            or name in _IMPORTED)          # built-in modules are found before the path


_IMPORTED = {"numpy", "mpmath", "flint", "sympy", "scipy", "distkin", "numba"}


def _module_warning(stem: str) -> str | None:
    """Why a file ``stem``.py cannot serve as the module it is meant to be, or None."""
    if not stem.isidentifier():
        return (f"{stem!r} is not a Python module name, so 'import' cannot load it "
                f"(importlib can; {_module_name(stem)}.py could be imported)")
    if keyword.iskeyword(stem):
        return (f"{stem!r} is a Python keyword, so 'import {stem}' is a syntax error "
                f"(importlib can load it; {_module_name(stem)}.py could be imported)")
    if _shadows(stem):
        return (f"{stem!r} is also the name of a module the kernels or Python itself import,"
                f" so a {stem}.py on the path hides that module from every import "
                f"(hint: {_module_name(stem)}.py)")
    return None


def _run(args) -> int:
    from .output_paths import check_output_path, write_text
    from .scene import input_files, load_scene
    scene = load_scene(args.scene)
    out = Path(args.output)
    if out.suffix != ".py":
        raise InputError(f"expected an output file ending in .py, got {args.output!r}",
                         field="--output")
    # before deriving (seconds for a new table), and never over the scene or its CSV
    check_output_path(out, "--output", inputs=input_files(scene))
    warning = _module_warning(out.stem)
    if warning:
        print(f"distkin: warning: --output: {warning}", file=sys.stderr)
    src, hit, note = scene_module_source(scene, args.flavour)
    write_text(out, src, "--output")
    names = [line.split("(")[0][4:] for line in src.splitlines() if line.startswith("def ")]
    print(f"wrote {out} ({len(src.splitlines())} lines; kernels: {', '.join(names)}; "
          f"{'from the derivation cache' if hit else 'derived'})"
          + (f"; {note}" if note else ""), file=sys.stderr)
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
