r"""Scene kernel modules of the octahedral manipulator and of its Δ 6-6 platforms.

``distkin codegen`` on a ``kind = "octahedral"`` or ``kind = "platform66"`` scene
(:func:`scene_module`).  Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited*
(ICRA 2012): the scene fixes the base P1 P2 P3 and the platform P4 P5 P6, so their six
squared sides are substituted **exactly** into the parts of eq. (3)
(:func:`distkin.codegen.octic.kernel_outputs`, the derivation of the committed kernel
``octic_general``: no second derivation) before common-subexpression elimination; the
queries vary the legs.

Inputs are **squared** leg lengths, as in every distkin octic kernel
(:mod:`distkin._generated.octic_general`): the octic's coefficients are polynomials in
them, and squared legs of rational (or Δ-mapped ``sqrt``) lengths are rational.

Kernels (batched: arrays ``(..., 6)`` -> ``(..., k)``; suffix ``_scalar``: 6 floats ->
a list):

``octic``
    the 9 coefficients :math:`o_8, \dots, o_0` of the octic :math:`O(s_{15})`, eq. (11)
    of the paper for its example (highest degree first, as the JSON contract's
    ``octic.coefficients``);
``parts``
    the 30 coefficients (constant, x, x²) of the ten quadratics of eq. (3) in
    :data:`~distkin.octahedral.octic.PART_NAMES` order, for telling assembly modes from
    spurious roots (:mod:`distkin.octahedral.certified`);
``s15_interval``
    ``[lo, hi]``: every real assembly has :math:`lo \le s_{15} \le hi` (triangle
    inequalities of the four triangles :math:`P_1P_kP_5` with two known sides);
``l_squared`` (``platform66`` only)
    the squared l-legs of the equivalent octahedral manipulator,
    :math:`l^2 = \mathbf A^{-1}(m^2 + \mathbf b)`, eq. (8).

For ``platform66`` every kernel takes the squared **m**-legs: the exact inverse of
eq. (8) is composed into the octic symbolically (the affine map substituted into the
quadratic parts, which stay of low degree, then CSE), so the octic is a function of the
6-6 platform's own legs.
"""

from __future__ import annotations

from ..mechanisms.kernel_names import _SUFFIX
from ..octahedral.banana import LEG_PAIRS, SIDE_PAIRS, squared_distance_symbols
from ..octahedral.octic import PART_NAMES

__all__ = ["KERNELS", "QUERY_KERNELS", "interval_bounds", "module_text", "scene_module",
           "squared_unit_words"]

#: every kernel a scene module can hold, in module order
KERNELS = ("l_squared", "octic", "parts", "s15_interval")
#: scene query type -> the kernels it needs ("model only what a scene requires")
QUERY_KERNELS = {"forward_kinematics": ("octic", "parts", "s15_interval")}
#: rows per slice of the batched kernels (as the RSS scene modules)
CHUNK = 4096

#: the modules whose import closure keys the derivation cache
#: (:func:`~distkin.sourcecache.closure_text`); delta/transform.py derives eq. (8) for
#: the caller (a hand-kept file list missed codegen/rounding.py, QA 6)
_MODEL_MODULES = ("distkin.codegen.octahedral_scene", "distkin.delta.transform")

_DOCS = {
    "l_squared": "Squared l-legs l1^2..l6^2 of the equivalent octahedral manipulator,\n"
                 "l^2 = A^-1 (m^2 + b) (Rojas et al., eq. (8), exact A^-1 and b).",
    "octic": "Coefficients o8 .. o0 of the octic O(s15) (Rojas et al., Sec. III, O = G^2 -\n"
             "4 R1 R2; eq. (11) for the Sec. VI example), highest degree first.",
    "parts": "The ten quadratics of eq. (3) in s15, {names}, three\n"
             "coefficients each (constant, x, x^2): 30 values.",
    "s15_interval": "[lo, hi] with lo <= s15 <= hi for every real assembly: triangle\n"
                    "inequalities (a - b)^2 <= s15 <= (a + b)^2 of the triangles P1 Pk P5 with\n"
                    "known sides a, b.  lo > hi proves that no pose exists.",
}


def interval_bounds(values=None):
    r"""``(lo, hi)``: sympy bounds on :math:`s_{15}` from the triangles :math:`P_1P_kP_5`.

    Every :math:`k \in \{2, 3, 4, 6\}` whose sides :math:`s_{1k}`, :math:`s_{k5}` are both
    a base/platform side or a leg (:data:`~distkin.octahedral.banana.SIDE_PAIRS`,
    :data:`~distkin.octahedral.banana.LEG_PAIRS`) gives
    :math:`(\sqrt{s_{1k}} - \sqrt{s_{k5}})^2 \le s_{15} \le (\sqrt{s_{1k}} + \sqrt{s_{k5}})^2`;
    ``lo`` is the largest lower bound and ``hi`` the smallest upper bound (the same
    triangles as :data:`distkin.octahedral.closure.TRIANGLES_THROUGH_15`).

    Parameters
    ----------
    values : dict {(i, j): sympy number}, optional
        Squared distances substituted (the scene's sides).
    """
    import sympy
    los, his = _bound_terms(values)
    return sympy.Max(*los), sympy.Min(*his)


def _bound_terms(values=None):
    """The lower and upper bounds of :func:`interval_bounds`, as two lists."""
    import sympy
    s = dict(squared_distance_symbols())
    s.update(values or {})
    known = set(SIDE_PAIRS) | set(LEG_PAIRS)
    los, his = [], []
    for k in (2, 3, 4, 6):
        a_pair, b_pair = tuple(sorted((1, k))), tuple(sorted((k, 5)))
        if a_pair in known and b_pair in known:
            a, b = sympy.sqrt(s[a_pair]), sympy.sqrt(s[b_pair])
            los.append((a - b) ** 2)
            his.append((a + b) ** 2)
    return los, his


def _outputs(sides2, leg_map, names, identity=None):
    """name -> list of sympy outputs, in the squared legs (or squared m-legs).

    ``identity``, a list, receives the expressions that identify the outputs for
    :func:`~.emit.symbolic_hash`: the outputs in the squared legs and the mapped
    :math:`l^2` (the substituted outputs share those subtrees thousands of times, and
    their ``srepr`` as a tree ran for minutes on float coordinates, QA J 5)."""
    import sympy
    from .octic import kernel_outputs
    values = {pair: sympy.sympify(sides2[pair]) for pair in SIDE_PAIRS}
    all39 = kernel_outputs(values)
    lo, hi = interval_bounds(values)
    out = {"parts": all39[:30], "octic": all39[30:], "s15_interval": [lo, hi]}
    if identity is not None:
        identity.extend(e for n in names if n in out for e in out[n])
    if leg_map is not None:
        l2 = [e for _, e in _prelude(leg_map)]
        # the other outputs stay in the squared l-legs, which the kernels compute first
        # from the m-legs (:func:`_prelude`): substituting the mapped l^2 (float
        # coordinates: ~50,000 characters each) into the octic and the Max/Min of the
        # interval made sympy's Max/Min simplification and CSE run for minutes (QA J 5)
        out["l_squared"] = l2
        if identity is not None:
            identity.extend(l2)
    return {n: out[n] for n in names}


def _prelude(leg_map):
    """As :func:`_prelude_of`, computed once per leg map (a module asks for it once per
    kernel and flavour; the expansion costs seconds on float coordinates)."""
    key = id(leg_map)
    if _PRELUDE_MEMO.get("key") != key or _PRELUDE_MEMO.get("map") is not leg_map:
        _PRELUDE_MEMO.update(key=key, map=leg_map, value=_prelude_of(leg_map))
    return _PRELUDE_MEMO["value"]


_PRELUDE_MEMO: dict = {}


def _prelude_of(leg_map):
    """``(l_k^2 symbol, its expression in the squared m-legs)`` for the six legs, eq. (8):
    the first lines of a 6-6 kernel (:class:`~.emit.Kernel` ``extra["prelude"]``)."""
    import sympy
    Ainv, c = leg_map
    l2 = [sympy.expand(e) for e in Ainv * sympy.Matrix(_m_symbols()) + c]
    s = squared_distance_symbols()
    return tuple((s[pair], l2[k]) for k, pair in enumerate(LEG_PAIRS))


def _m_symbols():
    import sympy
    return [sympy.Symbol(f"m{k}sq", positive=True) for k in range(1, 7)]


def squared_unit_words(length_unit=None) -> str:
    """The words for a squared length: ``"mm^2 (the scene's unit)"`` for a scene with a
    physical length unit, ``"squared length units"`` for a unitless one (None, "none")."""
    if length_unit in (None, "none"):
        return "squared length units"
    return f"{length_unit}^2 (the scene's unit)"


def _units_paragraph(length_unit, what) -> str:
    """The module docstring's line naming the length unit of its numbers (QA: a
    ``length = "mm"`` scene's module was the unitless one's, SIDES2 in mm^2 unsaid)."""
    if length_unit in (None, "none"):
        return (f"Units: the scene's lengths are unitless; {what} are in the squares of "
                "its length unit.")
    return (f"Units: lengths in {length_unit} (the scene's [units] length); {what} are in "
            f"{length_unit}^2.")


def module_text(sides2, names, flavours, *, leg_map=None, generator, title,
                notes="", constants=None, length_unit=None) -> str:
    """Source of a scene module (only the kernels ``names``, in ``flavours``).

    Parameters
    ----------
    sides2 : dict {(i, j): sympy number}
        The six squared sides (:data:`~distkin.octahedral.banana.SIDE_PAIRS`), exact.
    names : sequence of str
        Some of :data:`KERNELS` (``l_squared`` needs ``leg_map``).
    flavours : sequence of str
        "batched" and/or "scalar".
    leg_map : (sympy.Matrix (6, 6), sympy.Matrix (6, 1)), optional
        ``(Ainv, c)`` with :math:`l^2 = A^{-1} m^2 + c` (a Δ-transform's exact inverse,
        :meth:`distkin.delta.DeltaTransform.inverse`): the kernels take squared m-legs.
    notes : str
        A paragraph for the module docstring (queries without a kernel, ...).
    constants : dict, optional
        Further module constants (written with ``repr``).
    length_unit : str, optional
        The scene's length unit ("mm", ...), named in the docstrings and as
        ``LENGTH_UNIT``; None or "none": unitless, the generic words.
    """
    import sympy
    from .emit import Kernel, module_source, symbolic_hash
    names = [n for n in KERNELS if n in names]
    identity = []
    outs = _outputs(sides2, leg_map, names, identity)
    s = squared_distance_symbols()
    if leg_map is None:
        inputs = (("legs2", tuple(s[p] for p in LEG_PAIRS)),)
        what = ("legs2 : (..., 6) squared legs l1^2..l6^2 (legs P1P4, P2P4, P2P5, P3P5,\n"
                f"P3P6, P1P6: docs/design.md §3), {squared_unit_words(length_unit)}")
    else:
        inputs = (("m_legs2", tuple(_m_symbols())),)
        what = ("m_legs2 : (..., 6) squared m-legs m1^2..m6^2 of the 6-6 platform (rows of\n"
                f"eq. (9)), {squared_unit_words(length_unit)}")
    kernels = []
    for flavour in flavours:
        for n in names:
            doc = _DOCS[n].format(names=", ".join(PART_NAMES))
            doc += f"\n\n{what if flavour == 'batched' else what.replace('(..., 6)', '(6,)')}"
            # checked: float64 inputs of shape (..., 6), >= 0 (.checks); the octic of
            # the package's own solver is the internal octic_general, not these
            extra = {"cse_optimizations": None, "chunk": CHUNK, "checked": True,
                     "nonnegative": True,
                     "units": {inputs[0][0]: squared_unit_words(length_unit)}}
            if leg_map is not None and n != "l_squared":
                extra["prelude"] = _prelude(leg_map)
            kernels.append(Kernel(n + _SUFFIX[flavour], inputs, outs[n], flavour=flavour,
                                  doc=doc, extra=extra))
    sides_text = {f"s{i}{j}": sympy.sstr(sides2[(i, j)]) for i, j in SIDE_PAIRS}
    doc = (f"{title} (Rojas, Borràs, Thomas, The Octahedral Manipulator Revisited, "
           "ICRA 2012).\n\n"
           f"Squared sides substituted exactly before CSE: {sides_text}.\n"
           f"Inputs: {what}.\n"
           + _units_paragraph(length_unit, "SIDES2, the inputs, s15 (s15_interval)"
                              + (", l_squared" if "l_squared" in names else ""))
           + "\n"
           "Batched kernels take (..., 6) arrays; scalar ones (suffix _scalar) 6 floats.\n"
           "Inputs are converted to float64 first; a wrong shape or a negative squared\n"
           "length is a ValueError naming it.\n"
           "Needs only numpy.  Coefficients are float64 evaluations of exact expressions;\n"
           "the octic is ill-conditioned near clustered roots (docs/design.md §5): for a\n"
           "certified root count use distkin's certified tier.")
    if notes:
        doc += "\n\n" + notes
    src = module_source(kernels, generator=generator, doc=doc,
                        source_hash=symbolic_hash(*identity, order="none"),
                        constants={"SIDES2": sides_text,
                                   "LENGTH_UNIT": (None if length_unit in (None, "none")
                                                   else length_unit),
                                   "PART_NAMES": PART_NAMES,
                                   **(constants or {}), "KERNELS": tuple(names),
                                   "FLAVOURS": tuple(flavours)})
    return src


def scene_module(key_parts, sides2, names, flavours, *, leg_map=None, scene_name,
                 notes="", constants=None, length_unit=None):
    """(source, cache_hit) of a scene's module, through the derivation cache.

    ``key_parts`` identify the scene's geometry (the exact texts of its points and
    offsets), so that a cache hit needs no algebra: ``sides2`` and ``leg_map`` are
    callables returning the values of :func:`module_text`, called only to derive;
    ``length_unit``, the scene's, is named in the module (:func:`module_text`).
    """
    from ..sourcecache import cached_source, closure_text, source_key
    gen = (f"distkin codegen {scene_name} (distkin.codegen.octahedral_scene; derivation: "
           "derivations/octahedral_octic.py)")
    key = source_key(closure_text(_MODEL_MODULES), repr(key_parts), tuple(names), tuple(flavours),
                     gen, notes, repr(constants), repr(length_unit))
    path, hit = cached_source("octahedral", key, lambda: module_text(
        sides2(), names, flavours, leg_map=leg_map() if leg_map else None, generator=gen,
        title=f"Kernels of scene {scene_name}", notes=notes, constants=constants,
        length_unit=length_unit))
    return path.read_text(encoding="utf-8"), hit
