"""True single-difference ambiguities refer to the wind-up as the estimator unwraps it.

Authority: the phase model (wind-up equal in cycles on both frequencies, Wu et al. 1993) and
the unwrapping rule of leopod.gnss.corrections.unwrap_windup that the estimator applies from
the first epoch of its arc: a wind-up that has wandered by k whole cycles since the simulated
day began moves the estimated N1 by k and leaves N_WL = N1 - N2 unchanged.
"""

import numpy as np
import xarray as xr

from leopod.simulate.ambiguity_truth import true_single_differences

T = np.datetime64("2021-07-12T00:00", "ns") + np.arange(6) * np.timedelta64(30, "s")


def _case(windup):
    sv = ["C19", "C20"]
    truth = xr.Dataset({
        "amb_L1P_cyc": (("obs_time", "sv"), np.tile([5.0, 2.0], (6, 1))),
        "amb_L5P_cyc": (("obs_time", "sv"), np.tile([1.0, 1.0], (6, 1))),
        "windup_cyc": (("obs_time", "sv"), windup),
    }, coords={"obs_time": T, "sv": sv})
    # the arc begins at the third epoch; one pass per satellite
    residuals = xr.Dataset({"pass_index": (("time", "sv"), np.tile([0, 1], (4, 1)))},
                           coords={"time": T[2:], "sv": sv})
    table = xr.Dataset({"pass_i": ("pair", [0]), "pass_j": ("pair", [1])})
    return table, residuals, [truth]


def test_windup_within_half_a_cycle_changes_nothing():
    windup = np.tile([0.1, -0.2], (6, 1))
    wl, nl = true_single_differences(*_case(windup), phases=("L1P", "L5P"))
    assert wl[0] == (5 - 1) - (2 - 1) and nl[0] == 5 - 2


def test_windup_wandered_by_whole_cycles_moves_n1_not_n_wl():
    # C19's simulated wind-up is 2.3 cycles at the arc start: the estimator's starts at 0.3
    windup = np.stack([np.linspace(2.1, 2.4, 6), np.full(6, -0.2)], axis=1)
    wl, nl = true_single_differences(*_case(windup), phases=("L1P", "L5P"))
    assert wl[0] == 3.0
    assert nl[0] == (5 + 2) - 2
