"""Numba caches older than the package's sources are dropped (distkin._jitcache; QA
round E: numba checks the file defining a function, not the files of its callees, so
an edit of a callee kept serving the old machine code).  Run on a stand-in tree."""

from __future__ import annotations

from distkin import _jitcache


def test_caches_are_dropped_when_the_sources_change(tmp_path, monkeypatch):
    pkg = tmp_path / "pkg"
    (pkg / "sub" / "__pycache__").mkdir(parents=True)
    files = [pkg / "sub" / "__pycache__" / "m.f-1.py311.nbi",
             pkg / "sub" / "__pycache__" / "m.f-1.py311.1.nbc"]
    keep = pkg / "sub" / "__pycache__" / "m.cpython-311.pyc"
    for f in files + [keep]:
        f.write_bytes(b"x")
    monkeypatch.setattr(_jitcache, "_ROOT", pkg)
    monkeypatch.setattr(_jitcache, "STAMP", pkg / "__pycache__" / "numba-code-version")
    version = ["v1"]
    monkeypatch.setattr("distkin.runstore.code_version", lambda: version[0])
    assert _jitcache.ensure_fresh() is True                 # no stamp yet: dropped
    assert not any(f.exists() for f in files) and keep.exists()
    for f in files:
        f.write_bytes(b"x")
    assert _jitcache.ensure_fresh() is False                # same sources: kept
    assert all(f.exists() for f in files)
    version[0] = "v2"                                       # a source changed
    assert _jitcache.ensure_fresh() is True
    assert not any(f.exists() for f in files) and keep.exists()
    assert _jitcache.STAMP.read_text().strip() == "v2"
