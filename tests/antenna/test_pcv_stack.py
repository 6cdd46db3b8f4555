"""Unit tests of the residual-method PCV map (leopod.antenna.pcv).

Authority: the definition of the residual method (Wang et al. 2024, eqs. 12-13: the PCV of a
node is the mean of the phase residuals in its neighbourhood) computed by brute force on
synthetic residuals (the bilinear estimator: node values of a smooth pattern), and the ANTEX convention that the IF PCV of a pair of equal per-frequency
PCVs is that PCV (Jäggi et al. 2009, GOCE values filled in for both frequencies).
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from leopod.antenna.pcv import (
    PcvSettings,
    apriori_pattern,
    estimated_antenna,
    map_differences,
    map_rms_m,
    stack_maps,
    stack_residuals,
)
from leopod.codebias.grid import AntennaGrid
from leopod.gnss.leo_antenna import leo_antenna, receiver_pcv_if
from leopod.io.antex_write import write_antex
from leopod.workflow.config import with_defaults

PCO_TABLE = {"L1": [0.1, 0.0, -0.5], "L2": [0.1, 0.0, -0.48]}


def _truth_m(az_deg, el_deg):
    """A synthetic ±1 cm pattern: cross-track asymmetry and an elevation term [m]."""
    return 0.01 * np.sin(np.radians(az_deg)) * np.cos(np.radians(el_deg)) \
        + 0.004 * np.cos(2 * np.radians(90 - el_deg))


def _residuals(n=200_000, noise_m=0.003, seed=0) -> xr.Dataset:
    rng = np.random.default_rng(seed)
    az = rng.uniform(0, 360, n)
    el = np.degrees(np.arcsin(rng.uniform(0, 1, n)))          # uniform over the hemisphere
    r = _truth_m(az, el) + rng.normal(0, noise_m, n)
    rej = (rng.uniform(size=n) < 0.01).astype(np.int8)
    r[rej == 1] = 1.0                                        # rejected outliers: left out
    shape = (n // 10, 10)
    return xr.Dataset({"phase_residual_m": (("time", "sv"), r.reshape(shape)),
                       "el_deg": (("time", "sv"), el.reshape(shape)),
                       "az_deg": (("time", "sv"), az.reshape(shape)),
                       "phase_rejected": (("time", "sv"), rej.reshape(shape))})


def _settings(**kw) -> PcvSettings:
    return PcvSettings.from_config(with_defaults("pcv", kw))


def test_nearest_node_is_the_half_step_neighbourhood():
    g = AntennaGrid(10.0, 10.0)
    nodes = g.nearest([4.9, 5.1, 355.1, 123.0, 0.0, 0.0, 0.0],
                      [4.9, 5.1, 0.0, 85.1, -4.9, -5.1, np.nan])
    assert nodes.tolist() == [0, 1 * 36 + 1, 0, g.n_nodes - 1, 0, -1, -1]


def test_node_values_are_cell_means_with_the_datum_removed():
    res = _residuals()
    s = _settings(min_count=50, estimator="mean")
    m = stack_residuals([res.isel(time=slice(0, 10_000)), res.isel(time=slice(10_000, None))],
                        s)
    g = s.grid
    ok = np.isfinite(res.phase_residual_m.values.ravel()) & (res.phase_rejected.values.ravel()
                                                              == 0)
    r = res.phase_residual_m.values.ravel()[ok]
    node = g.nearest(res.az_deg.values.ravel()[ok], res.el_deg.values.ravel()[ok])
    # brute force: node at azimuth 40, zenith 30 (elevation 60, ring 6), and the zenith cap
    for (az, zen), k in (((40.0, 30.0), 6 * 36 + 4), ((0.0, 0.0), g.n_nodes - 1)):
        sel = r[node == k]
        cell = m.sel(azimuth_deg=az, zenith_deg=zen)
        assert int(cell["count"]) == sel.size
        assert float(cell.pcv_if_m) + m.attrs["datum_offset_m"] == pytest.approx(sel.mean(),
                                                                                 abs=1e-12)
        assert float(cell.sigma_m) == pytest.approx(sel.std(ddof=1) / np.sqrt(sel.size))
    # datum: the mean of the estimated nodes (zenith once) is zero
    well = m["count"].values >= 50
    well[1:, 0] = False
    assert np.mean(m.pcv_if_m.values[well]) == pytest.approx(0.0, abs=1e-12)
    # the zenith node repeats over the azimuths of zenith 0
    assert np.unique(m.pcv_if_m.values[:, 0]).size == 1


def test_map_matches_a_synthetic_pattern_within_the_noise():
    res = _residuals()
    for step, estimator in ((10.0, "mean"), (5.0, "mean"), (10.0, "bilinear"),
                            (5.0, "bilinear")):
        s = _settings(az_step_deg=step, zenith_step_deg=step, min_count=30,
                      estimator=estimator)
        m = stack_residuals([res], s)
        zz, aa = np.meshgrid(m.zenith_deg.values, m.azimuth_deg.values)
        truth = _truth_m(aa, 90.0 - zz)
        rms = map_rms_m(m, truth, min_count=30)
        # cell averaging of a smooth pattern + 3 mm noise over ~>100 residuals per node
        assert rms < 1e-3, (step, estimator, rms)


def test_zenith_datum_and_too_few_residuals():
    res = _residuals(20_000)
    m = stack_residuals([res], _settings(datum="zenith"))
    assert float(m.pcv_if_m.sel(zenith_deg=0.0, azimuth_deg=0.0)) == 0.0
    with pytest.raises(ValueError, match="no node has"):
        stack_residuals([res.isel(time=slice(0, 2))], _settings(min_count=1000))


def test_estimated_antex_is_applied_as_the_pod_reads_it(tmp_path):
    """The pattern with the map, written as ANTEX and read back through the satellite's
    antenna keys, gives ionosphere-free PCV = map at the nodes and the table's PCO."""
    m = stack_residuals([_residuals()], _settings())
    ant = estimated_antenna(PCO_TABLE, m)
    for band, pco in PCO_TABLE.items():
        np.testing.assert_allclose(ant[band], pco, atol=1e-12)
    pattern, _ = apriori_pattern(ant)
    path = write_antex(tmp_path / "pcv.atx", [pattern])
    back = leo_antenna(None, {"antex": str(path), "type": "LEOPOD PCV"})
    for band, pco in PCO_TABLE.items():
        np.testing.assert_allclose(back[band], pco, atol=1e-5)
    f_if = receiver_pcv_if(back, "G", ("L1C", "L2W"))
    zz, aa = np.meshgrid(m.zenith_deg.values, m.azimuth_deg.values)
    got = f_if(90.0 - zz, aa)
    want = np.nan_to_num(m.pcv_if_m.values)
    np.testing.assert_allclose(got, want, atol=1e-5)
    # a second iteration adds its correction to the first
    again = estimated_antenna(back, m)
    np.testing.assert_allclose(receiver_pcv_if(again, "G", ("L1C", "L2W"))(90 - zz, aa),
                               2 * want, atol=2e-5)


def test_stacked_periods_are_the_inverse_variance_mean():
    res = _residuals()
    s = _settings(estimator="mean", min_count=20)
    half = res.sizes["time"] // 2
    a = stack_residuals([res.isel(time=slice(0, half))], s, period="2019-01")
    b = stack_residuals([res.isel(time=slice(half, None))], s, period="2019-02")
    st = stack_maps([a, b], s)
    assert st.attrs["period"] == "2019-01 2019-02"
    np.testing.assert_array_equal(st["count"].values, a["count"].values + b["count"].values)
    wa, wb = a.sigma_m.values ** -2, b.sigma_m.values ** -2
    both = np.isfinite(a.pcv_if_m.values) & np.isfinite(b.pcv_if_m.values)
    mean = (wa * a.pcv_if_m.values + wb * b.pcv_if_m.values) / (wa + wb)
    mean = mean - np.nanmean(mean[both & _once(mean.shape)]) if both.all() else mean
    d = st.pcv_if_m.values[both] - mean[both]
    assert np.ptp(d) < 1e-12                 # equal up to the datum constant
    np.testing.assert_allclose(st.sigma_m.values[both], (wa + wb)[both] ** -0.5)
    ((pa, pb, rms, n),) = map_differences([a, b])
    assert (pa, pb) == ("2019-01", "2019-02") and n > 0 and 0 < rms < 3e-3


def test_maps_of_different_grids_are_not_stacked():
    res = _residuals(50_000)
    a = stack_residuals([res], _settings())
    b = stack_residuals([res], _settings(az_step_deg=5.0, zenith_step_deg=5.0))
    with pytest.raises(ValueError, match="cannot be stacked"):
        stack_maps([a, b], _settings())


def _once(shape):
    m = np.ones(shape, dtype=bool)
    m[1:, 0] = False
    return m
