"""The forward_kinematics query of an octahedral leg table (Rojas et al. Fig. 4: three
base and three platform points, each on two legs) reports every assembly mode of the
exact octic, as the Python API's ``fk.modes`` holds them (QA 2026-11-29: the API held
16, the report and the JSON none).  Reference: numpy's leg lengths |R p + x - b| at
every reported mode against the scene's legs."""

from __future__ import annotations

import json

import numpy as np

from distkin.app.cli import main
from distkin.spatial import rotation_matrix

BASE = [(200.0, 0.0), (200.0, 0.0), (-100.0, 173.20508075688775), (-100.0, 173.20508075688775),
        (-100.0, -173.20508075688767), (-100.0, -173.20508075688767)]
PLAT = [(50.0, 86.60254037844386), (50.0, -86.60254037844386), (50.0, 86.60254037844386),
        (-100.0, 0.0), (-100.0, 0.0), (50.0, -86.60254037844386)]
LEGS = [311.69582216376295, 290.5426311726739, 307.2938651712411, 303.935374261522,
        298.2108045283888, 314.92636325270774]


def test_every_assembly_mode_is_reported(tmp_path, capsys):
    legs = "".join(f'[[mechanism.leg]]\ntype = "SPS"\nbase = [{b[0]!r}, {b[1]!r}, 0]\n'
                   f'platform = [{p[0]!r}, {p[1]!r}, 0]\nrange = [100, 500]\n'
                   for b, p in zip(BASE, PLAT))
    f = tmp_path / "s.toml"
    f.write_text('[units]\nlength = "mm"\nangle = "deg"\n[mechanism]\nkind = "legs"\n'
                 'name = "octa33"\nhome = [0, 0, 250, 0, 0, 0]\n' + legs
                 + f'[[query]]\ntype = "forward_kinematics"\nangles = {LEGS!r}\n'
                   'guess = [0, 0, 250, 0, 0, 0]\n')
    assert main(["run", str(f), "--json", str(tmp_path / "o.json")]) == 0
    out = capsys.readouterr().out
    res = json.loads((tmp_path / "o.json").read_text())["queries"][0]["result"]
    modes = np.array(res["modes"])
    assert res["unit"]["modes"] == "m, rad" and modes.shape[1] == 6 and len(modes) >= 2
    assert f"assembly modes (exact octic, Rojas et al. eq. (3)): {len(modes)}" in out
    b = np.c_[np.array(BASE), np.zeros(6)] / 1e3
    p = np.c_[np.array(PLAT), np.zeros(6)] / 1e3
    for x in modes:                                 # each mode closes every leg
        lengths = np.linalg.norm(p @ rotation_matrix(x[3:]).T + x[:3] - b, axis=1)
        np.testing.assert_allclose(lengths * 1e3, LEGS, rtol=1e-9)
    assert np.isclose(np.linalg.norm(modes - np.array(res["pose"]), axis=1), 0,
                      atol=1e-9).any()              # the polished pose is one of them
