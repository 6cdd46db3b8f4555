"""True single-difference integers of simulated arcs (leopod.simulate.ambiguity_truth).

Authorities: the definitions ``N_WL = N1 − N2`` and ``ΔN = N_i − N_j`` on hand-made integers
(analytic truth) - a combined GPS + Galileo arc takes each system's own phase pair (the truth
file's ``amb_L1C_cyc`` holds both systems); and the phase model (wind-up equal in cycles on
both frequencies, Wu et al. 1993) with the unwrapping rule of
leopod.gnss.corrections.unwrap_windup that the estimator applies from the first epoch of its
arc: a wind-up that has wandered by k whole cycles since the simulated day began moves the
estimated N1 by k and leaves N_WL = N1 - N2 unchanged. The per-pass median of one sort
against numpy's ``nanmedian`` of each pass.
"""

import warnings

import numpy as np
import xarray as xr

from leopod.simulate.ambiguity_truth import _group_medians, true_single_differences, wrong_fixes

SVS = ["E02", "E03", "G01", "G02"]
TIMES = np.datetime64("2023-07-08T00:00", "ns") + np.arange(3) * np.timedelta64(30, "s")
#: integers per satellite: L1C (both systems), L2W (GPS), L5Q (Galileo)
N = {"L1C": [10, 4, 7, 3], "L2W": [np.nan, np.nan, 2, 5], "L5Q": [1, 9, np.nan, np.nan]}


def _inputs():
    truth = xr.Dataset({f"amb_{p}_cyc": (("obs_time", "sv"), np.tile(v, (3, 1)))
                        for p, v in N.items()}, coords={"obs_time": TIMES, "sv": SVS})
    residuals = xr.Dataset({"pass_index": (("time", "sv"), np.tile(np.arange(4), (3, 1)))},
                           coords={"time": TIMES, "sv": SVS})
    table = xr.Dataset({"pass_i": ("pair", [0, 2]), "pass_j": ("pair", [1, 3]),
                        "system": ("pair", ["E", "G"])})
    return table, residuals, truth


def test_each_system_takes_its_own_phase_pair():
    table, residuals, truth = _inputs()
    wl, nl = true_single_differences(table, residuals, [truth],
                                     {"G": ("L1C", "L2W"), "E": ("L1C", "L5Q")})
    # E02 - E03: N_WL (10 - 1) - (4 - 9) = 14, N1 10 - 4 = 6; G01 - G02: (7 - 2) - (3 - 5) = 7
    np.testing.assert_array_equal(wl, [14.0, 7.0])
    np.testing.assert_array_equal(nl, [6.0, 4.0])


def test_one_pair_for_all_leaves_the_other_system_unknown_and_counted_wrong():
    """With the GPS pair alone the Galileo SD has no true WL (NaN): a fix of it cannot agree
    with the truth, which is why a combined arc needs the per-system pairs."""
    table, residuals, truth = _inputs()
    wl, nl = true_single_differences(table, residuals, [truth], ("L1C", "L2W"))
    assert np.isnan(wl[0]) and wl[1] == 7.0 and nl[0] == 6.0
    fixed = table.assign(wl_fixed=("pair", [1, 1]), nl_fixed=("pair", [0, 0]),
                         constrained=("pair", [0, 0]), wl_integer=("pair", [14, 7]),
                         nl_integer=("pair", [6, 4]))
    assert wrong_fixes(fixed, wl, nl)["wl_wrong"] == 1
    right = true_single_differences(table, residuals, [truth],
                                    {"G": ("L1C", "L2W"), "E": ("L1C", "L5Q")})
    assert wrong_fixes(fixed, *right)["wl_wrong"] == 0


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


def test_the_pass_medians_are_numpys_nanmedian_of_each_pass():
    rng = np.random.default_rng(7)
    for size in (0, 1, 2, 7, 300):
        passes = rng.integers(0, 12, size)
        values = rng.integers(-4, 4, size).astype(float)
        values[rng.random(size) < 0.3] = np.nan          # epochs without the signal
        keys, medians = _group_medians(passes, values)
        np.testing.assert_array_equal(keys, np.unique(passes))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)    # all-NaN pass: NaN
            expected = [np.nanmedian(values[passes == k]) for k in keys]
        np.testing.assert_array_equal(medians, expected)
