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


def test_an_unusable_cache_folder_is_bad_input(tmp_path, monkeypatch, capsys):
    """QA U 9: DISTKIN_CACHE below a file made ``distkin codegen`` end in an internal
    failure (NotADirectoryError, exit 1); now an InputError naming the variable (exit 2),
    and a default chunk store there hints at it."""
    import pytest

    from distkin.app.cli import main
    from distkin.errors import InputError
    from distkin.runstore import make_store
    (tmp_path / "file").write_text("x")
    bad = tmp_path / "file" / "sub"
    monkeypatch.setenv("DISTKIN_CACHE", str(bad))
    with pytest.raises(InputError, match="writable cache folder") as info:
        cached_source("t", source_key("test", "v2"), lambda: SRC)
    assert info.value.field == "DISTKIN_CACHE"
    with pytest.raises(InputError) as info:
        make_store(bad / "sweeps" / "x")
    assert "set DISTKIN_CACHE" in info.value.hint
    scene = tmp_path / "s.toml"
    scene.write_text('[mechanism]\nkind = "points"\npoints = [[0, 0, 0], [1, 0, 0], '
                     '[0, 1, 0], [0, 0, 1]]\n[[query]]\ntype = "cayley_menger"\n'
                     'determinants = ["D(1,2,3,4)"]\n', encoding="utf-8")
    code = main(["codegen", str(scene), "-o", str(tmp_path / "m.py")])
    err = capsys.readouterr().err
    # QA W 6: refused once, before any work (no derivation, no "cached" line)
    assert code == 2 and err.strip().splitlines() == [
        f"distkin: error: DISTKIN_CACHE: expected a folder for distkin's cache, got "
        f"{str(bad)!r} ({str(tmp_path / 'file')!r} is a file) (hint: set DISTKIN_CACHE to "
        f"a folder that can be written, or unset it)"], err
    assert not (tmp_path / "m.py").exists()
