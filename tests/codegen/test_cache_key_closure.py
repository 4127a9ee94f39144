"""The derivation cache's key covers every distkin module a generator imports (QA 6: a
hand-kept file list omitted mechanisms/kernel_names.py and codegen/rounding.py, so an
edit of LOOP_KERNELS was served the module cached before it) and the toolchain's
versions (a sympy upgrade must not be served a module whose header names the old one).

The closure is compared with a second route, the import graph of
``tests/test_import_graph.py`` (its own parser); a change is stood in for by
monkeypatching the file reading, so nothing in the package is edited."""

from __future__ import annotations

import importlib.util
import pathlib
from functools import lru_cache
from pathlib import Path

import pytest

import distkin
from distkin import sourcecache
from distkin.codegen import cayley_menger_scene, octahedral_scene, octic, rss

ROOT = Path(distkin.__file__).resolve().parent

GENERATORS = {
    "rss": rss._MODEL_MODULES,
    "octahedral": octahedral_scene._MODEL_MODULES,
    "cayley_menger": cayley_menger_scene._MODEL_MODULES,
    "octic": octic._OCTIC_MODULES,
}


@lru_cache(maxsize=1)
def _graph():
    """(import graph, module -> file) of test_import_graph (parsed once)."""
    spec = importlib.util.spec_from_file_location(
        "_import_graph_for_closure", Path(__file__).resolve().parents[1] / "test_import_graph.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.import_graph(), mod._modules()


def _graph_closure(roots):
    """The transitive closure of ``roots`` in the import graph of test_import_graph."""
    graph, files = _graph()
    seen, todo = set(), list(roots)
    while todo:
        m = todo.pop()
        if m not in seen:
            seen.add(m)
            todo += graph.get(m, ())
    return {files[m].resolve().relative_to(ROOT).as_posix() for m in seen}


@pytest.mark.parametrize("name", sorted(GENERATORS))
def test_the_closure_is_the_import_graphs(name):
    roots = GENERATORS[name]
    assert set(sourcecache.import_closure(roots)) == _graph_closure(roots)


def test_the_closures_hold_the_files_the_lists_forgot():
    assert "mechanisms/kernel_names.py" in sourcecache.import_closure(rss._MODEL_MODULES)
    octa = sourcecache.import_closure(octahedral_scene._MODEL_MODULES)
    assert {"mechanisms/kernel_names.py", "codegen/rounding.py", "codegen/octic.py",
            "delta/transform.py"} <= set(octa)


def _edited(monkeypatch, target):
    """Path.read_text returning ``target``'s text with a line appended."""
    real = pathlib.Path.read_text

    def read_text(self, *args, **kwargs):
        text = real(self, *args, **kwargs)
        if Path(self).resolve() == (ROOT / target).resolve():
            text += "\nLOOP_KERNELS = ('jq_jx',)  # edited\n"
        return text
    monkeypatch.setattr(pathlib.Path, "read_text", read_text)


def test_an_edit_of_kernel_names_changes_the_rss_key(monkeypatch):
    """The key both derived_module and scene_module use (the QA reproduction)."""
    before = rss._model_source_text()
    _edited(monkeypatch, "mechanisms/kernel_names.py")
    assert rss._model_source_text() != before


@pytest.mark.parametrize("name", sorted(GENERATORS))
def test_an_edit_of_any_imported_file_changes_the_key(name, monkeypatch):
    roots = GENERATORS[name]
    files = sourcecache.import_closure(roots)
    before = sourcecache.closure_text(roots)
    for rel in files:
        with monkeypatch.context() as m:
            _edited(m, rel)
            assert sourcecache.closure_text(roots) != before, rel
    assert sourcecache.closure_text(roots) == before


def test_a_sympy_upgrade_changes_the_key(monkeypatch):
    from importlib import metadata
    before = rss._model_source_text()
    real = metadata.version
    monkeypatch.setattr(metadata, "version",
                        lambda d: "99.0" if d == "sympy" else real(d))
    after = rss._model_source_text()
    assert after != before and "sympy 99.0" in after


def test_the_versions_are_those_a_header_names():
    """The key's versions line is the header's second line (emit.module_source), a
    second route to the same versions (imported modules, not distribution metadata)."""
    from distkin.codegen.emit import Kernel, module_source
    import sympy
    x = sympy.Symbol("x")
    src = module_source([Kernel("f", (("x", (x,)),), [x], flavour="scalar")],
                        generator="test", doc="t", source_hash="0" * 64)
    assert src.splitlines()[1] == "# " + sourcecache.toolchain_versions()


def test_the_cached_octic_is_keyed_by_its_closure(tmp_path, monkeypatch):
    """An edit of a file the octic's derivation imports but its former hand-kept list
    (octahedral/octic.py, octahedral/banana.py, codegen/octic.py) omitted is not served
    the octic cached before it."""
    import sympy as sp
    from distkin.octahedral.banana import SIDE_PAIRS
    monkeypatch.setenv("DISTKIN_CACHE", str(tmp_path))
    rel = next(f for f in sourcecache.import_closure(octic._OCTIC_MODULES)
               if f.endswith("exact.py"))
    sides = {p: sp.Integer(100 + 7 * k) for k, p in enumerate(SIDE_PAIRS)}
    fixed = {**sides, (1, 4): 400, (2, 4): 324, (2, 5): 324, (3, 5): 289, (3, 6): 225}
    first = octic.octic_in_legs(fixed)
    octic.octic_in_legs(fixed)
    assert len(list(tmp_path.glob("octic_*.pickle"))) == 1
    _edited(monkeypatch, rel)
    again = octic.octic_in_legs(fixed)
    assert len(list(tmp_path.glob("octic_*.pickle"))) == 2          # derived again
    assert all(sp.expand(a - b) == 0 for a, b in zip(first, again))
