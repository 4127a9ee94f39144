r"""Rigorous rounding-error bounds of generated polynomial kernels, from their source.

A generated ``scalar`` or ``batched`` kernel (:mod:`.emit`) is straight-line code of
``+``, ``-``, unary ``-`` and ``*`` over its inputs and integer constants.  This module
reads the emitted source itself (Python's :mod:`ast`, so that the analysis is of the
code that runs, in its evaluation order) and gives, for each output :math:`k`, three
numbers and a companion kernel:

* the **depth** :math:`d_k`: the largest number of roundings on a product of factors
  :math:`(1+\delta)` a term can collect, by the recursion
  :math:`d(a\pm b) = \max(d_a, d_b) + 1`, :math:`d(ab) = d_a + d_b + 1`,
  :math:`d(2^j a) = d_a` (an exact scaling, :math:`j \ge 0`), :math:`d(-a) = d_a`,
  :math:`d = 0` at inputs and constants;
* the **degree** :math:`g_k`: the total degree in the inputs (how many rounded inputs a
  term can contain);
* the **underflow allowance** :math:`U_k`: what gradual underflow can add, for inputs of
  modulus at most ``leaf_bound``;
* the **magnitude kernel**: the same code with every subtraction turned into an
  addition, every unary minus dropped, every constant and input replaced by its
  absolute value.  It evaluates the *magnitude* :math:`A_k(x)`, the output's expression
  tree with absolute values throughout.

Theorem (the standard model of floating-point arithmetic, IEEE 754 binary64 with
rounding to nearest, no overflow: :math:`\mathrm{fl}(a\pm b) = (a\pm b)(1+\delta)`,
:math:`\mathrm{fl}(ab) = ab(1+\delta) + \eta`, :math:`|\delta| \le u = 2^{-53}`,
:math:`|\eta| \le 2^{-1075}`, sums of floats in the subnormal range are exact; Higham,
*Accuracy and Stability of Numerical Algorithms*, 2nd ed., SIAM 2002, Sec. 2.2 and
Lemma 3.1).  If the kernel runs on floats :math:`\hat x_i = x_i(1+\epsilon_i)`,
:math:`|\epsilon_i| \le \eta_x`, :math:`|x_i| \le` ``leaf_bound``, its computed output
:math:`\hat y_k` satisfies

.. math:: |\hat y_k - y_k(x)| \le \big[(1+u)^{d_k}(1+\eta_x)^{g_k} - 1\big]\,A_k(x) + U_k,
          \qquad A_k(x) \le (1+\eta_x)^{g_k}\,\frac{\hat A_k + U_k}{(1-u)^{d_k}},

with :math:`\hat A_k` the magnitude kernel's computed value at :math:`\hat x`.  Proof:
by induction over the code, every computed node equals
:math:`\sum_m c_m\,m(x)\,\Theta_m + E` summed over the terms :math:`c_m\,m(x)` of the
node's formal expansion (without cancellation), each :math:`\Theta_m` a product of at
most :math:`d` factors :math:`1+\delta` and :math:`g` factors :math:`1+\epsilon_i`, and
:math:`|E|` at most the node's underflow allowance, propagated as
:math:`U(a\pm b) = 2(U_a + U_b)`,
:math:`U(ab) = 2(2B_aU_b + 2B_bU_a + U_aU_b) + 2^{-1074}` with :math:`B` the magnitude
at inputs of modulus ``leaf_bound`` (the factors 2 cover :math:`(1+u)^d \le 2`).  The
magnitude kernel has no subtraction, so its computed value is
:math:`A(\hat x)\,\Theta + E` with :math:`\Theta \ge (1-u)^{d}`, and :math:`A` is
monotone in :math:`|x_i|`.  Fused multiply-adds (which numba does not emit without
``fastmath``) would only remove roundings, never add one; numpy's element-wise
arithmetic rounds each operation once.

Anything else in the source (division, powers, function calls) is refused: the
analysis raises rather than bound what it does not model.
"""

from __future__ import annotations

import ast
import math
from dataclasses import dataclass
from fractions import Fraction

__all__ = ["Bounds", "analyse", "magnitude_source"]

_TINY_MUL = Fraction(1, 2 ** 1074)      # 2 x the largest underflow error of one product


@dataclass(frozen=True)
class Bounds:
    """The rounding constants of the outputs of one kernel (see the module docstring).

    Attributes
    ----------
    depth, degree : tuple of int, one per output
    underflow : tuple of float, one per output (rounded up)
    """

    depth: tuple
    degree: tuple
    underflow: tuple


@dataclass(frozen=True)
class _Node:
    depth: int
    degree: int
    big: int | Fraction        # magnitude at inputs of modulus leaf_bound
    under: Fraction            # underflow allowance


def _pow2(value) -> bool:
    """A non-negative power of two, or 1 (exact scaling)."""
    v = abs(value)
    return isinstance(v, int) and v >= 1 and v & (v - 1) == 0


class _Walker:
    def __init__(self, leaves: set, leaf_bound):
        self.env = {}
        self.leaves = leaves
        self.leaf = Fraction(leaf_bound)

    def node(self, e) -> _Node:
        if isinstance(e, ast.Name):
            if e.id in self.env:
                return self.env[e.id]
            raise ValueError(f"unknown name {e.id!r} in a generated kernel")
        if isinstance(e, ast.Constant):
            v = e.value
            if isinstance(v, bool) or not isinstance(v, int) or abs(v) >= 2 ** 53:
                raise ValueError(f"expected an integer constant below 2^53, got {v!r}")
            return _Node(0, 0, abs(v), Fraction(0))
        if isinstance(e, ast.UnaryOp) and isinstance(e.op, (ast.USub, ast.UAdd)):
            return self.node(e.operand)
        if isinstance(e, ast.BinOp) and isinstance(e.op, (ast.Add, ast.Sub)):
            a, b = self.node(e.left), self.node(e.right)
            return _Node(max(a.depth, b.depth) + 1, max(a.degree, b.degree), a.big + b.big,
                         2 * (a.under + b.under))
        if isinstance(e, ast.BinOp) and isinstance(e.op, ast.Mult):
            for c, other in ((e.left, e.right), (e.right, e.left)):
                if isinstance(c, ast.Constant) and _pow2(c.value):
                    o = self.node(other)
                    k = abs(c.value)
                    return _Node(o.depth, o.degree, k * o.big, k * o.under)
            a, b = self.node(e.left), self.node(e.right)
            return _Node(a.depth + b.depth + 1, a.degree + b.degree, a.big * b.big,
                         2 * (2 * a.big * b.under + 2 * b.big * a.under + a.under * b.under)
                         + _TINY_MUL)
        raise ValueError(f"the rounding analysis models + - * only, got {ast.unparse(e)!r}")

    def leaf_node(self) -> _Node:
        return _Node(0, 1, self.leaf, Fraction(0))


def _function(source: str, name: str) -> ast.FunctionDef:
    tree = ast.parse(source)
    for f in tree.body:
        if isinstance(f, ast.FunctionDef) and f.name == name:
            return f
    raise ValueError(f"no function {name!r} in the source")


def _is_input(value, args) -> bool:
    """``sides[0]`` or ``sides[..., 0]``: an input component."""
    return (isinstance(value, ast.Subscript) and isinstance(value.value, ast.Name)
            and value.value.id in args)


def _outputs(f: ast.FunctionDef):
    """The output expressions in order: ``return [...]`` (scalar) or the
    ``_out[..., k] = expr`` statements (batched)."""
    outs = []
    for st in f.body:
        if isinstance(st, ast.Return) and isinstance(st.value, ast.List):
            return list(st.value.elts)
        if (isinstance(st, ast.Assign) and isinstance(st.targets[0], ast.Subscript)
                and isinstance(st.targets[0].value, ast.Name)
                and st.targets[0].value.id == "_out"):
            outs.append(st.value)
    if not outs:
        raise ValueError(f"no outputs found in {f.name}")
    return outs


def analyse(source: str, name: str, *, leaf_bound=1, outputs=None) -> Bounds:
    """The rounding constants of function ``name`` in ``source`` (module docstring).

    Parameters
    ----------
    source : str
        Emitted source (:func:`.emit.kernel_source` or a whole module).
    name : str
        The function.
    leaf_bound : number
        A bound on the modulus of every input (for the underflow allowance only).
    outputs : sequence of int, optional
        The outputs to report (default all).
    """
    f = _function(source, name)
    args = {a.arg for a in f.args.args}
    w = _Walker(args, leaf_bound)
    for st in f.body:
        if (isinstance(st, ast.Assign) and isinstance(st.targets[0], ast.Name)
                and st.targets[0].id != "_out"):
            target = st.targets[0].id
            w.env[target] = w.leaf_node() if _is_input(st.value, args) else w.node(st.value)
    nodes = [w.node(e) for e in _outputs(f)]
    if outputs is not None:
        nodes = [nodes[i] for i in outputs]

    return Bounds(tuple(n.depth for n in nodes), tuple(n.degree for n in nodes),
                  tuple(_up(n.under) for n in nodes))


def _up(q: Fraction) -> float:
    """The smallest float not below q."""
    x = float(q)
    return x if Fraction(x) >= q else math.nextafter(x, math.inf)


class _Magnitude(ast.NodeTransformer):
    def visit_BinOp(self, node):
        self.generic_visit(node)
        if isinstance(node.op, ast.Sub):
            node.op = ast.Add()
        return node

    def visit_UnaryOp(self, node):
        self.generic_visit(node)
        if isinstance(node.op, (ast.USub, ast.UAdd)):
            return node.operand
        return node

    def visit_Constant(self, node):
        if isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
            return ast.copy_location(ast.Constant(abs(node.value)), node)
        return node


def magnitude_source(source: str, name: str, new_name: str, doc: str, *,
                     outputs=None, into: bool = False) -> str:
    """The magnitude kernel of function ``name`` (module docstring), as source text of a
    function ``new_name`` returning a list of the selected ``outputs`` (default all);
    assignments no selected output needs are dropped.  ``into``: the function takes one
    argument more, ``_out``, and writes the outputs into it (``_out[i] = ...``) instead
    of returning a list (numba builds a list of floats element by element, issue 17)."""
    f = _function(source, name)
    args = {a.arg for a in f.args.args}
    outs = _outputs(f)
    if outputs is not None:
        outs = [outs[i] for i in outputs]
    assigns = [st for st in f.body if isinstance(st, ast.Assign)
               and isinstance(st.targets[0], ast.Name) and st.targets[0].id != "_out"]
    need = {n.id for e in outs for n in ast.walk(e) if isinstance(n, ast.Name)}
    keep = []
    for st in reversed(assigns):
        if st.targets[0].id in need:
            keep.append(st)
            need |= {n.id for n in ast.walk(st.value) if isinstance(n, ast.Name)}
    body = []
    for st in reversed(keep):
        if _is_input(st.value, args):
            value = ast.Call(ast.Name("abs", ast.Load()), [st.value], [])
        else:
            value = _Magnitude().visit(st.value)
        body.append(ast.Assign([st.targets[0]], value, lineno=0))
    fargs = f.args
    if into:
        for i, e in enumerate(outs):
            target = ast.Subscript(ast.Name("_out", ast.Load()), ast.Constant(i), ast.Store())
            body.append(ast.Assign([target], _Magnitude().visit(e), lineno=0))
        fargs = ast.arguments(posonlyargs=[], args=f.args.args + [ast.arg("_out")],
                              kwonlyargs=[], kw_defaults=[], defaults=[])
    else:
        body.append(ast.Return(ast.List([_Magnitude().visit(e) for e in outs], ast.Load())))
    fn = ast.FunctionDef(new_name, fargs, body, [], lineno=0)
    head, _, rest = ast.unparse(ast.fix_missing_locations(fn)).partition("\n")
    return (head + '\n    """' + doc.strip().replace("\n", "\n    ") + '\n    """\n'
            + rest + "\n")
