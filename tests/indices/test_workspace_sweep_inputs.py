"""Bad input to the workspace functions and the GII sweeps is an InputError naming the
argument (QA round H 12, 13): before, a broadcast ValueError, a numba or ufunc error, a
silent count of 0, a NaN design picked as the best, a typo read as an option, or a wrong
volume from an uneven axis.  Valid input keeps the analytic values (the Table II cube's
3375 cm³, the brute-force GII)."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.indices.design import design_sigmas
from distkin.indices.isotropy import brute_force_sweep, culling_sweep, gii
from distkin.indices.workspace import (PoseGrid, axis_values, design_criteria,
                                       dexterous_workspace, table2_grid)

G = table2_grid()
N = G.n_positions
ONES = np.ones(N, bool)
MINS = {"velocity": np.full(N, 2.0), "acceleration": np.full(N, 100.0),
        "force": np.full(N, 5.0)}
RNG = np.random.default_rng(2)
LO, HI = RNG.uniform(0.1, 1, (5, 12)), RNG.uniform(1, 3, (5, 12))


def _ev(designs, poses):
    return LO[np.ix_(designs, poses)], HI[np.ix_(designs, poses)]


def _nan_ev(designs, poses):
    lo, hi = _ev(designs, poses)
    return np.where(lo > 0.5, np.nan, lo), hi


BAD = [
    ("reachable_all length", lambda: dexterous_workspace(G, np.ones(10, bool), MINS,
                                                         {"velocity": 1.0}), "reachable_all"),
    ("minima length", lambda: dexterous_workspace(G, ONES, {"velocity": np.ones(10)},
                                                  {"velocity": 1.0}), "minima.velocity"),
    ("threshold NaN", lambda: dexterous_workspace(G, ONES, MINS, {"velocity": np.nan}),
     "thresholds.velocity"),
    ("threshold text", lambda: dexterous_workspace(G, ONES, MINS, {"velocity": "1"}),
     "thresholds.velocity"),
    ("criteria without acceleration",
     lambda: design_criteria(8, G, ONES, {"velocity": MINS["velocity"],
                                          "force": MINS["force"]}), "minima"),
    ("axis step NaN", lambda: axis_values(0, 1, np.nan), "grid"),
    ("axis min NaN", lambda: axis_values(np.nan, 1, 0.1), "grid"),
    ("axis max inf", lambda: axis_values(0, np.inf, 0.1), "grid"),
    ("grid uneven", lambda: PoseGrid((0.0, 0.01, 0.03), (0.0,), (0.3,), (0.0,), (0.0,),
                                     (0.0,)), "grid.x"),
    ("grid descending", lambda: PoseGrid((0.02, 0.01, 0.0), (0.0,), (0.3,), (0.0,), (0.0,),
                                         (0.0,)), "grid.x"),
    ("grid empty", lambda: PoseGrid((), (0.0,), (0.3,), (0.0,), (0.0,), (0.0,)), "grid.x"),
    ("gii lengths", lambda: gii([0.1, 0.2, 0.3], [2.0]), "smax"),
    ("gii NaN", lambda: gii([0.1, np.nan], [1.0, 2.0]), "smin"),
    ("culling seed empty", lambda: culling_sweep(_ev, 5, 12, seed_poses=[]), "seed_poses"),
    ("culling seed out of range", lambda: culling_sweep(_ev, 5, 12, seed_poses=[5, 100]),
     "seed_poses"),
    ("culling seed negative", lambda: culling_sweep(_ev, 5, 12, seed_poses=[-1]),
     "seed_poses"),
    ("culling block 0", lambda: culling_sweep(_ev, 5, 12, block=0), "block"),
    ("brute block 0", lambda: brute_force_sweep(_ev, 5, 12, block=0), "block"),
    ("culling NaN σ", lambda: culling_sweep(_nan_ev, 5, 12), "evaluate"),
    ("brute NaN σ", lambda: brute_force_sweep(_nan_ev, 5, 12), "evaluate"),
]


@pytest.mark.parametrize("what, call, field", BAD, ids=[b[0] for b in BAD])
def test_bad_input_names_the_argument(what, call, field):
    with pytest.raises(InputError) as err:
        call()
    assert err.value.field == field and f"{field}: expected " in str(err.value)


def test_an_unreachable_option_typo_is_refused(presets):
    P = np.array([[0, 0, 0.3, 0, 0, 0.0], [0, 0, 2.0, 0, 0, 0.0]])
    with pytest.raises(InputError) as err:
        design_sigmas(presets["hunt"], P, unreachable="skp")
    assert err.value.field == "unreachable"
    skip, zero = (design_sigmas(presets["hunt"], P, unreachable=u) for u in ("skip", "zero"))
    assert skip[0][1] == np.inf and zero[0][1] == 0.0 and skip[0][0] == zero[0][0]


def test_valid_input_keeps_the_analytic_values():
    d = dexterous_workspace(G, ONES, MINS, {"velocity": 1.0, "acceleration": 9.81})
    assert d["cells"] == 15 ** 3 and d["volume_m3"] == pytest.approx(0.150 ** 3)
    assert len(axis_values(-0.075, 0.075, 0.01)) == 16
    c = culling_sweep(_ev, 5, 12, seed_poses=[0, 11], block=5)
    b, g = brute_force_sweep(_ev, 5, 12, block=7)
    assert c.best == b.best and c.gii == b.gii == g.max()
    assert g[b.best] == pytest.approx(LO[b.best].min() / HI[b.best].max(), rel=0)
