"""path_crossings(refine=True) finds a pair of roots inside one sample interval (QA F2),
against analytic roots."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.singularity import path_crossings


@pytest.mark.parametrize("c, h", [(0.5, 1e-3), (24.5 / 119, 2e-3), (0.77, 1e-6)])
def test_root_pair_inside_one_interval(c, h):
    f = lambda s: (np.asarray(s) - c) ** 2 - h * h  # noqa: E731   roots c -/+ h
    grid_only, grid, _ = path_crossings(f, 120)
    assert grid_only == []                    # both roots between two samples
    roots, _, _ = path_crossings(f, 120, refine=True)
    assert roots == pytest.approx([c - h, c + h], abs=1e-12)


def test_no_pair_where_the_minimum_keeps_its_sign():
    f = lambda s: (np.asarray(s) - 0.5) ** 2 + 1e-8  # noqa: E731   no real root
    assert path_crossings(f, 120, refine=True)[0] == []


def test_refine_keeps_the_simple_roots():
    # cos(9 s): roots (2k + 1) pi / 18 in [0, 1], each a simple sign change
    roots, _, _ = path_crossings(lambda s: np.cos(9 * np.asarray(s)), 50, refine=True)
    assert roots == pytest.approx([np.pi / 18, 3 * np.pi / 18, 5 * np.pi / 18], abs=1e-12)
