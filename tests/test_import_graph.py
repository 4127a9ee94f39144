"""The package's import graph: no cycles, and every arrow runs the documented way.

The graph is read with :mod:`ast` from the source of ``distkin/`` (nothing is
imported).  An arrow ``a -> b`` is any ``import``/``from ... import`` of ``b`` written in
``a``: at module level, and also inside a function or method (a deferred import is still
a dependency; it only runs later).  ``from pkg import name`` counts as an arrow to
``pkg.name`` when that is a module, else to ``pkg``.  ``if TYPE_CHECKING:`` blocks count
too.  Arrows from a module to its own package ``__init__`` (which only re-exports) are
not edges of the cycle check, and neither are arrows *from* a package ``__init__`` to
its own submodules.

The layers, lowest first (docs/design.md, "Import direction"): a module may import its
own layer or a lower one, never a higher one.

0. ground floor: errors, exact numbers and exact root isolation, input checks (TOML
   syntax errors among them),
   spatial maths, units, numbers in messages, the run store (its files, its progress
   bar), the version;
1. geometry;
2. models: the octahedral banana and octic algebra, the RSS descriptions, presets and
   symbolic model (the symbolic parts import sympy inside functions);
3. code generation (``distkin.codegen``) and its committed output (``_generated``);
4. numeric analyses on the generated kernels: the octahedral tiers, indices, certify;
5. control;
6. the application: scenes, queries, reports, plots, the CLI.
"""

from __future__ import annotations

import ast
from collections import defaultdict
from functools import lru_cache
from pathlib import Path

import distkin

ROOT = Path(distkin.__file__).parent

#: (module prefix, layer); the longest matching prefix decides.
LAYERS: dict[str, int] = {
    "distkin": 0,
    "distkin.__main__": 6,
    "distkin._version": 0,
    "distkin.errors": 0,
    "distkin.exact": 0,
    "distkin.exact_roots": 0,
    "distkin.argcheck": 0,
    "distkin.toml_syntax": 0,
    "distkin.spatial": 0,
    "distkin.numfmt": 0,
    "distkin.runstore": 0,
    "distkin.chunkfiles": 0,
    "distkin.progress": 0,
    "distkin.sourcecache": 0,
    "distkin._jitcache": 0,
    "distkin.scenes": 0,
    "distkin.geometry": 1,
    "distkin.octahedral": 4,
    "distkin.octahedral.banana": 2,
    "distkin.octahedral.octic": 2,
    "distkin.delta": 4,
    "distkin.singularity": 4,
    "distkin.mechanisms": 4,
    "distkin.mechanisms.description": 2,
    "distkin.mechanisms.legs": 2,
    "distkin.mechanisms.leg_architecture": 2,
    "distkin.mechanisms.presets": 2,
    "distkin.mechanisms.symbolic": 2,
    "distkin.mechanisms.kernel_names": 2,
    "distkin.mechanisms.reference": 2,
    "distkin.mechanisms.plot": 6,
    "distkin.codegen": 3,
    "distkin._generated": 3,
    "distkin.indices": 4,
    "distkin.indices.plots": 6,
    "distkin.certify": 4,
    "distkin.certify.plot": 6,
    "distkin.control": 5,
    "distkin.app": 6,
}

#: Arrows forbidden although the layers allow them (docs/design.md): the certified
#: tier and the analyses get their run store and root isolation from the ground floor,
#: and nothing outside ``codegen`` derives kernels at run time.
FORBIDDEN: list[tuple[str, str]] = [
    ("distkin.certify", "distkin.indices"),
    ("distkin.indices", "distkin.codegen"),
    ("distkin.control", "distkin.codegen"),
    ("distkin.certify", "distkin.codegen"),
    ("distkin.mechanisms", "distkin.codegen"),   # except the one run-time derivation:
    ("distkin.octahedral", "distkin.codegen"),
    ("distkin.octahedral", "distkin.certify"),
]

#: Arrows that still run against the direction or close a cycle: each one is a
#: recorded defect to remove (the test fails when one of them disappears, so the list
#: only shrinks).
KNOWN: set[tuple[str, str]] = set()


def _modules() -> dict[str, Path]:
    mods = {}
    for path in ROOT.rglob("*.py"):
        parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        mods[".".join(parts)] = path
    return mods


def _targets(mod: str, node, is_pkg: bool, mods) -> list[str]:
    if isinstance(node, ast.Import):
        names = [a.name for a in node.names]
    else:
        if node.level:
            base = mod.split(".") if is_pkg else mod.split(".")[:-1]
            base = base[:len(base) - (node.level - 1)]
            pkg = ".".join(base + ([node.module] if node.module else []))
        else:
            pkg = node.module or ""
        names = [f"{pkg}.{a.name}" if f"{pkg}.{a.name}" in mods else pkg for a in node.names]
    out = []
    for name in names:
        if name.split(".")[0] != "distkin":
            continue
        while name not in mods and "." in name:
            name = name.rsplit(".", 1)[0]
        out.append(name)
    return out


@lru_cache(maxsize=1)
def import_graph() -> dict[str, set[str]]:
    """module -> the distkin modules it imports (module level and deferred)."""
    mods = _modules()
    graph: dict[str, set[str]] = defaultdict(set)
    for mod, path in mods.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        is_pkg = path.name == "__init__.py"
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                for t in _targets(mod, node, is_pkg, mods):
                    if t != mod:
                        graph[mod].add(t)
        graph.setdefault(mod, set())
    return graph


def layer(mod: str) -> int:
    best = max((p for p in LAYERS if mod == p or mod.startswith(p + ".")), key=len)
    return LAYERS[best]


def _is_package_edge(a: str, b: str, graph) -> bool:
    """``a`` imports its own package's ``__init__``, or an ``__init__`` its own part."""
    return a.startswith(b + ".") or b.startswith(a + ".")


def cycles(graph) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]

    def edges(v):
        return [w for w in graph.get(v, ()) if not _is_package_edge(v, w, graph)
                and (v, w) not in KNOWN]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges(v):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def upward(graph) -> list[tuple[str, str]]:
    """Arrows from a lower layer to a higher one."""
    return sorted((a, b) for a, bs in graph.items() for b in bs
                  if layer(b) > layer(a) and not a.startswith(b + ".")
                  and (a, b) not in KNOWN)


def test_graph_is_read():
    g = import_graph()
    # a few arrows that must be seen, module level and deferred
    assert "distkin.errors" in g["distkin.argcheck"]
    assert len(g) > 80


def test_no_import_cycles():
    found = cycles(import_graph())
    assert found == [], "import cycles:\n" + "\n".join(" <-> ".join(c) for c in found)


def test_imports_run_the_documented_direction():
    bad = upward(import_graph())
    assert bad == [], "imports against the direction:\n" + "\n".join(
        f"{a} (layer {layer(a)}) -> {b} (layer {layer(b)})" for a, b in bad)


def _under(mod: str, prefix: str) -> bool:
    return mod == prefix or mod.startswith(prefix + ".")


#: allowed although FORBIDDEN matches: a custom RSS geometry (not a committed preset)
#: has its kernels derived on first use ("model only what a scene requires",
#: docs/design.md), through this one function-level import.
ALLOWED: set[tuple[str, str]] = {("distkin.mechanisms.kernels", "distkin.codegen.rss")}


def forbidden(graph) -> list[tuple[str, str]]:
    return sorted((a, b) for a, bs in graph.items() for b in bs
                  if (a, b) not in KNOWN and (a, b) not in ALLOWED
                  and any(_under(a, x) and _under(b, y) for x, y in FORBIDDEN))


def test_no_forbidden_arrows():
    bad = forbidden(import_graph())
    assert bad == [], "forbidden imports:\n" + "\n".join(f"{a} -> {b}" for a, b in bad)


def test_known_exceptions_still_exist():
    g = import_graph()
    gone = sorted((a, b) for a, b in KNOWN if b not in g.get(a, ()))
    assert gone == [], f"remove these from KNOWN, they are fixed: {gone}"


def test_layer_table_covers_every_module():
    # every module falls under a prefix more specific than the root "distkin" unless
    # it is one of the root's own ground-floor files
    g = import_graph()
    loose = [m for m in g if m.count(".") >= 1 and max(
        (p for p in LAYERS if m == p or m.startswith(p + ".")), key=len) == "distkin"]
    assert loose == [], f"modules with no layer: {loose}"


def test_layer_table_names_only_modules_that_exist():
    # a stale entry (a module renamed or removed) would give a layer to nothing and
    # hide that its successor has none; the dict literal cannot show a duplicate key
    g = import_graph()
    stale = sorted(p for p in LAYERS if p not in g)
    assert stale == [], f"LAYERS names modules that do not exist: {stale}"
    source = Path(__file__).read_text(encoding="utf-8")
    block = source.split("LAYERS: dict[str, int] = {", 1)[1].split("\n}", 1)[0]
    keys = [line.split(":", 1)[0].strip().strip('"') for line in block.splitlines()
            if line.strip().startswith('"')]
    assert len(keys) == len(set(keys)), "LAYERS repeats a key"
