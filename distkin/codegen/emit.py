"""sympy expressions -> Python source, with common-subexpression elimination.

Three flavours of the same symbolic source (STYLE.md, sympy/codegen):

``batched``
    numpy; every input is an array ``(..., k)`` whose last axis is unpacked, the
    output has shape ``(...,) + out_shape``.  For sweeps over many poses.
``scalar``
    plain floats and :mod:`math`; inputs are sequences, the output a nested list.
    For the 1 kHz control loop, where numpy's per-call overhead dominates.
``loop``
    the scalar flavour's arithmetic in a loop over the rows of 2-D inputs ``(N, k)``,
    writing row ``n`` of a given output ``(N,) + out_shape`` (the last argument,
    ``_out``): plain Python, written to be compiled by numba (``numba.njit`` of the
    function), which evaluates a pose with no temporary arrays.  For the study's sweeps
    (:mod:`distkin.indices.study_compiled`), where the batched flavour's few hundred
    numpy temporaries per call cost most of the kernel's time.
``exact``
    only ``+ - * /`` and integer powers, rationals printed as ``_Q(p, q)``
    (``flint.fmpq``); evaluates exactly on ``fmpq`` inputs and as certified balls on
    ``arb`` inputs.  Polynomial/rational expressions only.
``arb``
    python-flint balls (:mod:`distkin.certify`): ``+ - * /``, integer powers, ``abs``,
    square roots, ``sin`` and ``cos`` written as methods of the operands
    (``x.sqrt()``, ``x.sin()``; a number as ``_A(2).sqrt()``), ``atan2(y, x)`` as
    ``_A.atan2(y, x)``, floats and the rationals that are doubles as exact double
    literals, other rationals as ``(_A(p) / q)`` (exact integer ball, rounded division),
    so every operation returns an enclosure of the exact value.  The same kernel also runs on
    any number type with those methods (the forward-mode derivative balls of
    :mod:`distkin.certify.intervals`).  Evaluated on a box of ``arb`` inputs it gives
    the plain interval enclosure of the kernel over the box.

A module written by :func:`module_source` opens with a header naming its generator,
the versions used and a SHA-256 of the symbolic source (``srepr`` of the kernels'
expressions), and it imports neither sympy nor distkin.
"""

from __future__ import annotations

import hashlib
import platform
from dataclasses import dataclass, field

from .checks import batch_shape_name, helpers, prologue

__all__ = ["Kernel", "kernel_source", "module_source", "symbolic_hash", "FLAVOURS"]

FLAVOURS = ("batched", "scalar", "loop", "exact", "arb")


@dataclass(frozen=True)
class Kernel:
    """One generated function.

    Parameters
    ----------
    name : str
        The function's name.
    inputs : tuple of (str, tuple of sympy.Symbol)
        Arguments in order; each argument is a vector whose components are the symbols
        (a length-1 tuple for a scalar argument, still passed as a vector).
    output : sympy.Matrix or sequence of sympy.Expr
        The value; a Matrix keeps its shape, a sequence is a vector.
    flavour : {"batched", "scalar", "exact", "arb"}
    doc : str
        Docstring body (cite the paper and equation; state shapes and units).
    cse : bool
        Run common-subexpression elimination.
    extra : dict
        Options: ``cse_optimizations`` (passed to ``sympy.cse``; default "basic");
        ``chunk`` (batched flavour: a 2-D batch longer than this is evaluated in slices
        of this many rows, every input sliced alike along its first axis);
        ``prelude`` (a sequence of (symbol, expression in the inputs): assigned in order
        after the inputs are read, so that the output may use the symbols as
        intermediate variables instead of the expressions substituted into it);
        ``checked`` (batched, scalar and loop flavours: the inputs converted to float and
        their shapes checked first, :mod:`.checks`; the scene modules' kernels),
        ``nonnegative`` (with ``checked``: inputs that are squared lengths) and
        ``positive`` (with ``checked``: {input name: column indices} that must be > 0,
        the prismatic legs' lengths of a closure) and ``units`` (with ``checked``:
        {input name: the words of its units}, named by a scalar kernel's refusal of an
        entry that is not a number).
    """

    name: str
    inputs: tuple
    output: object
    flavour: str = "batched"
    doc: str = ""
    cse: bool = True
    extra: dict = field(default_factory=dict)


def _is_constant(expr) -> bool:
    """A number sympy keeps unevaluated (``sqrt(7188...)``, ``3*sqrt(2)``, ``pi``,
    ``sin(1)``): neither a Rational nor a Float, and no free symbols."""
    import sympy
    return (isinstance(expr, sympy.Expr) and not isinstance(expr, sympy.core.relational.Relational)
            and not expr.is_Rational and not expr.is_Float and expr.is_number)


def nearest_double(expr):
    """The binary64 value nearest the exact constant ``expr`` (correctly rounded; an
    infinity beyond the float64 range), or ``None`` when it is not a real number.

    An ``arb`` enclosure (:func:`distkin.exact.sympy_to_arb`: rationals, ``+ - *``,
    rational powers, ``pi``) at rising precision until both ends of the ball round to
    the same double (rounding is monotone, so the exact value rounds to it too); other
    constants (``E``, ``sin(1)``) through ``evalf`` at 60 digits, rounded once.  Printed
    as a literal, the constant costs nothing at run time, and it never reaches numpy as
    a Python integer beyond int64 (``numpy.sqrt(7188024561708202275234453794882)`` is an
    object-dtype call that numpy refuses) or ``math`` as an int beyond 1.8e308."""
    import math
    from fractions import Fraction

    import sympy
    from ..errors import InputError

    def dyadic(x):                          # the exact value of an arb of radius 0
        man, exp = x.mid().man_exp()
        man, exp = int(man), int(exp)
        return Fraction(man * 2 ** exp) if exp >= 0 else Fraction(man, 2 ** -exp)

    def rounded(q):
        try:
            return float(q)                 # Fraction -> float: correctly rounded
        except OverflowError:
            return math.inf if q > 0 else -math.inf

    try:
        import flint
        from ..exact import sympy_to_arb
        for prec in (128, 256, 1024, 4096):
            with flint.ctx.workprec(prec):
                ball = sympy_to_arb(expr)
                if not ball.is_finite():
                    break
                lo, hi = rounded(dyadic(ball.lower())), rounded(dyadic(ball.upper()))
            if lo == hi:
                return lo
    except (InputError, ImportError):
        pass
    value = expr.evalf(60)
    if not value.is_Float:
        return None                         # complex, or not a number after all
    return rounded(Fraction(*map(int, sympy.Rational(value).as_numer_denom())))


def _printers():
    import math

    import sympy
    from sympy.printing.numpy import NumPyPrinter
    from sympy.printing.pycode import PythonCodePrinter

    class Float64(object):
        """What the batched and the scalar flavour print alike (a mixin before their
        sympy printer): small integer powers multiplied out, binary64 parameters and
        irrational constants as correctly rounded doubles."""

        def _print_Pow(self, expr, rational=False):
            base, exp = expr.as_base_exp()
            if exp.is_Integer and 2 <= int(exp) <= 4:
                # in parentheses: the Mul printer may put a power after "/" (a/(x*x))
                b = self.parenthesize(base, sympy.printing.precedence.PRECEDENCE["Mul"])
                return "(" + "*".join([b] * int(exp)) + ")"
            if exp.is_Integer and int(exp) == -1:
                b = self.parenthesize(base, sympy.printing.precedence.PRECEDENCE["Mul"])
                return f"1.0/{b}"
            return super()._print_Pow(expr, rational=rational)

        def _print_Float(self, expr):
            # a binary64 parameter prints as its shortest round-trip repr (17 significant
            # digits at most), not sympy's 15-digit default, which can be off by an ulp
            v = float(expr)
            if expr._prec == 53 and sympy.Float(v, precision=53)._mpf_ == expr._mpf_:
                return repr(v)
            return super()._print_Float(expr)

        def _print(self, expr, **kwargs):
            # a constant that is not a rational (sqrt(7188...), 3*sqrt(2), pi) prints as
            # its correctly rounded double (nearest_double): no numpy.sqrt of a Python int
            if _is_constant(expr):
                v = nearest_double(expr)
                if v is not None and not math.isfinite(v):
                    # beyond the float64 range: what evaluating it in float64 gives
                    return "math.inf" if v > 0 else "(-math.inf)"
                if v is not None:
                    # a negative value in parentheses unless sympy already treats the
                    # expression as a difference (-sqrt(2)): then the Add printer writes
                    # "x - 1.4142135623730951" and a power parenthesizes its base
                    prec = sympy.printing.precedence.precedence(expr)
                    add = sympy.printing.precedence.PRECEDENCE["Add"]
                    return repr(v) if v >= 0 or prec <= add else f"({v!r})"
            return super()._print(expr, **kwargs)

        def _numeric_part(self, expr, kind):
            # x*3*sqrt(2) -> 4.242640687119285*x, x + 1 + sqrt(2) -> x + 2.414213562373095:
            # the numeric factors (terms) of a product (sum) with an irrational one are
            # one correctly rounded double, not several roundings
            num = [a for a in expr.args if a.is_number]
            if len(num) > 1 and any(_is_constant(a) for a in num):
                v = nearest_double(kind(*num))
                if v is not None and math.isfinite(v):
                    rest = [a for a in expr.args if not a.is_number]
                    expr = kind(sympy.Float(v, precision=53), *rest, evaluate=False)
            return expr

        def _print_Mul(self, expr, *args, **kwargs):
            return super()._print_Mul(self._numeric_part(expr, sympy.Mul), *args, **kwargs)

        def _print_Add(self, expr, *args, **kwargs):
            return super()._print_Add(self._numeric_part(expr, sympy.Add), *args, **kwargs)

    def _fold(ufunc):
        # numpy.maximum(a, numpy.maximum(b, c)): elementwise, and no functools import
        # (sympy's own NumPyPrinter folds with functools.reduce)
        def fold(self, expr):
            args = [self.doprint(a) for a in expr.args]
            out = args[-1]
            for a in reversed(args[:-1]):
                out = f"numpy.{ufunc}({a}, {out})"
            return out
        return fold

    class Batched(Float64, NumPyPrinter):
        _print_Max = _fold("maximum")
        _print_Min = _fold("minimum")

    class Scalar(Float64, PythonCodePrinter):
        pass

    class Exact(PythonCodePrinter):
        def _print_Rational(self, expr):
            return f"_Q({expr.p}, {expr.q})"

        def _print_Integer(self, expr):
            return str(expr.p)

        def _print_Pow(self, expr, rational=False):
            base, exp = expr.as_base_exp()
            if not exp.is_Integer:
                raise ValueError(f"the exact flavour takes integer powers only, got {expr}")
            b = self.parenthesize(base, sympy.printing.precedence.PRECEDENCE["Pow"])
            return f"{b}**{int(exp)}" if int(exp) >= 0 else f"_Q(1)/({b}**{-int(exp)})"

        def _print_Float(self, expr):
            raise ValueError(f"the exact flavour takes no floats, got {expr}")

        def _print_Function(self, expr):
            raise ValueError(f"the exact flavour takes no functions, got {expr}")

    class Arb(PythonCodePrinter):
        # every constant is turned into a ball exactly (doubles) or rigorously (p / q)
        #: kernel_source sets a dict {(p, q): name}: the other rationals become locals
        #: computed once per call at the top of the kernel (kernel_source)
        hoisted = None

        def _print_Rational(self, expr):
            p, q = expr.p, expr.q
            if q & (q - 1) == 0 and abs(p) < 2 ** 53 and q.bit_length() < 1000:
                # a double exactly (p / 2^k, k < 1000: a normal double): its literal
                return repr(float(expr))
            if self.hoisted is None:
                return f"(_A({p}) / {q})"
            return self.hoisted.setdefault((p, q), f"_k{len(self.hoisted)}")

        def _operand(self, expr):
            # the receiver of a method call (x.sqrt(), x.sin()): a number is made a
            # ball first (``2.sqrt()`` is no Python, a double has no .sqrt())
            if expr.is_Number:
                return f"_A({self.doprint(expr)})"
            return self.parenthesize(expr, sympy.printing.precedence.PRECEDENCE["Atom"],
                                     True)

        def _print_Integer(self, expr):
            return str(expr.p)

        def _print_Float(self, expr):
            v = float(expr)
            if sympy.Float(v, precision=expr._prec)._mpf_ != expr._mpf_:
                raise ValueError(f"the arb flavour takes floats exact in binary64, got {expr}")
            return repr(v)

        def _print_Pow(self, expr, rational=False):
            base, exp = expr.as_base_exp()
            b = self._operand(base)
            if exp == sympy.Rational(1, 2):
                return f"{b}.sqrt()"
            if exp == sympy.Rational(-1, 2):
                return f"(1 / {b}.sqrt())"
            if not exp.is_Integer:
                raise ValueError(f"the arb flavour takes integer and half powers, got {expr}")
            n = int(exp)
            if n == 0:
                return "1"
            # a product in parentheses (the Mul printer may put it after a "/"); balls
            # multiply tightly, while arb's ** of a wide ball can be loose
            bp = self.parenthesize(base, sympy.printing.precedence.PRECEDENCE["Mul"])
            prod = "(" + "*".join([bp] * abs(n)) + ")" if abs(n) > 1 else bp
            return prod if n > 0 else f"(1 / {prod})"

        def _print_Abs(self, expr):
            return f"abs({self.doprint(expr.args[0])})"

        def _unary(self, expr, method):
            return f"{self._operand(expr.args[0])}.{method}()"

        def _print_sin(self, expr):
            return self._unary(expr, "sin")

        def _print_cos(self, expr):
            return self._unary(expr, "cos")

        def _print_atan2(self, expr):
            # arb's two-argument arctangent (a static method of the ball type ``_A``)
            y, x = (self.doprint(a) for a in expr.args)
            return f"_A.atan2({y}, {x})"

        def _print_Function(self, expr):
            raise ValueError(f"the arb flavour has no rule for {expr.func}, got {expr}")

        def _refuse(self, expr, *args, **kwargs):
            raise ValueError(f"the arb flavour has no rule for {type(expr).__name__}, got "
                             f"{expr}")

    # every function or constant the Python printer knows, except ours, is refused
    from sympy.printing.pycode import _known_constants_math, _known_functions_math
    for _name in list(_known_functions_math) + list(_known_constants_math) + ["Min", "Max"]:
        if _name not in ("sin", "cos", "Abs", "atan2"):
            setattr(Arb, f"_print_{_name}", Arb._refuse)

    return {"batched": Batched({"fully_qualified_modules": True}),
            "scalar": Scalar({"fully_qualified_modules": True}),
            "loop": Scalar({"fully_qualified_modules": True}),
            "exact": Exact(), "arb": Arb()}


def symbolic_hash(*exprs, order: str | None = None) -> str:
    """SHA-256 of the ``srepr`` of expressions (the identity of a symbolic source).

    ``order="none"`` writes sums and products in sympy's own argument order (canonical
    within a sympy version, which a module's header names) instead of the default
    printing order, which sorts every sum by evaluating the numeric factors of each
    term (``complex(sqrt(7188...))``): the octahedral scene modules use it, whose sides
    substituted from decimal coordinates put large irrational constants in thousands of
    terms (30 s of srepr for a ``platform66`` scene in inches, 1 s in this order).  The
    default keeps the hashes of the committed modules of ``distkin/_generated``."""
    import sympy
    settings = {} if order is None else {"order": order}
    h = hashlib.sha256()
    for e in exprs:
        h.update(sympy.srepr(e, **settings).encode())
        h.update(b"\x00")
    return h.hexdigest()


def _flat_output(output):
    import sympy
    if isinstance(output, sympy.MatrixBase):
        return list(output), tuple(output.shape)
    out = list(output)
    return out, (len(out),)


_CSE_MEMO: dict = {}


def _cse(flat, optimizations):
    """sympy.cse of a kernel's outputs, remembered for the flavours of the same kernel
    (the batched and scalar flavours print one elimination; CSE is most of a
    derivation's time).  Deterministic: the same expressions give the same result."""
    import sympy
    key = (tuple(flat), optimizations)
    hit = _CSE_MEMO.get(key)
    if hit is None:
        hit = sympy.cse(flat, symbols=sympy.numbered_symbols("_c"), optimizations=optimizations)
        if len(_CSE_MEMO) >= 32:
            _CSE_MEMO.pop(next(iter(_CSE_MEMO)))
        _CSE_MEMO[key] = hit
    return hit


def kernel_source(k: Kernel, integers: dict | None = None) -> str:
    """The source text of one function.

    In the arb flavour every rational constant that is not a double is computed once per
    call at the top of the kernel, ``_k0 = (_A(p) / q)``; given ``integers`` (a dict
    int -> index, shared by a module's kernels: :func:`module_source`) as
    ``_k0 = _Z[i] / _Z[j]`` from the module's exact integer balls ``_Z`` instead, which
    saves converting big Python integers on every call."""
    import sympy
    if k.flavour not in FLAVOURS:
        raise ValueError(f"expected a flavour in {FLAVOURS}, got {k.flavour!r}")
    printer = _printers()[k.flavour]
    if k.flavour == "arb":
        printer.hoisted = {}
    flat, shape = _flat_output(k.output)
    if k.cse:
        # extra["cse_optimizations"]: None skips sympy's "basic" pre-optimisations, which
        # cost seconds on large kernels (the RSS Jacobians) for little gain
        reps, reduced = _cse(flat, k.extra.get("cse_optimizations", "basic"))
    else:
        reps, reduced = [], flat
    args = [name for name, _ in k.inputs]
    loop = k.flavour == "loop"
    lines = [f"def {k.name}({', '.join(args + (['_out'] if loop else []))}):"]
    doc = k.doc.strip() or f"Generated kernel {k.name}."
    if k.flavour == "loop":
        doc += ("\n\nLoop flavour: row n of every input (N, k) -> row n of ``_out`` (N, ...),"
                "\nfor numba (plain Python here: slow uncompiled).")
    lines.append('    """' + doc.replace("\n", "\n    ") + '\n    """')
    # float64 and shape checks of a checked kernel (.checks); a checked batched kernel of
    # several inputs gets their broadcast batch shape, ``batch``, which its output and
    # its chunks follow (else the first input's, unchecked: the committed kernels)
    lines += prologue(k, shape)
    batch = batch_shape_name(k)
    chunk = k.extra.get("chunk") if k.flavour == "batched" else None
    if chunk and batch:
        sliced = ", ".join(f"({a}[_i:_i + {int(chunk)}] if {a}.ndim == 2 and len({a}) == "
                           f"{batch}[0] else {a})" for a in args)
        lines += [
            f"    if len({batch}) == 1 and {batch}[0] > {int(chunk)}:",
            "        _res = None",
            f"        for _i in range(0, {batch}[0], {int(chunk)}):",
            f"            _part = {k.name}({sliced})",
            "            if _res is None:",
            f"                _res = numpy.empty(({batch}[0],) + _part.shape[1:])",
            f"            _res[_i:_i + {int(chunk)}] = _part",
            "        return _res",
        ]
    elif chunk:
        # large 2-D batches run in chunks whose temporaries stay in the CPU cache (about
        # 5x faster at N = 1e5 than one pass over the whole batch)
        first = args[0]
        # the other inputs sliced only where they are rows of the batch too: one that
        # broadcasts (a pose (6,) beside q (N, L)) is passed whole (QA W 4: sliced, it
        # came out empty past the first chunk)
        sliced = ", ".join(
            f"{a}[_i:_i + {int(chunk)}]" if a == first else
            f"({a}[_i:_i + {int(chunk)}] if numpy.ndim({a}) == 2 and len({a}) == len({first})"
            f" else {a})" for a in args)
        lines += [
            f"    if numpy.ndim({first}) == 2 and len({first}) > {int(chunk)}:",
            "        _res = None",
            f"        for _i in range(0, len({first}), {int(chunk)}):",
            f"            _part = {k.name}({sliced})",
            "            if _res is None:",
            f"                _res = numpy.empty((len({first}),) + _part.shape[1:])",
            f"            _res[_i:_i + {int(chunk)}] = _part",
            "        return _res",
        ]
    ind = "    "
    if loop:
        lines.append(f"    for _n in range({args[0]}.shape[0]):")
        ind = "        "
    for name, syms in k.inputs:
        for i, s in enumerate(syms):
            if k.flavour == "batched":
                lines.append(f"    {printer.doprint(s)} = {name}[..., {i}]")
            elif loop:
                lines.append(f"{ind}{printer.doprint(s)} = {name}[_n, {i}]")
            else:
                lines.append(f"    {printer.doprint(s)} = {name}[{i}]")
    for sym, expr in k.extra.get("prelude", ()):
        lines.append(f"{ind}{printer.doprint(sym)} = {printer.doprint(expr)}")
    head = len(lines)
    for sym, expr in reps:
        lines.append(f"{ind}{printer.doprint(sym)} = {printer.doprint(expr)}")
    if loop:
        for idx, expr in enumerate(reduced):
            lines.append(f"{ind}_out[_n, {numpy_index(idx, shape)}] = {printer.doprint(expr)}")
    elif k.flavour == "batched":
        first = k.inputs[0][0]
        lines.append(f"    _out = numpy.empty({batch} + {shape!r})" if batch else
                     f"    _out = numpy.empty(numpy.shape({first})[:-1] + {shape!r})")
        for idx, expr in enumerate(reduced):
            pos = numpy_index(idx, shape)
            lines.append(f"    _out[..., {pos}] = {printer.doprint(expr)}")
        lines.append("    return _out")
    else:
        vals = [printer.doprint(e) for e in reduced]
        if k.flavour == "arb":
            # a constant output is a ball too (as every other output), not a Python int
            vals = [f"_A({v})" if e.is_Number else v for v, e in zip(vals, reduced)]
        if len(shape) == 1:
            lines.append("    return [" + ", ".join(vals) + "]")
        else:
            rows = []
            for r in range(shape[0]):
                rows.append("[" + ", ".join(vals[r * shape[1]:(r + 1) * shape[1]]) + "]")
            lines.append("    return [\n        " + ",\n        ".join(rows) + ",\n    ]")
    if k.flavour == "arb" and printer.hoisted:
        if integers is None:
            defs = [f"(_A({p}) / {q})" for p, q in printer.hoisted]
        else:
            defs = [f"_Z[{integers.setdefault(p, len(integers))}] / "
                    f"_Z[{integers.setdefault(q, len(integers))}]" for p, q in printer.hoisted]
        lines[head:head] = [f"    {name} = {d}" for name, d in zip(printer.hoisted.values(),
                                                                    defs)]
    return "\n".join(lines) + "\n"


def numpy_index(flat_index: int, shape: tuple) -> str:
    idx = []
    for dim in reversed(shape):
        idx.append(flat_index % dim)
        flat_index //= dim
    return ", ".join(str(i) for i in reversed(idx))


def module_source(kernels, *, generator: str, doc: str, source_hash: str,
                  constants: dict | None = None, functions=()) -> str:
    """A whole importable module: header, imports, constants and the kernels.

    Parameters
    ----------
    kernels : sequence of Kernel
    generator : str
        The derivation script or function that produced it (named in the header).
    doc : str
        Module docstring body.
    source_hash : str
        :func:`symbolic_hash` of the symbolic source; a stale module shows here.
    constants : dict, optional
        Extra module-level names (``{"L": 8}``), written with ``repr``.
    functions : sequence of (name, str), optional
        Further generated functions as source text (e.g. a magnitude kernel of
        :mod:`.rounding`), appended after the kernels and listed in ``__all__``.
    """
    import mpmath
    import numpy
    import sympy
    flavours = {k.flavour for k in kernels}
    head = [
        f"# GENERATED BY {generator} -- DO NOT EDIT",
        f"# sympy {sympy.__version__}, numpy {numpy.__version__}, mpmath {mpmath.__version__}, "
        f"python {platform.python_version().rsplit('.', 1)[0]}",
        f"# symbolic source sha256: {source_hash}",
        '"""' + doc.strip() + '\n"""',
        "",
    ]
    imports = ["import math"]
    if "batched" in flavours:
        imports.append("import numpy")
    if "exact" in flavours:
        imports.append("from flint import fmpq as _Q")
    if "arb" in flavours:
        imports.append("from flint import arb as _A")
    body = ["", f"SOURCE_SHA256 = {source_hash!r}"]
    for name, value in (constants or {}).items():
        body.append(f"{name} = {value!r}")
    body.append(f"__all__ = {[k.name for k in kernels] + [n for n, _ in functions]!r}")
    integers: dict = {}
    texts = [kernel_source(k, integers) for k in kernels]
    if integers:
        # the arb kernels' rational constants p / q: their integers, exact balls of any
        # size at every precision, built once here (_Z) and divided on each call
        body += ["", "", "def _integers(_A):",
                 '    """The integers of the kernels\' rational constants (each constant is '
                 "_Z[i] / _Z[j],\n    rounded at the caller's precision) as exact numbers "
                 "of the type _A; the\n    module's own, _Z, are arb balls "
                 '(distkin.mechanisms.kinematics_tiers.on_mpmath\n    binds its own)."""',
                 "    return (", *[f"        _A({n})," for n in integers], "    )", "", "",
                 "_Z = _integers(_A)"]
    out = "\n".join(head + imports + body) + "\n"
    for _, text in helpers(kernels):
        out += "\n\n" + text
    for text in texts:
        out += "\n\n" + text
    for _, text in functions:
        out += "\n\n" + text
    return out
