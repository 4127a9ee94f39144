"""The run store (distkin.runstore) keys its chunks by the code version.

The bug this guards: ``distkin demo`` failed on its certified-workspace scene when the
user cache held chunks of that scene made by another version of distkin (the store was
refused as "made for another sweep").  Now the default store is a folder per code
version, with a sub-folder per sweep definition, and a store that the user names is
refused, with a hint, only if another version of the code or another sweep filled it
(never silently mixed).
"""

import json
from importlib import resources

import numpy as np
import pytest

from distkin.app.cli import run_scene
from distkin.errors import InputError
from distkin.runstore import code_version, default_store, run_chunks, user_cache_dir
from distkin.app.scene import loads_scene


def _square(spec):
    return {"y": np.arange(spec) ** 2}


def _plant_foreign_store(folder):
    folder.mkdir(parents=True)
    (folder / "sweep.json").write_text(json.dumps(
        {"key": "0123456789abcdef", "code": "0.0.0-000000000000", "chunks": 8}))
    np.savez(folder / "chunk_00000.npz", lo=np.zeros(3))


def test_code_version_names_the_package_version_and_a_source_hash():
    from distkin import __version__
    version, _, digest = code_version().rpartition("-")
    assert version == __version__ and len(digest) == 12
    int(digest, 16)


def test_default_store_is_one_folder_per_code_version(tmp_path, monkeypatch):
    monkeypatch.setenv("DISTKIN_CACHE", str(tmp_path))
    assert user_cache_dir() == tmp_path
    assert default_store("x") == tmp_path / "sweeps" / code_version() / "x"


def test_certify_scene_runs_beside_chunks_of_another_code_version(tmp_path, monkeypatch):
    monkeypatch.setenv("DISTKIN_CACHE", str(tmp_path))
    name = "certify_hunt_certify_workspace"
    _plant_foreign_store(tmp_path / "sweeps" / name)                       # layout before
    _plant_foreign_store(tmp_path / "sweeps" / "0.0.0-000000000000" / name)  # other version
    text = resources.files("distkin.scenes").joinpath("certify_hunt.toml").read_text()
    text = text.replace("workers = 2", "workers = 1")
    scene = loads_scene(text, path=str(tmp_path / "certify_hunt.toml"))
    records, _, worst = run_scene(scene, progress=False)
    assert worst == 0, records[0].get("error")
    # the default store keeps the sweep in a sub-folder named by its definition's key,
    # and the JSON names that sub-folder, where the chunks are (it named the parent)
    metas = list(default_store(name).glob("*/sweep.json"))
    assert len(metas) == 1 and metas[0].parent.name == json.loads(metas[0].read_text())["key"]
    assert records[0]["result"]["store"] == str(metas[0].parent)
    assert len(list(metas[0].parent.glob("chunk_*.npz"))) == json.loads(
        metas[0].read_text())["chunks"]


def test_a_named_store_filled_by_other_code_is_refused(tmp_path):
    store = tmp_path / "store"
    first = run_chunks(_square, [2, 3], store, definition={"n": 2}, progress=False)
    again = run_chunks(_square, [2, 3], store, definition={"n": 2}, progress=False)
    assert [r["y"].tolist() for r in again] == [r["y"].tolist() for r in first]
    meta = json.loads((store / "sweep.json").read_text())
    assert meta["code"] == code_version()
    meta["code"] = "0.0.0-000000000000"
    (store / "sweep.json").write_text(json.dumps(meta))
    with pytest.raises(InputError, match="made by this code"):
        run_chunks(_square, [2, 3], store, definition={"n": 2}, progress=False)


def _mixed(spec):
    """A chunk of arrays of several dtypes and shapes (a study chunk's are ~100 arrays
    of per-position values; the certified workspace's have other shapes)."""
    rng = np.random.default_rng(spec)
    out = {f"q{i}_min": rng.random(5) for i in range(6)}
    out |= {"n_ok": np.arange(5), "argmin": np.arange(5) - 1, "box": rng.random((4, 6)),
            "flag": np.array([True, False, True]), "empty": np.zeros(0), "total": 2.5,
            "label": np.array(["a", "bc"])}
    return out


def test_chunks_written_stacked_load_back_bit_for_bit(tmp_path):
    """Arrays of one dtype and shape are stored stacked (one zip entry); a resumed sweep
    loads every array back with its name, dtype, shape and bits, in the task's order."""
    specs = [1, 2, 3]
    first = run_chunks(_mixed, specs, tmp_path, progress=False)
    again = run_chunks(_mixed, specs, tmp_path, progress=False)     # all from disk
    with np.load(tmp_path / "chunk_00000.npz") as z:
        assert len(z.files) < len(first[0])                         # stacked
    for a, b in zip(first, again):
        assert list(a) == list(b)
        for k in a:
            x = np.asarray(a[k])
            assert b[k].dtype == x.dtype and b[k].shape == x.shape, k
            assert np.array_equal(b[k], x), k


_CERT = """
[units]
length = "mm"
angle = "deg"
[mechanism]
kind = "rss"
preset = "hunt"
[[query]]
type = "certify_workspace"
region = {{ lower = [0, 0, 300, 0, 0, 0], upper = [{x}, 0, 300, 0, 0, 0] }}
workers = 1
"""


def test_default_store_is_keyed_by_the_sweep_definition(tmp_path, monkeypatch, capsys):
    """The default store was keyed by the scene file's name and the query type only: an
    edited scene (or another scene of the same name) exited 2 with "expected a chunk
    store made for this sweep".  Now a changed sweep starts its own store and an
    unchanged one resumes from it."""
    from distkin.app.cli import main
    monkeypatch.setenv("DISTKIN_CACHE", str(tmp_path / "cache"))
    scene = tmp_path / "s.toml"
    out = tmp_path / "out.json"

    def run(x):
        scene.write_text(_CERT.format(x=x), encoding="utf-8")
        code = main(["sweep", str(scene), "--no-progress", "--json", str(out)])
        assert code == 0, capsys.readouterr().err
        return json.loads(out.read_text())["queries"][0]["result"]

    first = run(10)
    second = run(20)                                  # same file name, another region
    assert second["region"]["upper"][0] == pytest.approx(0.020)
    again = run(10)                                   # the first sweep, unchanged
    assert again["chunks_resumed"] == again["chunks"] == first["chunks"]
    metas = sorted(default_store("s_certify_workspace").glob("*/sweep.json"))
    keys = {json.loads(m.read_text())["key"] for m in metas}
    assert len(metas) == 2 and keys == {m.parent.name for m in metas}


def test_damaged_chunks_are_redone_and_an_unreadable_sweep_json_is_refused(tmp_path):
    """A truncated or empty chunk raised BadZipFile / EOFError though the code meant to
    redo it; a corrupt sweep.json raised JSONDecodeError (QA).  Reference: the chunks of
    an undamaged run."""
    store = tmp_path / "store"
    first = run_chunks(_square, [2, 3, 4], store, definition={"n": 3}, progress=False)
    chunk = store / "chunk_00001.npz"
    whole = chunk.read_bytes()
    for damage in (whole[: len(whole) // 2], b"", b"not a zip file"):
        chunk.write_bytes(damage)
        stats = {}
        again = run_chunks(_square, [2, 3, 4], store, definition={"n": 3}, progress=False,
                           stats=stats)
        assert [r["y"].tolist() for r in again] == [r["y"].tolist() for r in first]
        assert stats["loaded"] == 2                      # the damaged one was computed
    (store / "sweep.json").write_text("{not json")
    with pytest.raises(InputError, match="unreadable.*sweep.json|sweep.json.*unreadable"):
        run_chunks(_square, [2, 3, 4], store, definition={"n": 3}, progress=False)
    assert chunk.exists()                                # nothing was deleted


def test_a_run_without_a_store_computes_every_chunk_in_memory(tmp_path):
    """store=None: the same results as a stored run, nothing written, stats say so."""
    stats = {}
    mem = run_chunks(_square, [2, 3, 4], None, progress=False, stats=stats)
    ref = run_chunks(_square, [2, 3, 4], tmp_path / "s", progress=False)
    assert [r["y"].tolist() for r in mem] == [r["y"].tolist() for r in ref]
    assert stats == {"loaded": 0, "store": None}


def test_two_runs_into_one_store_at_once(tmp_path):
    """Two processes filling the same store: both finish with the right chunks (they
    shared one temporary file name and one crashed with FileNotFoundError; QA)."""
    import subprocess
    import sys
    code = ("import sys, time, numpy as np\n"
            "from distkin.runstore import run_chunks\n"
            "from test_runstore import _slow_square\n"
            "r = run_chunks(_slow_square, list(range(24)), sys.argv[1], definition={'n': 24},"
            " progress=False)\n"
            "assert [int(x['y'][0]) for x in r] == [i * i for i in range(24)]\n")
    env = {**__import__("os").environ,
           "PYTHONPATH": str(__import__("pathlib").Path(__file__).parent)}
    procs = [subprocess.Popen([sys.executable, "-c", code, str(tmp_path / "s")], env=env,
                              stderr=subprocess.PIPE, text=True) for _ in range(2)]
    for p in procs:
        _, err = p.communicate(timeout=600)
        assert p.returncode == 0, err


def _slow_square(x):
    import time
    time.sleep(0.005)
    return {"y": np.array([x * x])}


# ------------------------------------------------------------- worker counts (QA L 7)
def test_an_absurd_worker_count_is_refused_with_exit_2(tmp_path, capsys):
    """--workers 100000 was accepted, and every pending chunk could start an interpreter:
    now refused (exit 2, one line naming --workers and the limit)."""
    from distkin.app.cli import main
    from distkin.argcheck import MAX_WORKERS
    scene = tmp_path / "s.toml"
    scene.write_text('[mechanism]\nkind = "rss"\npreset = "hunt"\n[[query]]\n'
                     'type = "performance"\n', encoding="utf-8")
    assert main(["sweep", str(scene), "--workers", str(MAX_WORKERS + 1), "--no-progress"]) == 2
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert len(err) == 1 and "--workers" in err[0]
    assert f"at most {MAX_WORKERS} worker processes" in err[0]
    assert f"got {MAX_WORKERS + 1}" in err[0]


def test_workers_above_the_cpus_warn_and_the_pool_is_capped_at_the_chunks(tmp_path, capsys):
    """3 chunks on a pool of cpu_count + 2 workers: one warning line on stderr, and never
    more pending chunks (so never more started processes) than chunks."""
    import os

    from distkin.runstore import local_executor, run_chunks
    n = (os.cpu_count() or 1) + 2
    seen = []

    class Spy:
        _max_workers = n

        def __init__(self, ex):
            self.ex = ex

        def submit(self, fn, *a):
            seen.append(len(a))
            return self.ex.submit(fn, *a)

    with local_executor(n) as ex:
        assert ex._max_workers == n
        out = run_chunks(_square, [1, 2, 3], None, executor=Spy(ex), progress=False)
        started = len(ex._processes)               # a process per submitted chunk at most
    assert [o["y"].tolist() for o in out] == [[1], [4], [9]]
    assert len(seen) == 3 and started <= 3
    err = [ln for ln in capsys.readouterr().err.splitlines() if "warning" in ln]
    assert len(err) == 1 and f"{n} worker processes on {n - 2} CPUs" in err[0]


def test_the_pool_s_workers_run_with_worker_env(monkeypatch):
    """The local pool's workers have WORKER_ENV (single-threaded BLAS, docs/design.md §6)
    whatever this process has, and this process keeps its own.  It was set around the
    pool's creation only; the workers start at a submit, and had this process's values."""
    import os

    from distkin.runstore import WORKER_ENV, local_executor
    for k in WORKER_ENV:
        monkeypatch.setenv(k, "7")
    with local_executor(2) as ex:
        seen = {k: ex.submit(os.getenv, k).result() for k in WORKER_ENV}
    assert seen == WORKER_ENV
    assert {k: os.environ[k] for k in WORKER_ENV} == dict.fromkeys(WORKER_ENV, "7")


def _square(x):
    import numpy as np
    return {"y": np.array([x * x])}


def test_a_chunk_copied_from_another_sweep_is_refused_and_genuine_chunks_resume(tmp_path):
    """QA S 1: only sweep.json was checked, so a chunk file copied in from another
    sweep (another definition, or another index of this one) was loaded as this sweep's
    (107 % of a grid reachable).  Every chunk now carries its sweep's key, code version,
    index and count; a foreign one is refused with a hint, nothing is deleted.
    Reference: the chunks each sweep computed itself."""
    a, b = tmp_path / "a", tmp_path / "b"
    mine = run_chunks(_square, [2, 3, 4], a, definition={"n": 3}, progress=False)
    run_chunks(_square, [5, 6, 7], b, definition={"n": 4}, progress=False)
    stats = {}
    again = run_chunks(_square, [2, 3, 4], a, definition={"n": 3}, progress=False,
                       stats=stats)                       # genuine chunks resume
    assert stats["loaded"] == 3
    assert [r["y"].tolist() for r in again] == [r["y"].tolist() for r in mine]
    chunk = a / "chunk_00001.npz"
    for source in (b / "chunk_00001.npz",                 # another sweep, same index
                   a / "chunk_00002.npz"):                # this sweep, another index
        chunk.write_bytes(source.read_bytes())
        planted = chunk.read_bytes()
        with pytest.raises(InputError, match=r"chunk_00001\.npz") as exc:
            run_chunks(_square, [2, 3, 4], a, definition={"n": 3}, progress=False)
        assert exc.value.hint and "delete" in exc.value.hint
        assert chunk.read_bytes() == planted              # refused, not overwritten


def test_a_chunk_without_a_key_is_not_trusted(tmp_path):
    """A chunk written without a stamp (the old format, or by hand) is refused like a
    foreign one: nothing says which sweep made it."""
    from distkin.runstore import _save
    store = tmp_path / "s"
    run_chunks(_square, [2, 3], store, definition={"n": 2}, progress=False)
    _save(store / "chunk_00000.npz", _square(2))          # right data, no stamp
    with pytest.raises(InputError, match="no sweep key"):
        run_chunks(_square, [2, 3], store, definition={"n": 2}, progress=False)


def test_foreign_chunks_in_a_folder_without_sweep_json_exit_2(tmp_path, capsys):
    """QA S 2: a folder emptied of its sweep.json and filled with another sweep's
    chunks (of other shapes) ended in "error (internal): IndexError" (exit 1).  Now the
    chunk stamps refuse it: exit 2, one line naming the chunk, with a hint; no
    sweep.json is written for chunks that are not this sweep's.  Reference: the two
    certify scenes of _CERT (regions of 10 and 20 mm)."""
    from distkin.app.cli import main
    scenes, stores = [], []
    for x in (10, 20):
        scene = tmp_path / f"c{x}.toml"
        scene.write_text(_CERT.format(x=x), encoding="utf-8")
        store = tmp_path / f"st{x}"
        assert main(["sweep", str(scene), "--no-progress", "--store", str(store)]) == 0
        scenes.append(scene)
        stores.append(store)
    capsys.readouterr()
    for f in stores[0].iterdir():
        f.unlink()
    copied = sorted(stores[1].glob("chunk_*.npz"))
    assert copied
    for f in copied:
        (stores[0] / f.name).write_bytes(f.read_bytes())
    code = main(["sweep", str(scenes[0]), "--no-progress", "--store", str(stores[0])])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "internal" not in err and "chunk_00000.npz" in err and "hint" in err
    assert not (stores[0] / "sweep.json").exists()
