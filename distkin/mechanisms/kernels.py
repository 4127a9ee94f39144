"""Generated kernels of RSS mechanisms: derivation, committed preset modules, cache.

For a mechanism, the symbolic kernels of :mod:`.symbolic` (with its parameters
substituted before differentiation) go through :mod:`distkin.codegen.emit` in two
flavours:

========== ==================================== ==================================
kernel     batched (``name``)                   scalar (``name_scalar``)
========== ==================================== ==================================
ik         pose (..., 6) -> q (..., L)          pose (6 floats) -> list of L floats
reach      pose -> reach margin (..., L) (m^2)  idem, list
jacobian   pose -> J (..., L, 6)                pose -> L lists of 6
jq_jx      pose -> (..., L, 7) [Jq_ii, Jx_i]    idem, nested lists
closure    q (..., L), pose -> (..., L, 7)      q (L), pose -> nested lists
           [Phi_i (m), dPhi_i/d(v, omega)]
========== ==================================== ==================================

A third flavour, ``arb`` (suffix ``_arb``; :mod:`distkin.codegen.emit`), evaluates
``reach`` and ``jq_jx`` on python-flint balls: on a point it gives certified values, on a
box of poses an interval enclosure, and on the forward-mode derivative balls of
:mod:`distkin.certify.intervals` the derivatives' enclosures over the box (the
centred form of :mod:`distkin.certify.boxes`).  Those kernels live in separate modules
``rss_<name>_arb`` (:data:`ARB_KERNELS`, :func:`load_kernels` with ``flavour="arb"``),
so the fast modules stay as they are; the symbolic source is the same.

The five presets' modules are committed as ``distkin/_generated/rss_<name>.py``
(registered in :data:`distkin.codegen.registry.GENERATED`, derivation script
``derivations/rss_model.py``).  Any other parameter set is derived on first use, with
only the kernels asked for, and cached (:mod:`distkin.codegen.cache`); the cache key
hashes the model's source files and the parameters, so a second run does no algebra and
imports no sympy.
"""

from __future__ import annotations

import importlib
import time
from pathlib import Path

__all__ = ["KERNELS", "FLAVOURS", "QUERY_KERNELS", "KernelSet", "module_text", "load_kernels",
           "scene_module",
           "preset_module_name", "generate_hunt", "generate_hexa", "generate_ergin",
           "generate_octopod", "generate_octo", "derivation_profile", "ARB_KERNELS",
           "generate_hunt_arb", "generate_hexa_arb", "generate_ergin_arb",
           "generate_octopod_arb", "generate_octo_arb"]

KERNELS = ("ik", "reach", "jacobian", "jq_jx", "closure")
FLAVOURS = ("batched", "scalar")
#: the kernels of the certified (arb) flavour, in their own module ``rss_<name>_arb``
ARB_KERNELS = ("reach", "jq_jx")
_SUFFIX = {"batched": "", "scalar": "_scalar", "arb": "_arb"}
#: rows per slice of the batched kernels (temporaries of 32 KiB stay in cache)
CHUNK = 4096
GENERATOR = "distkin.mechanisms.kernels (derivation: derivations/rss_model.py)"

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

_MODEL_FILES = ("symbolic.py", "kernels.py")

#: scene query type -> the kernels it needs ("model only what a scene requires")
QUERY_KERNELS = {
    "inverse_kinematics": ("ik", "reach"),
    "jacobian": ("jacobian",),
    "forward_kinematics": ("closure",),
}


def preset_module_name(name: str, flavour: str = "batched") -> str:
    return f"rss_{name}_arb" if flavour == "arb" else f"rss_{name}"


def _expressions(mech, names):
    from .symbolic import model_expressions
    me = model_expressions(mech)
    return me, {n: me.get(n) for n in names}


def _kernel_list(mech, exprs, flavours):
    import sympy as sp
    from ..codegen.emit import Kernel
    from .symbolic import POSE, q_symbols
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
    from ..codegen.emit import module_source, symbolic_hash
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


def _generate_preset(name):
    from .presets import description, preset
    return module_text(preset(name), title=f"Preset {name!r}: {description(name)}")


def generate_hunt():
    return _generate_preset("hunt")


def generate_hexa():
    return _generate_preset("hexa")


def generate_ergin():
    return _generate_preset("ergin")


def generate_octopod():
    return _generate_preset("octopod")


def generate_octo():
    return _generate_preset("octo")


def _generate_preset_arb(name):
    from .presets import description, preset
    return module_text(preset(name), ARB_KERNELS, ("arb",),
                       title=f"Preset {name!r}: {description(name)}")


def generate_hunt_arb():
    return _generate_preset_arb("hunt")


def generate_hexa_arb():
    return _generate_preset_arb("hexa")


def generate_ergin_arb():
    return _generate_preset_arb("ergin")


def generate_octopod_arb():
    return _generate_preset_arb("octopod")


def generate_octo_arb():
    return _generate_preset_arb("octo")


class KernelSet:
    """Kernels of one flavour as attributes ``ik, reach, jacobian, jq_jx, closure``
    (the ``arb`` flavour: ``reach, jq_jx``)."""

    def __init__(self, module, flavour):
        self.module = module
        self.flavour = flavour
        suffix = _SUFFIX[flavour]
        for n in KERNELS:
            fn = getattr(module, n + suffix, None)
            if fn is not None:
                setattr(self, n, fn)

    def __repr__(self):
        return f"<KernelSet {self.flavour} of {getattr(self.module, '__name__', '?')}>"


_LOADED: dict = {}


def _preset_for(mech):
    from .presets import PRESETS, preset
    key = mech.geometry_key()
    for name in PRESETS:
        if preset(name).geometry_key() == key:
            return name
    return None


def _model_source_text() -> str:
    here = Path(__file__).resolve().parent
    emit = here.parent / "codegen" / "emit.py"
    return "".join((here / f).read_text(encoding="utf-8") for f in _MODEL_FILES) + \
        emit.read_text(encoding="utf-8")


def load_kernels(mech, flavour: str = "batched") -> KernelSet:
    """The kernels of ``mech``: the committed preset module, else a cached derivation.

    ``flavour`` is "batched", "scalar" or "arb" (:data:`ARB_KERNELS` only, from the
    module ``rss_<name>_arb``).
    """
    if flavour not in FLAVOURS + ("arb",):
        from ..errors import InputError
        raise InputError(f"expected a flavour in {FLAVOURS + ('arb',)}, got {flavour!r}",
                         field="flavour")
    key = (mech.geometry_key(), flavour)
    if key in _LOADED:
        return _LOADED[key]
    if flavour == "arb":
        return _load_arb(mech, key)
    name = _preset_for(mech)
    if name is not None:
        module = importlib.import_module(f"distkin._generated.{preset_module_name(name)}")
    else:
        from ..codegen.cache import cached_source, load_module_file, source_key
        ckey = source_key(_model_source_text(), repr(mech.geometry_key()), KERNELS, FLAVOURS)
        path, _ = cached_source("rss", ckey, lambda: module_text(mech))
        module = load_module_file(path)
    for fl in FLAVOURS:
        _LOADED[(mech.geometry_key(), fl)] = KernelSet(module, fl)
    return _LOADED[key]


def _load_arb(mech, key):
    name = _preset_for(mech)
    if name is not None:
        module = importlib.import_module(f"distkin._generated.{preset_module_name(name, 'arb')}")
    else:
        from ..codegen.cache import cached_source, load_module_file, source_key
        ckey = source_key(_model_source_text(), repr(mech.geometry_key()), ARB_KERNELS,
                          ("arb",))
        path, _ = cached_source("rss", ckey, lambda: module_text(mech, ARB_KERNELS, ("arb",)))
        module = load_module_file(path)
    _LOADED[key] = KernelSet(module, "arb")
    return _LOADED[key]


def scene_module(scene, flavours=FLAVOURS):
    """(source, cache_hit) of the module with the kernels a scene's queries need.

    Used by ``distkin codegen``; the source goes through the derivation cache.
    """
    from ..codegen.cache import cached_source, source_key
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
