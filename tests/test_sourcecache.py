"""The derived-source cache trusts a file only when it matches the digest written with it
(QA round E: an emptied or truncated cached kernel module was loaded, giving
AttributeError or kernels returning None)."""

from __future__ import annotations

from pathlib import Path

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


#: a process asking for the entry "t" of a slow build: prints BUILD when it builds,
#: WAIT when it waits for another process, then the path and whether it was a hit
_DERIVER = """
import sys, time
from pathlib import Path
from distkin.sourcecache import cached_source, source_key
marker = Path(sys.argv[1])

def build():
    print("BUILD", flush=True)
    marker.write_text("building")
    time.sleep(float(sys.argv[2]))
    return "def f(x):\\n    return 2 * x\\n"

path, hit = cached_source("t", source_key("concurrent"), build,
                          on_wait=lambda: print("WAIT", flush=True))
print(path, hit, flush=True)
"""


def _deriver(tmp_path, seconds):
    import os
    import subprocess
    import sys
    env = {**os.environ, "DISTKIN_CACHE": str(tmp_path / "cache"),
           "PYTHONPATH": os.pathsep.join(sys.path)}
    return subprocess.Popen([sys.executable, "-c", _DERIVER, str(tmp_path / "building"),
                             str(seconds)], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


def _wait_for(path, timeout=60.0):
    import time
    t0 = time.monotonic()
    while not path.exists():
        assert time.monotonic() - t0 < timeout, "the first process never started building"
        time.sleep(0.02)


def test_two_processes_derive_a_missing_entry_once(tmp_path):
    """QA: the two workers of ``certify_hexa.toml`` (workers = 2) each printed "deriving
    ... once" and derived the same kernels: the second now waits for the first (the
    entry's lock) and loads its file."""
    import sys
    if sys.platform == "win32":
        import pytest
        pytest.skip("no fcntl: concurrent processes may derive twice")
    first = _deriver(tmp_path, 2.0)
    _wait_for(tmp_path / "building")          # the first holds the lock, mid-build
    second = _deriver(tmp_path, 2.0)
    out1, err1 = first.communicate(timeout=120)
    out2, err2 = second.communicate(timeout=120)
    assert first.returncode == 0 and second.returncode == 0, err1 + err2
    lines1, lines2 = out1.split(), out2.split()
    assert lines1[0] == "BUILD" and lines1[-1] == "False"
    assert lines2[0] == "WAIT" and lines2[-1] == "True" and "BUILD" not in lines2
    assert lines1[1] == lines2[1]                # one file, the same for both
    path = tmp_path / "cache" / lines1[1].rsplit("/", 1)[-1]
    assert load_module_file(path).f(21) == 42


def test_a_process_waiting_for_the_lock_can_be_interrupted(tmp_path):
    """Ctrl-C while another process derives the entry ends the waiting process (a
    KeyboardInterrupt, not a hang); the holder still finishes and stores its module."""
    import signal
    import sys
    import time
    if sys.platform == "win32":
        import pytest
        pytest.skip("no fcntl")
    first = _deriver(tmp_path, 6.0)
    _wait_for(tmp_path / "building")
    second = _deriver(tmp_path, 6.0)
    assert second.stdout.readline().strip() == "WAIT"
    t0 = time.monotonic()
    second.send_signal(signal.SIGINT)
    _, err2 = second.communicate(timeout=30)
    assert time.monotonic() - t0 < 3.0 and "KeyboardInterrupt" in err2
    out1, _ = first.communicate(timeout=120)
    assert out1.split()[-1] == "False"


def test_the_default_cache_folder_is_named_as_such(tmp_path):
    """QA pkg 7: with DISTKIN_CACHE unset and HOME unusable, each query's line said
    ``query[0].HOME: expected a writable cache folder ...``; the field is the setting
    that names the cache folder, and the message says where the default came from."""
    import os
    import subprocess
    import sys
    root = Path(__file__).resolve().parents[1]
    home = tmp_path / "home"
    home.write_text("a file, not a folder")
    env = {k: v for k, v in os.environ.items() if k not in ("DISTKIN_CACHE", "XDG_CACHE_HOME")}
    env.update(HOME=str(home), PYTHONPATH=str(root) + os.pathsep + env.get("PYTHONPATH", ""))
    proc = subprocess.run([sys.executable, "-m", "distkin", "run",
                           str(root / "examples" / "gough_stewart_6ups.toml")],
                          capture_output=True, text=True, env=env, cwd=tmp_path, timeout=300)
    assert proc.returncode == 2, proc.stderr
    lines = [ln for ln in proc.stderr.splitlines() if "cache folder for the derived" in ln]
    assert lines, proc.stderr
    for line in lines:
        assert ".HOME:" not in line
        assert ".DISTKIN_CACHE: expected a writable cache folder for the derived kernels, got " \
               f"{str(home / '.cache' / 'distkin')!r}" in line
        assert f"DISTKIN_CACHE is not set, so the cache folder is ~/.cache/distkin, " \
               f"HOME={str(home)!r}" in line
