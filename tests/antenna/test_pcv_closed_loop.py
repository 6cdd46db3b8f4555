"""Closed loop of the residual-method PCV (leopod.antenna.pcv) on a simulated arc.

Authority: the simulation truth - orbit and the real AIUB GOCE pattern
(../shared/data/antex/GOCE_MAIN_0001.ATX, Jäggi et al. 2009) with which the observations were
simulated; the POD starts without any PCV (tests/antenna/_pcv_loop.py). Issue 22 asks for a
map within 1 mm RMS of the truth over well-observed cells and an orbit with the estimated map
as good as with the true one.

Measured here (float POD of 1-5 h, 30° x 15° grid, 57 nodes with >= 30 residuals, bilinear
estimator, one iteration; orbit 3D RMS against the truth): no PCV 42.98 mm, true PCV
29.98 mm, estimated map 38.28 mm; map RMS against the truth 5.7 mm (the truth's own RMS over
those nodes about 6 mm; the cell-mean estimator: 37.38 mm and 4.1 mm). A 4-h float arc leaves
most of the pattern in the float ambiguities of its short passes and in the clocks: the orbit
improves, but neither criterion of the issue is met on such an arc. benchmarks/pcv.py
measures a whole day with iterations (figures in its docstring). About 30 s on one core.
"""

from __future__ import annotations

import numpy as np
import pytest
from _pcv_loop import pcv_loop
from _simulated_arc import GOCE  # tests/estimation, on the path through _pcv_loop

pytestmark = pytest.mark.skipif(not GOCE.exists(), reason="needs ../shared/data/antex")


@pytest.fixture(scope="module")
def loop(tmp_path_factory):
    return pcv_loop(tmp_path_factory.mktemp("pcv"), hours=(1.0, 5.0), steps=(30.0, 15.0),
                    min_count=30, iterations=1)


def test_the_estimated_map_improves_the_orbit_without_pcv(loop):
    orbit = loop["orbit_3d_m"]
    print("\norbit 3D RMS vs truth [mm]: " + ", ".join(f"{k} {v * 1e3:.2f}"
                                                     for k, v in orbit.items())
          + f"; map RMS vs truth {loop['map_rms_m'][0] * 1e3:.2f} mm ({loop['seconds']:.0f} s)")
    assert orbit["none"] > orbit["true"] + 5e-3
    assert orbit["estimated_1"] < orbit["none"] - 3e-3


def test_the_map_follows_the_true_pattern(loop):
    truth = loop["truth_map"]
    well = truth["count"].values >= 30
    est = loop["maps"][0].pcv_if_m.values[well]
    true = truth.pcv_if_m.values[well]
    corr = float(np.corrcoef(est - est.mean(), true - true.mean())[0, 1])
    assert corr > 0.5
    assert loop["map_rms_m"][0] < float(np.std(true))


@pytest.mark.xfail(strict=True, reason="issue 22 criterion not met on a 4-h float arc: the "
                   "map is 5-6 mm RMS from the truth, the orbit 8 mm worse than with the truth")
def test_the_issue_criteria(loop):
    assert loop["map_rms_m"][-1] < 1e-3
    assert loop["orbit_3d_m"]["estimated_1"] < loop["orbit_3d_m"]["true"] + 1e-3
