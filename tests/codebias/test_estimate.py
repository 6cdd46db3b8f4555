"""Map estimation from multipath: closed loop against a known map (analytic truth)."""

import dataclasses

import numpy as np
import pytest
from _synthetic import smooth_map

from leopod.codebias.estimate import (
    MapSettings,
    _solve_datum,
    _solve_datum_regular,
    estimate_map,
)
from leopod.codebias.grid import AntennaGrid
from leopod.codebias.products import mp_statistics
from leopod.codebias.samples import MpSamples
from leopod.workflow.config import section_defaults

#: The schema's defaults (campaign code_bias section) on a 10° grid.
MAP = MapSettings.from_config(section_defaults("code_bias"))
SETTINGS = dataclasses.replace(MAP, az_step_deg=10.0, el_step_deg=10.0, min_count=50)


def _node_truth(grid: AntennaGrid) -> np.ndarray:
    return smooth_map(*grid.node_directions())


def test_recovers_the_map_up_to_a_constant_within_its_formal_sigma(passes):
    az, el, mp, key, _, _ = passes
    fit = estimate_map(az, el, mp, key, SETTINGS)
    ok = fit.count >= SETTINGS.min_count
    assert ok.sum() > 300
    err = fit.value_m[ok] - _node_truth(SETTINGS.grid)[ok]
    err -= err.mean()  # the datum (a constant) is not observable
    # the map is smooth but not bilinear: a 10-deg grid misfits it by < ~1 cm; noise 5-20 cm
    assert np.sqrt(np.mean(err**2)) < 0.02
    # formal sigmas describe the scatter of the errors (chi-square style check)
    z = err / fit.sigma_m[ok]
    assert 0.6 < np.sqrt(np.mean(z**2)) < 1.6
    # datum: zero count-weighted mean over the estimated nodes
    assert abs(np.nansum(fit.count * fit.value_m)) < 1e-9 * fit.count.sum()
    # weights are 1/sigma^2 per elevation band: unit variance ~ 1
    assert 0.8 < fit.sigma0 < 1.2


def test_pass_offsets_do_not_change_the_map(passes):
    az, el, mp, key, _, _ = passes
    shifted = mp + 1000.0 * np.sin(key)  # any constant per pass
    a = estimate_map(az, el, mp, key, SETTINGS)
    b = estimate_map(az, el, shifted, key, SETTINGS)
    assert np.nanmax(np.abs(a.value_m - b.value_m)) < 1e-6


def test_outliers_are_down_weighted(passes):
    az, el, mp, key, _, _ = passes
    rng = np.random.default_rng(3)
    bad = rng.random(mp.size) < 0.01
    spoiled = mp + np.where(bad, rng.choice([-5.0, 5.0], mp.size), 0.0)
    fit = estimate_map(az, el, spoiled, key, SETTINGS)
    plain = estimate_map(az, el, spoiled, key, dataclasses.replace(SETTINGS, iterations=0))
    ok = fit.count >= SETTINGS.min_count
    truth = _node_truth(SETTINGS.grid)[ok]

    def rms(v):
        e = v[ok] - truth
        return np.sqrt(np.mean((e - e.mean()) ** 2))

    assert fit.n_downweighted >= bad.sum() * 0.9
    assert rms(fit.value_m) < 0.025 < rms(plain.value_m)


def test_corrected_multipath_is_the_noise(passes):
    az, el, mp, key, _, sigma = passes
    fit = estimate_map(az, el, mp, key, SETTINGS)
    stats = mp_statistics(MpSamples(az, el, mp, key, np.zeros(az.size, int)), fit.value_m,
                          SETTINGS.grid)
    # after the correction, the pass-centred multipath is noise (+ a small grid misfit)
    assert stats.el_deg.size == az.size
    assert np.sqrt(np.mean(stats.after_m**2)) < 1.1 * np.sqrt(np.mean(sigma**2))


def test_smoothing_fills_nodes_without_data_and_empty_data_fails(passes):
    az, el, mp, key, _, _ = passes
    keep = ~((az > 100) & (az < 130) & (el < 40))  # a hole in the sky
    plain = estimate_map(az[keep], el[keep], mp[keep], key[keep], SETTINGS)
    smooth = estimate_map(az[keep], el[keep], mp[keep], key[keep],
                          dataclasses.replace(SETTINGS, smoothing_sigma_m=0.05))
    hole = SETTINGS.grid.n_az * 1 + 11  # ring 10 deg, azimuth 110 deg
    assert np.isnan(plain.value_m[hole]) and plain.count[hole] == 0
    assert np.isfinite(smooth.value_m[hole])
    with pytest.raises(ValueError, match="no finite multipath"):
        estimate_map(az, el, np.full(mp.size, np.nan), key, SETTINGS)



def test_a_pass_that_sees_nothing_else_is_left_out(passes):
    # a pass whose observations all sit on one node no other pass sees is an island: its
    # node cannot be separated from its offset, so both are dropped (not a failure)
    az, el, mp, key, _, _ = passes
    keep = ~((az > 100) & (az < 130) & (el < 40))
    n = 30
    fit = estimate_map(np.r_[az[keep], np.full(n, 110.0)], np.r_[el[keep], np.full(n, 10.0)],
                       np.r_[mp[keep], np.full(n, 3.0)],
                       np.r_[key[keep], np.full(n, key.max() + 1)], SETTINGS)
    node = SETTINGS.grid.n_az * 1 + 11  # ring 10 deg, azimuth 110 deg
    assert np.isnan(fit.value_m[node]) and fit.empty(min_count=1)[node]
    assert np.isfinite(fit.value_m).sum() > 300  # the rest of the map is estimated


def test_datum_solution_and_defect_detection():
    # analytic truth: nodes 0-1 tied by one difference (x0 - x1 = 1), node 2 without data;
    # datum w = (1/2, 1/2, 0): x = (0.5, -0.5, -), node 2 is a defect beyond the datum
    n = np.array([[1.0, -1.0, 0.0], [-1.0, 1.0, 0.0], [0.0, 0.0, 0.0]])
    b = np.array([1.0, -1.0, 0.0])
    x, cov_diag, undetermined = _solve_datum(n, b, np.array([0.5, 0.5, 0.0]))
    assert undetermined.tolist() == [False, False, True]
    assert np.allclose(x[:2], [0.5, -0.5])
    # covariance of x0 = -x1 = d/2 with var(d) = 1 (N00 = 1): var(x0) = 1/4
    assert np.allclose(cov_diag[:2], 0.25)


def test_cholesky_datum_solution_equals_the_eigen_one():
    # analytic truth: for N with the datum as its only defect, M = N + c w wᵀ is positive
    # definite and both factorisations give x = M⁻¹ b and diag(M⁻¹) - 1/c
    rng = np.random.default_rng(4)
    a = rng.normal(size=(40, 6))
    a -= a.mean(axis=1, keepdims=True)  # rows of differences: the constant is the defect
    n = a.T @ a
    b = a.T @ rng.normal(size=40)
    w = np.full(6, 1 / 6)
    x_e, cov_e, undetermined = _solve_datum(n, b, w)
    x_c, cov_c = _solve_datum_regular(n, b, w, covariance=True)
    assert not undetermined.any()
    assert abs(w @ x_c) < 1e-12
    np.testing.assert_allclose(x_c, x_e, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(cov_c, cov_e, rtol=1e-10)
    assert _solve_datum_regular(n, b, w, covariance=False)[1] is None
