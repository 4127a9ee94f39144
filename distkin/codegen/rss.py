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

from ..mechanisms.kernel_names import _SUFFIX, ARB_KERNELS, FLAVOURS, KERNELS

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
}

_MODEL_FILES = ("mechanisms/symbolic.py", "codegen/rss.py", "codegen/emit.py")

#: scene query type -> the kernels it needs ("model only what a scene requires")
QUERY_KERNELS = {
    "inverse_kinematics": ("ik", "reach"),
    "jacobian": ("jacobian",),
    "forward_kinematics": ("closure",),
}


def _expressions(mech, names):
    from ..mechanisms.symbolic import model_expressions
    me = model_expressions(mech)
    return me, {n: me.get(n) for n in names}


def _kernel_list(mech, exprs, flavours):
    import sympy as sp
    from ..mechanisms.symbolic import POSE, q_symbols
    from .emit import Kernel
    out = []
    for flavour in flavours:
        for n, M in exprs.items():
            if n == "closure":
                inputs = (("q", tuple(q_symbols(mech.legs))), ("pose", tuple(POSE)))
            else:
                inputs = (("pose", tuple(POSE)),)
            output = list(M) if M.shape[1] == 1 else M
            if M.shape[1] == 1:
                output = sp.Matrix(output).T.tolist()[0]
            name = n + _SUFFIX[flavour]
            out.append(Kernel(name, inputs, output, flavour=flavour, doc=_DOCS[n],
                              extra={"cse_optimizations": None, "chunk": CHUNK}))
    return out


def module_text(mech, names=KERNELS, flavours=FLAVOURS, *, generator=GENERATOR,
                title=None, timings=None) -> str:
    """Source of a kernel module for ``mech`` (only the kernels ``names``).

    Parameters
    ----------
    mech : RSSMechanism
    names : sequence of str
        Some of :data:`KERNELS`.
    flavours : sequence of str
        "batched" and/or "scalar".
    timings : dict, optional
        Filled with seconds spent per step: ``substitute`` (parameters into the leg
        model), ``differentiate``, ``assemble`` (IK, J = Jq^-1 Jx, ...), ``hash``,
        ``cse_and_print`` (common-subexpression elimination and printing).
    """
    from .emit import module_source, symbolic_hash
    names = [n for n in KERNELS if n in names]
    t_start = time.perf_counter()
    me, exprs = _expressions(mech, names)
    kernels = _kernel_list(mech, exprs, flavours)
    t0 = time.perf_counter()
    # the symbolic source: the substituted leg closures Phi_i(q, P) and P_i(pose), from
    # which every kernel is derived deterministically (cheaper to hash than the kernels)
    h = symbolic_hash(*[e for leg in me.legs() for e in (leg["Phi"], leg["P"])],
                      *sorted(names))
    params = {k: v for k, v in mech.geometry_key()}
    doc = (f"{title or 'Kernels of an RSS/RRRS mechanism'} (Kühne et al., Sec. II-C).\n\n"
           f"Parameters (SI): {params!r}.\n"
           "Batched kernels take (..., 6) poses; scalar ones (suffix _scalar) plain floats.\n"
           "Poses: (x, y, z) m, (rx, ry, rz) rad with R = Rz Ry Rx.  Needs only numpy.")
    if tuple(flavours) == ("arb",):
        doc = (f"{title or 'Kernels of an RSS/RRRS mechanism'} (Kühne et al., Sec. II-C), "
               "arb flavour.\n\n"
               f"Parameters (SI): {params!r}.\n"
               "Kernels (suffix _arb) take 6 python-flint arb balls (or forward-mode\n"
               "derivative balls) and return enclosures; constants are the doubles of the\n"
               "fast kernels, exactly.  Poses: (x, y, z) m, (rx, ry, rz) rad with\n"
               "R = Rz Ry Rx.  Needs only python-flint.")
    t1 = time.perf_counter()
    src = module_source(kernels, generator=generator, doc=doc, source_hash=h,
                        constants={"L": mech.legs, "PARAMETERS": params,
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
    here = Path(__file__).resolve().parent
    return "".join((here.parent / f).read_text(encoding="utf-8") for f in _MODEL_FILES)


def derived_module(mech, names, flavours):
    """The kernel module of a geometry that has no committed module: derived once (only
    ``names`` in ``flavours``) and cached on disk (:mod:`.cache`), then imported."""
    from ..sourcecache import cached_source, load_module_file, source_key
    key = source_key(_model_source_text(), repr(mech.geometry_key()), names, tuple(flavours))
    path, _ = cached_source("rss", key, lambda: module_text(mech, names, flavours))
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
    gen = f"distkin codegen {Path(scene.path).name}"
    key = source_key(_model_source_text(), repr(mech.geometry_key()), names, flavours, gen)
    path, hit = cached_source("rss", key, lambda: module_text(
        mech, names, flavours, generator=gen,
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
