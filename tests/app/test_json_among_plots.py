"""``--json`` never lands on a file a query writes into the ``--plots`` folder (QA 23 D2:
``distkin run examples/rus8_device.toml --json P/q3_performance_tables.json --plots P``
replaced the performance query's table; ``check_apart`` let any non-PNG name through).

The files are those a real run writes: the test runs the device's performance query
with ``--plots`` and tries every file it wrote as ``--json``."""

import json
from pathlib import Path

from distkin.app.cli import main

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "rus8_device.toml"


def _performance_only(tmp_path) -> Path:
    text = EXAMPLE.read_text(encoding="utf-8")
    head, _, rest = text.partition("[[query]]")
    perf = "[[query]]" + rest[rest.index("type = \"performance\"") - 1:]
    perf = perf[:perf.index("[[query]]", 1)] if "[[query]]" in perf[1:] else perf
    scene = tmp_path / "rus8_perf.toml"
    scene.write_text(head + perf + f'store = "{tmp_path / "store"}"\n', encoding="utf-8")
    return scene


def test_json_refused_on_every_file_a_query_wrote_in_the_plots_folder(tmp_path, capsys):
    scene = _performance_only(tmp_path)
    plots = tmp_path / "plots"
    assert main(["run", str(scene), "--plots", str(plots), "--no-progress"]) == 0
    written = sorted(p for p in plots.iterdir())
    assert any(p.suffix == ".json" for p in written)     # the tables, beside the PNGs
    before = {p: p.read_bytes() for p in written}
    capsys.readouterr()
    for target in written:
        code = main(["run", str(scene), "--json", str(target), "--plots", str(plots),
                     "--no-progress"])
        err = capsys.readouterr().err.strip().splitlines()
        assert code == 2 and len(err) == 1, (target, err)
        assert err[0].startswith("distkin: error: --json: ") and "--plots" in err[0]
        assert str(target) in err[0]
    assert {p: p.read_bytes() for p in written} == before
    # another name in the folder is still fine
    assert main(["run", str(scene), "--json", str(plots / "r.json"), "--plots",
                 str(plots), "--no-progress"]) == 0
    assert json.loads((plots / "r.json").read_text())["queries"][0]["type"] == "performance"
