"""Loading the generated kernels of RSS mechanisms: committed preset modules, one cache.

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

The batched flavour of ``reach`` and ``jq_jx`` (:data:`LOOP_KERNELS`) comes with a
``loop`` twin (suffix ``_loop``; :mod:`distkin.codegen.emit`): ``f(pose (N, 6), out)``
fills ``out`` row by row with the scalar arithmetic, plain Python that
:mod:`distkin.indices.study_compiled` compiles with numba (``KernelSet.loops``).

A third flavour, ``arb`` (suffix ``_arb``; :mod:`distkin.codegen.emit`), evaluates
``ik``, ``reach`` and ``jq_jx`` on python-flint balls: on a point it gives certified values
(the certified tier of :mod:`.kinematics_tiers`), on a
box of poses an interval enclosure, and on the forward-mode derivative balls of
:mod:`distkin.certify.intervals` the derivatives' enclosures over the box (the
centred form of :mod:`distkin.certify.boxes`).  Those kernels live in separate modules
``rss_<name>_arb`` (:data:`ARB_KERNELS`, :func:`load_kernels` with ``flavour="arb"``),
so the fast modules stay as they are.  Their symbolic source is the exact model of
:mod:`.symbolic` (the same mechanism with every number exact: what the certified tier
certifies), where the fast flavours round the parameters to float64 first.

The five presets' modules are committed as ``distkin/_generated/rss_<name>.py``
(registered in :data:`distkin.codegen.registry.GENERATED`, derived by
:mod:`distkin.codegen.rss`, derivation script ``derivations/rss_model.py``).  Any other
parameter set is derived on first use by :func:`distkin.codegen.rss.derived_module` (the
one run-time arrow into the code generator: "model only what a scene requires") and
cached on disk (:mod:`distkin.sourcecache`); the cache key hashes the model's source
files and the parameters, so a second run does no algebra and imports no sympy.  Loaded
kernel sets are kept in one cache (``_LOADED``, keyed by the geometry), outside the
frozen mechanisms.
"""

from __future__ import annotations

import importlib
import math

from .kernel_names import _SUFFIX, ARB_KERNELS, FLAVOURS, KERNELS, LOOP_KERNELS, RANGE_KERNEL

__all__ = ["KERNELS", "FLAVOURS", "ARB_KERNELS", "KernelSet", "load_kernels",
           "preset_module_name", "preset_table_matches", "PRESET_ULPS", "range_legs"]


def preset_module_name(name: str, flavour: str = "batched") -> str:
    return f"rss_{name}_arb" if flavour == "arb" else f"rss_{name}"


class KernelSet:
    """Kernels of one flavour as attributes ``ik, reach, jacobian, jq_jx, closure``
    (the ``arb`` flavour: ``ik, reach, jq_jx, closure``, and ``ranges`` for a leg table
    with revolute joint ranges: :func:`range_legs`); the batched flavour's ``loop`` twins
    (:data:`LOOP_KERNELS`, plain Python for numba) in ``loops`` (name -> function; empty
    for a module generated without them)."""

    def __init__(self, module, flavour):
        self.module = module
        self.flavour = flavour
        suffix = _SUFFIX[flavour]
        for n in KERNELS + (RANGE_KERNEL,):
            fn = getattr(module, n + suffix, None)
            if fn is not None:
                setattr(self, n, fn)
        self.loops = {}
        if flavour == "batched":
            for n in LOOP_KERNELS:
                fn = getattr(module, n + _SUFFIX["loop"], None)
                if fn is not None:
                    self.loops[n] = fn

    def __repr__(self):
        return f"<KernelSet {self.flavour} of {getattr(self.module, '__name__', '?')}>"


#: the loaded kernel sets, keyed by (kind, geometry key, flavour): the
#: :data:`_LOADED_KEPT` most recently loaded (a sweep over geometries must not grow it
#: without bound; a set dropped is loaded again from its module, derived sources being
#: cached on disk)
_LOADED: dict = {}
_LOADED_KEPT = 192


def _keep(key, value):
    """``_LOADED[key] = value``, the oldest entries dropped beyond :data:`_LOADED_KEPT`."""
    while len(_LOADED) >= _LOADED_KEPT:
        _LOADED.pop(next(iter(_LOADED)))
    _LOADED[key] = value
    return value


def _committed_presets() -> list[str]:
    """Names of the preset modules committed in ``distkin/_generated/`` (``rss_<name>.py``;
    the mechanism's own name first is only a hint)."""
    from importlib import resources
    names = [p.name[4:-3] for p in resources.files("distkin._generated").iterdir()
             if p.name.startswith("rss_") and p.name.endswith(".py")
             and not p.name.endswith("_arb.py")]
    return sorted(names)


#: how many units in the last place a number of a leg table may lie from the committed
#: preset's and still load that preset's module: numpy's cos and sin are not correctly
#: rounded (numpy 1.24 gives -0.06733974596215557 for a Hunt base coordinate, 2.x
#: ...58; SIMD variants differ across CPUs), so a preset's table is its committed one
#: only up to the last bit or two
PRESET_ULPS = 4


def _same_number(a, b) -> bool:
    """``a == b``, floats within :data:`PRESET_ULPS` ulps of the larger magnitude (a
    zero only equals a zero); tuples entry by entry; anything else exactly, same type."""
    if type(a) is float and type(b) is float:
        if a == b:
            return True
        return (a != 0.0 and b != 0.0 and math.isfinite(a) and math.isfinite(b)
                and math.copysign(1.0, a) == math.copysign(1.0, b)
                and abs(a - b) <= PRESET_ULPS * math.ulp(max(abs(a), abs(b))))
    if type(a) is tuple and type(b) is tuple:
        return len(a) == len(b) and all(_same_number(x, y) for x, y in zip(a, b))
    return type(a) is type(b) and a == b


def preset_table_matches(legs: tuple, committed: tuple) -> bool:
    """A leg table's :meth:`~.legs.LegsDescription.key` is a committed module's ``LEGS``:
    the same fields, types, branches and ranges' presence, every number within
    :data:`PRESET_ULPS` units in the last place (relative, entry by entry; 1e-9 m is
    ~1e7 ulps and does not match)."""
    return legs == committed or _same_number(legs, committed)


def _preset_for(mech):
    """The committed preset module whose leg table is ``mech``'s (their ``LEGS`` are
    the preset's :meth:`~.legs.LegsDescription.key`: ``python -m distkin.codegen
    --check``), up to the last bits of numpy's trigonometry
    (:func:`preset_table_matches`), or None.  A preset written out as legs finds its
    module here.  Reads the generated modules, not :mod:`.presets` (no import cycle)."""
    legs = mech.leg_description().key()
    names = _committed_presets()
    for name in sorted(names, key=lambda n: n != mech.name):
        module = importlib.import_module(f"distkin._generated.{preset_module_name(name)}")
        committed = getattr(module, "LEGS", None)
        if committed is not None and preset_table_matches(legs, committed):
            return name
    return None


def load_kernels(mech, flavour: str = "batched") -> KernelSet:
    """The kernels of ``mech`` (an RSS or leg description, or a mechanism on one), from
    its leg table: the committed preset module with that table, else a cached derivation
    (:func:`distkin.codegen.rss.derived_module`: a progress line and the time on stderr).

    ``flavour`` is "batched", "scalar" or "arb" (:data:`ARB_KERNELS` only, from the
    module ``rss_<name>_arb``).
    """
    if flavour not in FLAVOURS + ("arb",):
        from ..errors import InputError
        raise InputError(f"expected a flavour in {FLAVOURS + ('arb',)}, got {flavour!r}",
                         field="flavour")
    if getattr(mech, "route", "generated") == "numpy":
        return _numeric(mech, flavour)
    key = (type(mech).kind, mech.geometry_key(), flavour)
    if key in _LOADED:
        return _LOADED[key]
    if flavour == "arb":
        return _load_arb(mech, key)
    name = _preset_for(mech)
    if name is not None:
        module = importlib.import_module(f"distkin._generated.{preset_module_name(name)}")
    else:
        from ..codegen.rss import derived_module      # a custom geometry: derive once
        module = derived_module(mech, KERNELS, FLAVOURS)
    sets = {fl: KernelSet(module, fl) for fl in FLAVOURS}
    for fl in FLAVOURS:
        _keep(key[:2] + (fl,), sets[fl])
    return sets[key[2]]


def _numeric(mech, flavour):
    """The plain-numpy kernels of a leg mechanism (``route="numpy"``)."""
    if flavour == "arb":
        from ..errors import InputError
        raise InputError("expected route 'generated' for arb (certified) kernels, got the "
                         "numpy route, which has none", field="route")
    key = ("numpy", mech.geometry_key(), flavour)
    if key not in _LOADED:
        from .reference import NumericKernels
        return _keep(key, NumericKernels(mech.leg_description(), flavour))
    return _LOADED[key]


def _load_arb(mech, key):
    """The arb kernels certify the mechanism as stated (the exact model of
    :mod:`.symbolic`): an RSS mechanism's parameters, a leg table's numbers.  So a
    committed preset module serves only an RSS mechanism with the preset's parameters; a
    preset written out as legs gets the kernels of its table (which differs from the
    parameters' exact geometry by the float64 rounding of the table, cos 90° = 6.1e-17)."""
    module = None
    name = _preset_for(mech) if getattr(mech, "kind", None) == "rss" else None
    if name is not None:
        module = importlib.import_module(f"distkin._generated.{preset_module_name(name, 'arb')}")
        if getattr(module, "PARAMETERS", None) != dict(mech.geometry_key()):
            module = None
    if module is None:
        from ..codegen.rss import derived_module
        extra = (RANGE_KERNEL,) if range_legs(mech) else ()
        module = derived_module(mech, ARB_KERNELS + extra, ("arb",))
    return _keep(key, KernelSet(module, "arb"))


def range_legs(mech) -> list[int]:
    """The legs (0-based) of ``mech``'s table whose crank angles the arb flavour's
    ``ranges`` kernel bounds, in its row order (:func:`.legs.ranged_legs`)."""
    from .legs import ranged_legs
    return ranged_legs(getattr(mech.leg_description(), "leg_table", None) or ())


