"""``python -m benchmarks`` keeps what it wrote (QA 8): a multi-section run wrote each
BENCHMARKS.md section as it finished but results.json and its run-log entry only at the
end, so an interrupted or failed run lost the numbers of the sections already in
BENCHMARKS.md, and Ctrl-C or an exception printed a traceback.  Fake section modules
stand in for the real benchmarks (none is run); the reference is what they returned."""

from __future__ import annotations

import json
import re
import types

import pytest

import benchmarks.__main__ as bm

INFO = {"python": "3.x", "platform": "test", "cpu_count": 1, "processor": "cpu",
        "numpy": "1", "scipy": "1", "sympy": "1", "mpmath": "1", "python-flint": "1",
        "numba": "1", "argv": "test"}


def _fake(tmp_path, monkeypatch, raises=None):
    """Sections a, b, c (b raises ``raises`` if given); BENCHMARKS.md and results.json in
    ``tmp_path``.  Returns the data each section returned."""
    returned = {}

    def section(name):
        def run():
            if name == "b" and raises is not None:
                raise raises
            returned[name] = {"value": len(returned) + 1.5, "name": name}
            return f"table of {name}", returned[name]
        return types.SimpleNamespace(TITLE=f"Section {name}", DEFAULT=True, run=run)
    mods = {n: section(n) for n in "abc"}
    monkeypatch.setattr(bm, "MD", tmp_path / "BENCHMARKS.md")
    monkeypatch.setattr(bm, "JSON", tmp_path / "results.json")
    monkeypatch.setattr(bm, "modules", lambda: sorted(mods))
    monkeypatch.setattr(bm, "section_module", lambda n: mods[n])
    monkeypatch.setattr(bm, "machine", lambda: dict(INFO))
    return returned


def _sections_in_md(tmp_path):
    md = (tmp_path / "BENCHMARKS.md").read_text(encoding="utf-8")
    return sorted(set(re.findall(r"<!-- begin (\w+) -->", md)) - {"run"})


@pytest.mark.parametrize("raises, code, word", [(KeyboardInterrupt(), 130, "interrupted"),
                                                (ValueError("bad\nnumber"), 1, "failed")])
def test_a_stopped_run_keeps_the_numbers_of_the_sections_it_wrote(
        tmp_path, monkeypatch, capsys, raises, code, word):
    returned = _fake(tmp_path, monkeypatch, raises)
    assert bm.main([]) == code
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert "'b'" in err and word in err
    results = json.loads((tmp_path / "results.json").read_text(encoding="utf-8"))
    # every section in BENCHMARKS.md has its numbers in results.json, and only those
    assert _sections_in_md(tmp_path) == sorted(returned) == ["a"]
    assert {k: v["data"] for k, v in results.items() if k != "_last_run"} == returned
    assert list(results["_last_run"]["ran"]) == ["a"]
    md = (tmp_path / "BENCHMARKS.md").read_text(encoding="utf-8")
    assert f"stopped in `b` ({word}" in md


def test_results_are_written_after_each_section(tmp_path, monkeypatch, capsys):
    """When section b runs, a's numbers are already in results.json."""
    returned = _fake(tmp_path, monkeypatch)
    seen = {}
    real = bm.section_module

    def spy(name):
        if name == "b" and (tmp_path / "results.json").exists():
            seen.update(json.loads((tmp_path / "results.json").read_text(encoding="utf-8")))
        return real(name)
    monkeypatch.setattr(bm, "section_module", spy)
    assert bm.main([]) == 0
    assert seen["a"]["data"] == returned["a"]
    results = json.loads((tmp_path / "results.json").read_text(encoding="utf-8"))
    assert {k: v["data"] for k, v in results.items() if k != "_last_run"} == returned


def test_one_log_entry_per_run(tmp_path, monkeypatch, capsys):
    """Writing the entry after each section replaces the run's own entry: two runs of
    three sections give the entries (1) and (2), each naming its three sections."""
    _fake(tmp_path, monkeypatch)
    assert bm.main([]) == 0
    assert bm.main(["a", "c"]) == 0
    log = bm._run_block()
    assert re.findall(r"\((\d+)\) `python -m benchmarks", log) == ["1", "2"]
    assert log.count("`a` ") == 2 and log.count("`b` ") == 1 and log.count("`c` ") == 2
