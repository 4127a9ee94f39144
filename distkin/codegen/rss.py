"""Deriving the kernels of RSS mechanisms (sympy, :mod:`.emit`): the code generator's side.

For a mechanism, the symbolic kernels of :mod:`distkin.mechanisms.symbolic` (with its
parameters substituted before differentiation) go through :mod:`.emit` in the flavours
described in :mod:`distkin.mechanisms.kernels`, which loads them (the committed preset
modules, or :func:`derived_module` for any other geometry).  ``python -m
distkin.codegen`` writes the presets' modules (:mod:`.registry`); ``distkin codegen``
writes a scene's (:func:`scene_module`).
"""

from __future__ import annotations

import time
from pathlib import Path

from ..mechanisms.kernel_names import (_SUFFIX, ARB_KERNELS, FLAVOURS, KERNELS, LOOP_KERNELS,
                                       RANGE_KERNEL)

__all__ = ["module_text", "derived_module", "scene_module", "derivation_profile",
           "QUERY_KERNELS", "generate_preset", "generate_preset_arb"]

#: rows per slice of the batched kernels (temporaries of 32 KiB stay in cache)
CHUNK = 4096
GENERATOR = "distkin.codegen.rss (derivation: derivations/rss_model.py)"

_DOCS = {
    "ik": ("Closed-form IK (Kühne et al., Sec. II-C; distkin.mechanisms.symbolic).\n\n"
           "pose: (x, y, z) m, (rx, ry, rz) rad, R = Rz Ry Rx.  Returns the L crank\n"
           "angles (rad, 0 = horizontal); finite even where a leg cannot close (see reach)."),
    "reach": ("Reach margins rho^2 - C^2 (m^2) of A cos q + B sin q = C, one per leg;\n"
              "a leg closes iff its margin is >= 0."),
    "jacobian": ("J = Jq^-1 Jx (eqs. (1)-(2)), L x 6: qdot = J (v, omega), v in m/s,\n"
                 "omega in rad/s (base frame)."),
    "jq_jx": ("[Jq_ii, Jx_i] per leg, L x 7 (eq. (1): Jq qdot = Jx (v, omega)); Jq is\n"
              "diagonal, Jq_ii = dPhi_i/dq_i, Jx = -dPhi/d(v, omega)."),
    "closure": ("[Phi_i, dPhi_i/d(v, omega)] per leg, L x 7, for forward kinematics.\n"
                "Phi_i = (|P_i - D_i(q_i)|^2 - l3^2) / (2 l3) in m (about the length error)."),
    "ranges": ("Range margins rho^2 (cos(q - m) - cos w) (m^2) of the revolute legs whose\n"
               "range [qmin, qmax] is not the full turn (m, w its middle and half-width):\n"
               "> 0 iff the crank angle q of the IK's branch is inside the range mod 2 pi."),
}

#: the docstrings of a table of prismatic legs (SPS, UPS; distkin.mechanisms.symbolic)
_DOCS_PRISMATIC = {
    "ik": ("Closed-form IK of prismatic legs (distkin.mechanisms.symbolic).\n\n"
           "pose: (x, y, z) m, (rx, ry, rz) rad, R = Rz Ry Rx.  Returns the L leg\n"
           "lengths q_i = |P_i - B_i| (m)."),
    "reach": ("Stroke margins, one per leg (m^2): (q - qmin)(qmax - q) of the leg length q\n"
              "for a leg with a stroke range, q^2 for one without; a leg closes iff its\n"
              "margin is >= 0."),
    "jacobian": ("J = Jq^-1 Jx (eqs. (1)-(2)), L x 6: qdot = J (v, omega), qdot in m/s (leg\n"
                 "length rates), v in m/s, omega in rad/s (base frame); row i is the\n"
                 "normalised Plücker line of leg i (Rojas et al., eq. (5))."),
    "jq_jx": ("[Jq_ii, Jx_i] per leg, L x 7 (eq. (1): Jq qdot = Jx (v, omega)); Jq is\n"
              "diagonal, Jq_ii = dPhi_i/dq_i = -1, Jx = -dPhi/d(v, omega)."),
    "closure": ("[Phi_i, dPhi_i/d(v, omega)] per leg, L x 7, for forward kinematics.\n"
                "Phi_i = (|P_i - B_i|^2 - q_i^2) / (2 q_i) in m (about the length error),\n"
                "q_i the leg length (m)."),
    "ranges": "(none: a prismatic leg's stroke is in its reach margin)",
}


def _docs(desc, ranged=()) -> dict:
    """kernel name -> docstring for the leg table of ``desc``: revolute legs
    (:data:`_DOCS`), prismatic legs (:data:`_DOCS_PRISMATIC`), or, for a table of both,
    each with the legs it holds for (0-based, the rows of ``LEGS``); ``ranged``, the
    revolute legs whose declared range is in their reach margin (:func:`_reach_in_ranges`),
    named in the reach's."""
    docs = _table_docs(desc)
    if ranged:
        docs = dict(docs, reach=docs["reach"] + _RANGED_REACH.format(legs=list(ranged)))
    return docs


#: the reach docstring's paragraph on the revolute ranges in it (a scene module's)
_RANGED_REACH = (
    "\n\nRevolute legs {legs} (0-based rows of LEGS) declare a joint range [qmin, qmax]:\n"
    "their margin is the smaller of rho^2 - C^2 and the range margin\n"
    "rho^2 (cos(q - m) - cos w) (m^2; m, w the range's middle and half-width, q the\n"
    "crank angle of ik's branch), so it is >= 0 iff the leg closes with q in its\n"
    "range modulo 2 pi (distkin's inverse_kinematics 'valid').")


def _table_docs(desc) -> dict:
    """:func:`_docs` without the ranges."""
    prismatic = [i for i, leg in enumerate(desc.leg_table) if leg.prismatic]
    if not prismatic:
        return _DOCS
    if len(prismatic) == desc.L:
        return _DOCS_PRISMATIC
    revolute = [i for i in range(desc.L) if i not in prismatic]
    head = {"ik": "IK per leg: crank angles (rad) or leg lengths (m).",
            "reach": "Reach margins per leg (m^2).",
            "jacobian": "J = Jq^-1 Jx (eqs. (1)-(2)), L x 6, per leg as below.",
            "jq_jx": "[Jq_ii, Jx_i] per leg, L x 7, per leg as below.",
            "closure": "[Phi_i, dPhi_i/d(v, omega)] per leg, L x 7, per leg as below.",
            "ranges": "Range margins of the revolute legs with a range (m^2)."}
    return {n: (f"{head[n]}\n\nRevolute legs {revolute} (0-based rows of LEGS):\n{_DOCS[n]}"
                f"\n\nPrismatic legs {prismatic}:\n{_DOCS_PRISMATIC[n]}") for n in _DOCS}


#: the modules whose import closure keys the derivation cache (every distkin file they
#: import, transitively, and the toolchain's versions: :func:`~distkin.sourcecache.closure_text`;
#: a hand-kept file list missed mechanisms/kernel_names.py and served stale modules, QA 6)
_MODEL_MODULES = ("distkin.codegen.rss",)

#: scene query type -> the kernels it needs ("model only what a scene requires")
QUERY_KERNELS = {
    "inverse_kinematics": ("ik", "reach"),
    "jacobian": ("jacobian",),
    "forward_kinematics": ("closure",),
}


def _expressions(mech, names, exact=False):
    from ..mechanisms.symbolic import model_expressions
    me = model_expressions(mech, exact)
    return me, {n: me.get(n) for n in names}


def _reach_in_ranges(me, reach, ranged):
    """The reach margins (L, 1) with the declared range of each revolute leg of
    ``ranged`` (``me.range_legs()``) in it: ``min(rho^2 - C^2, rho^2 (cos(q - m) - cos w))``
    (m^2; the ``ranges`` kernel's row, :class:`~distkin.mechanisms.symbolic.ModelExprs`),
    >= 0 iff the leg closes with its crank angle in the range modulo 2 pi, as a prismatic
    leg's margin holds its stroke (a scene module's reach; QA: it held the stroke but
    not a crank's range).  The package's own ``reach`` kernels keep rho^2 - C^2, the IK
    equation's margin, which its callers combine with the ranges themselves
    (:meth:`~distkin.mechanisms.kinematics.KernelMethods._valid`)."""
    import sympy as sp
    rows = me.get("ranges")
    out = sp.Matrix(reach)
    for r, i in enumerate(ranged):
        out[i, 0] = sp.Min(reach[i, 0], rows[r, 0], evaluate=False)
    return out


def _input_units(L, pris) -> dict:
    """The units of the kernels' inputs, in words ({input name: words}; a checked scalar
    kernel names them when an entry is not a number): the pose in SI, ``q`` the crank
    angles (rad) and/or the prismatic legs' lengths (m) of the table."""
    q = ("leg lengths in m" if len(pris) == L else "crank angles in rad" if not pris
         else f"crank angles in rad, the prismatic legs {list(pris)} lengths in m")
    return {"pose": "x, y, z in m; rx, ry, rz in rad", "q": q}


def _kernel_list(desc, exprs, flavours, checked=False, ranged=()):
    import sympy as sp
    from ..mechanisms.symbolic import POSE, q_symbols
    from .emit import Kernel
    L, docs = desc.L, _docs(desc, ranged if checked else ())
    pris = tuple(i for i, leg in enumerate(desc.leg_table) if leg.prismatic)
    out = []
    # the batched flavour brings the loop twins of LOOP_KERNELS (emit: "loop")
    flavours = list(flavours) + (["loop"] if "batched" in flavours else [])
    for flavour in flavours:
        for n, M in exprs.items():
            if flavour == "loop" and n not in LOOP_KERNELS:
                continue
            if n == "closure":
                inputs = (("q", tuple(q_symbols(L))), ("pose", tuple(POSE)))
            else:
                inputs = (("pose", tuple(POSE)),)
            output = list(M) if M.shape[1] == 1 else M
            if M.shape[1] == 1:
                output = sp.Matrix(output).T.tolist()[0]
            name = n + _SUFFIX[flavour]
            # checked: the scene modules' inputs as float64 of the expected shape
            # (.checks); not the internal modules, whose scalar forms numba compiles.
            # A closure's prismatic lengths must be > 0 (it divides by them; QA)
            extra = {"cse_optimizations": None, "chunk": CHUNK, "checked": checked,
                     "units": _input_units(L, pris)}
            if checked and n == "closure" and pris:
                extra["positive"] = {"q": pris}
            out.append(Kernel(name, inputs, output, flavour=flavour, doc=docs[n],
                              extra=extra))
    return out


def module_text(mech, names=KERNELS, flavours=FLAVOURS, *, generator=GENERATOR,
                title=None, timings=None, checked=False) -> str:
    """Source of a kernel module for ``mech`` (only the kernels ``names``), built from its
    leg table (``mech.leg_description()``: the same legs give the same module body).

    Parameters
    ----------
    mech : LegsDescription, RSSDescription or a mechanism on either
    names : sequence of str
        Some of :data:`KERNELS` (and, for the arb flavour of a leg table with revolute
        joint ranges, ``"ranges"``).
    flavours : sequence of str
        "batched" and/or "scalar"; or ("arb",) alone: the arb flavour is derived from
        the exact model of the leg table (``model_expressions(mech, exact=True)``: every
        number its exact binary value, constants exact rationals), what the certified
        tier certifies.
    timings : dict, optional
        Filled with seconds spent per step: ``substitute`` (parameters into the leg
        model), ``differentiate``, ``assemble`` (IK, J = Jq^-1 Jx, ...), ``hash``,
        ``cse_and_print`` (common-subexpression elimination and printing).
    checked : bool
        The kernels convert their inputs to float64 and check their shapes first
        (:mod:`.checks`): the user-facing scene modules (:func:`scene_module`).
    """
    import sympy as sp

    from .emit import module_source, symbolic_hash
    names = [n for n in KERNELS + (RANGE_KERNEL,) if n in names]
    exact = tuple(flavours) == ("arb",)
    if "arb" in flavours and not exact:
        raise ValueError(f"expected the arb flavour alone (it is derived from the exact "
                         f"model), got flavours {tuple(flavours)!r}")
    t_start = time.perf_counter()
    desc = mech.leg_description()
    me, exprs = _expressions(mech, names, exact)
    # a scene module's reach holds the cranks' declared ranges (:func:`_reach_in_ranges`)
    ranged = me.range_legs() if checked and "reach" in exprs else []
    if ranged:
        exprs["reach"] = _reach_in_ranges(me, exprs["reach"], ranged)
    kernels = _kernel_list(desc, exprs, flavours, checked, ranged)
    t0 = time.perf_counter()
    # the symbolic source: the leg closures Phi_i(q, P) with the leg's numbers, P_i(pose),
    # the branches and ranges, from which every kernel is derived deterministically
    # (cheaper to hash than the kernels)
    sig = me.signature()
    source = [e for leg in me.legs() for e in (leg["Phi"], leg["P"])]
    if exact and any(e.atoms(sp.Float) for e in source):
        raise ValueError("expected an exact model (rationals only), got a Float in it")
    h = symbolic_hash(*source, *sorted(names), *([sig] if sig else []),
                      *(["reach within the ranges"] if ranged else []))
    rss = getattr(mech, "kind", None) == "rss"
    types = "/".join(sorted({leg.type for leg in desc.leg_table}))
    what = f"{desc.L} legs ({types}); leg table: LEGS"
    if rss:
        what += f"; parameters (SI): {dict(mech.geometry_key())!r}"
    cite = "Kühne et al., Sec. II-C" if rss else "distkin.mechanisms.legs"
    doc = (f"{title or 'Kernels of a parallel mechanism'} ({cite}).\n\n"
           f"{what}.\n"
           "Batched kernels take (..., 6) poses; scalar ones (suffix _scalar) plain floats.\n"
           "Poses: (x, y, z) m, (rx, ry, rz) rad with R = Rz Ry Rx.  Needs only numpy.")
    if checked:
        doc += ("\nInputs are converted to float64 first; a wrong shape, batch shapes that do "
                "not\nbroadcast together (closure's q and pose) or, in closure, a prismatic "
                "leg's\nlength <= 0 is a ValueError naming it.  The _loop kernels (for numba) "
                "take\nrows: a single pose is pose[None].")
    if exact:
        doc = (f"{title or 'Kernels of a parallel mechanism'} ({cite}), "
               "arb flavour.\n\n"
               f"{what}.\n"
               "Kernels (suffix _arb) take 6 python-flint arb balls (or forward-mode\n"
               "derivative balls) and return enclosures of the exact answers for the\n"
               + ("mechanism of PARAMETERS, each its float's exact binary value (the pair\n"
                  "azimuths' cos and sin exact, those of beta and gamma on the balls;\n"
                  if rss else "mechanism LEGS, each number its exact binary value\n(")
               + "distkin.mechanisms.symbolic, exact model): constants are exact,\n"
               "doubles where they are doubles, else _Z[i] / _Z[j] of exact integers.\n"
               "Poses: (x, y, z) m, (rx, ry, rz) rad with R = Rz Ry Rx.  Needs only\n"
               "python-flint.")
    t1 = time.perf_counter()
    src = module_source(kernels, generator=generator, doc=doc, source_hash=h,
                        constants={"L": desc.L, **({"PARAMETERS": dict(mech.geometry_key())}
                                                   if rss else {}), "LEGS": desc.key(),
                                   "KERNELS": tuple(names), "FLAVOURS": tuple(flavours)})
    if timings is not None:
        timings.update(me.timings)
        timings["assemble"] = t0 - t_start - sum(me.timings.values())
        timings["hash"] = t1 - t0
        timings["cse_and_print"] = time.perf_counter() - t1
    return src


def generate_preset(name):
    """Source of the committed module ``rss_<name>`` of preset ``name``."""
    from ..mechanisms.presets import description, preset_description
    return module_text(preset_description(name), title=f"Preset {name!r}: {description(name)}")


def generate_preset_arb(name):
    """Source of the committed module ``rss_<name>_arb`` of preset ``name``."""
    from ..mechanisms.presets import description, preset_description
    return module_text(preset_description(name), ARB_KERNELS, ("arb",),
                       title=f"Preset {name!r}: {description(name)}")


def _model_source_text() -> str:
    from ..sourcecache import closure_text
    return closure_text(_MODEL_MODULES)


def _prefix(mech) -> str:
    """File-name hint of a cached module: ``rss`` or ``legs`` (the scene's kind)."""
    return "rss" if getattr(mech, "kind", None) == "rss" else "legs"


#: the last derivation of :func:`derived_module`: name, legs, kernels, seconds
LAST_DERIVATION: dict = {}


def derived_module(mech, names, flavours, *, progress=None):
    """The kernel module of a leg table that has no committed module: derived once (only
    ``names`` in ``flavours``) and cached on disk (:mod:`distkin.sourcecache`, keyed by
    the model's source and the leg table), then imported.

    A derivation prints one progress line before and one with its time after (to
    ``progress``, default stderr) and is recorded in :data:`LAST_DERIVATION`; a process
    that finds another deriving the same module (a pool's workers) says it waits, then
    loads that one."""
    import sys
    from ..sourcecache import cached_source, load_module_file, source_key
    desc = mech.leg_description()
    # an RSS mechanism's kernels are derived from its parameters (symbolic), not its table
    params = [repr(mech.geometry_key())] if _prefix(mech) == "rss" else []
    key = source_key(_model_source_text(), repr(desc.key()), *params, names, tuple(flavours))
    out = progress if progress is not None else sys.stderr

    def build():
        print(f"distkin: deriving the {'/'.join(flavours)} kernels {', '.join(names)} of "
              f"{desc.name!r} ({desc.L} legs) with sympy, once ...", file=out, flush=True)
        t0 = time.perf_counter()
        src = module_text(desc, names, flavours)
        dt = time.perf_counter() - t0
        LAST_DERIVATION.clear()
        LAST_DERIVATION.update(name=desc.name, legs=desc.L, kernels=tuple(names),
                               flavours=tuple(flavours), seconds=dt)
        print(f"distkin: derived in {dt:.1f} s (cached; later runs load it)", file=out,
              flush=True)
        return src

    def waiting():               # a parallel worker is deriving it: load its module
        print(f"distkin: waiting for another process deriving the {'/'.join(flavours)} "
              f"kernels of {desc.name!r} ...", file=out, flush=True)

    path, _ = cached_source(_prefix(mech), key, build, on_wait=waiting)
    return load_module_file(path)


def scene_module(scene, flavours=FLAVOURS):
    """(source, cache_hit) of the module with the kernels a scene's queries need.

    Used by ``distkin codegen``; the source goes through the derivation cache.
    """
    from ..sourcecache import cached_source, source_key
    mech = scene.mechanism
    names = sorted({k for q in scene.queries for k in QUERY_KERNELS.get(q.type, ())},
                   key=KERNELS.index)
    if not names:
        from ..errors import InputError
        raise InputError(f"expected a query that needs kernels ({', '.join(QUERY_KERNELS)}), "
                         f"got {[q.type for q in scene.queries]}", field="query")
    # the derivation script covers the revolute legs; a prismatic leg's model is the
    # leg table's own (QA W 12: a 6-UPS module named the RSS script)
    pris = [bool(leg.prismatic) for leg in mech.leg_description().leg_table]
    model = ("derivations/rss_model.py" if not any(pris) else
             "distkin.mechanisms.symbolic, prismatic legs" if all(pris) else
             "derivations/rss_model.py and distkin.mechanisms.symbolic, prismatic legs")
    gen = (f"distkin codegen {Path(scene.path).name} (distkin.codegen.rss; derivation: "
           f"{model})")
    key = source_key(_model_source_text(), repr(mech.leg_description().key()), names,
                     flavours, gen)
    path, hit = cached_source(_prefix(mech), key, lambda: module_text(
        mech, names, flavours, generator=gen, checked=True,
        title=f"Kernels of scene {Path(scene.path).name} ({mech.name})"))
    return path.read_text(encoding="utf-8"), hit


def derivation_profile(mech, names=KERNELS, flavours=FLAVOURS, *, memory=False) -> dict:
    """Seconds per step of deriving ``mech``'s module (see :func:`module_text`), and with
    ``memory=True`` the peak of Python allocations (tracemalloc, bytes; it slows the run,
    so its timings are not representative)."""
    import tracemalloc
    timings = {}
    if memory:
        tracemalloc.start()
    t0 = time.perf_counter()
    src = module_text(mech, names, flavours, timings=timings)
    timings["total"] = time.perf_counter() - t0
    if memory:
        timings["peak_bytes"] = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    timings["source_chars"] = len(src)
    return timings
