"""The derived-source cache trusts a file only when it matches the digest written with it
(QA round E: an emptied or truncated cached kernel module was loaded, giving
AttributeError or kernels returning None)."""

from __future__ import annotations

from distkin.sourcecache import cached_source, load_module_file, source_key

SRC = "def f(x):\n    return 2 * x\n"


def test_a_damaged_cached_source_is_derived_again(tmp_path, monkeypatch):
    monkeypatch.setenv("DISTKIN_CACHE", str(tmp_path))
    calls = []

    def build():
        calls.append(1)
        return SRC

    key = source_key("test", "v1")
    path, hit = cached_source("t", key, build)
    assert not hit and len(calls) == 1
    assert cached_source("t", key, build) == (path, True) and len(calls) == 1
    for damage in (SRC[:17], "", SRC + "x = 1\n"):
        path.write_text(damage, encoding="utf-8")
        again, hit = cached_source("t", key, build)
        assert again == path and not hit
        assert path.read_text(encoding="utf-8") == SRC
    assert len(calls) == 4
    assert load_module_file(path).f(21) == 42
    path.with_suffix(".sha256").unlink()          # no digest (an older cache): derived again
    assert cached_source("t", key, build)[1] is False and len(calls) == 5
