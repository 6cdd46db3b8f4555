"""Tests of leopod.simulate.code_bias_map.

Authorities: the pattern described in Peng et al. (2021) (HY-2B P1, sec. II text of Figs. 7-10 and
the conclusion) and Jiang et al. (2023) (BDS-3 patchy maps), quoted at each check; independent
numerical quadrature for the map mean; analytic properties (continuity, zero model).
"""

from __future__ import annotations

import numpy as np
import pytest
from snakemake.exceptions import WorkflowError

from leopod.simulate.code_bias_map import HY2B_P1_AREA_MEAN_M, CodeBiasMap
from leopod.workflow.config import with_defaults

ATOL_M = 1e-12


def _map(model: str, signal: str = "C1W", **params) -> CodeBiasMap:
    """A map of ``simulate.code_bias_maps``: the schema's default parameters with ``params``."""
    return CodeBiasMap.from_config(with_defaults(
        "simulate_code_bias_map", {"model": model, "signal": signal, **params}))


@pytest.fixture(scope="module")
def hy2b():
    return _map("hy2b_p1", "C1W")


def test_hy2b_valley_on_the_long_axis(hy2b):
    # Peng et al. (2021): "a valley along the axis of the area, in which the errors reach a minimum,
    # about -0.3 m"; "the two ends of the area point to azimuths of 90° and 270°"
    for az in (90.0, 270.0):
        assert hy2b(az, 60.0) == pytest.approx(-0.3, abs=0.03)
    grid = hy2b.grid()["code_bias_m"]
    assert grid.min() == pytest.approx(-0.3, abs=0.03)
    where = grid.where(grid == grid.min(), drop=True)
    r = (90.0 - where["el"].values) / 90.0
    x = r * np.cos(np.radians(where["az"].values))   # distance from the azimuth 90/270 axis
    assert np.all(np.abs(x) < 0.02)


def test_hy2b_flat_ellipse_elongated_across_track(hy2b):
    # Peng et al. (2021): "an obviously elliptical area in the center of the map ... the errors
    # mainly varied by 10 to 20 cm"
    for az, el in ((0.0, 75.0), (180.0, 75.0), (45.0, 70.0), (315.0, 72.0)):
        assert 0.1 <= hy2b(az, el) <= 0.2
    # long axis along 90°/270°: at 50° elevation the cross-track direction is still inside the
    # ellipse (|b| < 0.3 m) while the along-track direction is already outside (0.5-1 m)
    assert abs(hy2b(90.0, 50.0)) < 0.3 and abs(hy2b(270.0, 50.0)) < 0.3
    assert 0.5 <= hy2b(0.0, 50.0) <= 1.0 and 0.5 <= hy2b(180.0, 55.0) <= 1.0


def test_hy2b_rest_of_the_map(hy2b):
    # Peng et al. (2021): "for the rest of the map, the errors vary from 0.5 to 1 m"
    for az, el in ((0.0, 30.0), (90.0, 20.0), (300.0, 10.0), (0.0, 5.0), (60.0, 15.0),
                   (270.0, 2.5), (30.0, 40.0)):
        assert 0.5 <= hy2b(az, el) <= 1.0 + 1e-3


def test_hy2b_crescent(hy2b):
    # Peng et al. (2021) conclusion: "reached a maximum of 3 m in the crescent area between azimuth
    # angles of 120° to 240°"
    grid = hy2b.grid()["code_bias_m"]
    assert 2.5 <= float(grid.max()) <= 3.1
    peak = grid.where(grid == grid.max(), drop=True)
    assert np.all((peak["az"] >= 120) & (peak["az"] <= 240)) and np.all(peak["el"] < 15)
    assert hy2b(180.0, 0.0) == pytest.approx(3.0, abs=0.1)
    az_in = np.arange(135.0, 226.0, 5.0)
    assert np.all(hy2b(az_in, 5.0) > 1.5)
    az_out = np.array([0.0, 30.0, 60.0, 90.0, 270.0, 300.0, 330.0])
    assert np.all(hy2b(az_out, 5.0) <= 1.0 + 1e-3)


def test_hy2b_rapid_increase_below_40_deg(hy2b):
    # Peng et al. (2021) abstract: "P1 code multipath errors ... rapidly increase from sub-meter to
    # several meters at elevation less than 40°"
    el = np.linspace(0.0, 40.0, 81)
    b = hy2b(180.0, el)
    assert b[-1] < 1.0 and b[0] > 2.5
    assert np.all(np.diff(b) < 0.0)


def test_grid_cell_centres_and_values(hy2b):
    ds = hy2b.grid(5.0)
    assert ds["code_bias_m"].dims == ("el", "az")
    assert ds.sizes == {"el": 18, "az": 72}
    np.testing.assert_allclose(ds["az"].values, np.arange(2.5, 360.0, 5.0))
    np.testing.assert_allclose(ds["el"].values, np.arange(2.5, 90.0, 5.0))
    # independent evaluation cell by cell
    for i, j in ((0, 0), (3, 35), (17, 71)):
        expected = hy2b(float(ds["az"][j]), float(ds["el"][i]))
        assert ds["code_bias_m"].values[i, j] == pytest.approx(expected, abs=ATOL_M)
    assert ds["code_bias_m"].attrs["units"] == "m"
    assert ds.attrs["signal"] == "C1W" and ds.attrs["model"] == "hy2b_p1"
    with pytest.raises(ValueError):
        hy2b.grid(7.0)


def test_area_mean_against_midpoint_quadrature(hy2b):
    # independent computation: midpoint rule on a 0.2° grid with cos(el) area weights
    step = 0.2
    el = np.arange(step / 2, 90.0, step)
    az = np.arange(step / 2, 360.0, step)
    w = np.cos(np.radians(el))[:, None]
    brute = float(np.sum(hy2b(az[None, :], el[:, None]) * w) / (np.sum(w) * az.size))
    assert hy2b.mean_m() == pytest.approx(brute, abs=1e-3)
    assert HY2B_P1_AREA_MEAN_M == pytest.approx(brute, abs=0.005)  # documented value
    assert hy2b.grid().attrs["area_mean_m"] == pytest.approx(brute, abs=1e-3)


@pytest.mark.parametrize("name", ["hy2b_p1", "bds3_patchy"])
def test_smooth_and_continuous(name):
    m = _map(name)
    # azimuth wrap (analytic: same direction)
    el = np.linspace(0.0, 90.0, 19)
    np.testing.assert_allclose(m(0.0, el), m(360.0, el), atol=ATOL_M)
    # the zenith is one direction: all azimuths agree there and nearly agree close to it
    az = np.arange(0.0, 360.0, 15.0)
    assert np.ptp(m(az, 90.0)) < 1e-12
    assert np.ptp(m(az, 89.9)) < 0.01
    # no jumps: neighbours 0.5° apart differ by less than 10 cm (the steepest slope is the
    # HY-2B crescent at the horizon, 2 m / 12° e-folding = 0.17 m/°)
    az, el = np.meshgrid(np.arange(0.0, 360.0, 0.5), np.arange(0.0, 90.01, 0.5))
    b = m(az, el)
    assert np.max(np.abs(np.diff(b, axis=0))) < 0.1
    assert np.max(np.abs(np.diff(b, axis=1))) < 0.1


def test_below_horizon_and_broadcasting(hy2b):
    assert hy2b(180.0, -5.0) == pytest.approx(hy2b(180.0, 0.0), abs=ATOL_M)
    out = hy2b(np.zeros((4, 1)), np.zeros((1, 3)))
    assert out.shape == (4, 3)


def test_none_model_is_zero():
    m = _map("none", "C1W")
    assert np.all(m(np.arange(0.0, 360.0, 10.0)[:, None], np.arange(0.0, 91.0, 10.0)) == 0.0)
    assert m.mean_m() == 0.0


def test_bds3_patchy_amplitude_seed_and_low_elevation():
    # Jiang et al. (2023): "patchy patterns with the amplitudes mainly concentrated within ±40 cm"
    blobs = _map("bds3_patchy", "C1P", low_elevation_m=0.0, seed=3)
    az, el = np.meshgrid(np.arange(0.0, 360.0, 0.25), np.arange(0.0, 90.01, 0.25))
    peak = np.max(np.abs(blobs(az, el)))
    assert 0.4 <= peak <= 0.42   # normalised to 0.4 m on a 1° grid, checked on a 0.25° grid
    # the same seed gives the same map, another seed another one
    again = _map("bds3_patchy", "C1P", low_elevation_m=0.0, seed=3)
    other = _map("bds3_patchy", "C1P", low_elevation_m=0.0, seed=4)
    assert np.array_equal(blobs(az, el), again(az, el))
    assert np.max(np.abs(blobs(az, el) - other(az, el))) > 0.1
    # Jiang et al. (2023): "at low elevation angles, the MPs of both frequencies predominantly fall
    # below 0 m": the default low-elevation term is -0.2 m at the horizon, 0 at the zenith
    full = _map("bds3_patchy", "C1P", seed=3)
    assert full(az[0], 0.0) - blobs(az[0], 0.0) == pytest.approx(np.full(az.shape[1], -0.2))
    assert full(0.0, 90.0) - blobs(0.0, 90.0) == pytest.approx(-0.2 * np.exp(-9.0))


def test_from_config_and_errors():
    m = _map("hy2b_p1", "C1W", valley_m=-0.5, crescent_az_deg=[100.0, 260.0])
    assert m(90.0, 90.0) == pytest.approx(-0.5, abs=1e-5)   # the valley bottom at the zenith
    assert m.model.crescent_az_deg == (100.0, 260.0)
    # the schema's defaults: model hy2b_p1 on C1W with the parameters of Peng et al. (2021)
    default = CodeBiasMap.from_config(with_defaults("simulate_code_bias_map", {}))
    assert (default.name, default.signal) == ("hy2b_p1", "C1W")
    assert default.model.valley_m == -0.3 and default.model.crescent_az_deg == (120.0, 240.0)
    # the schema names a misspelt or foreign parameter
    with pytest.raises(WorkflowError, match="valley_depth"):
        _map("hy2b_p1", valley_depth=1.0)
    with pytest.raises(WorkflowError, match="seed"):
        _map("hy2b_p1", seed=1)
    with pytest.raises(WorkflowError, match="gaussian"):
        _map("gaussian")
    # and the library an unknown model, a foreign or a missing parameter
    with pytest.raises(ValueError, match="unknown code-bias map model"):
        CodeBiasMap("gaussian", "C1W")
    with pytest.raises(ValueError, match="valley_depth"):
        CodeBiasMap("hy2b_p1", "C1W", valley_depth=1.0)
    with pytest.raises(ValueError, match="lacks the parameter.*plateau_m"):
        CodeBiasMap("hy2b_p1", "C1W", **{k: v for k, v in with_defaults(
            "simulate_map_hy2b_p1", {}).items() if k != "plateau_m"})


def test_yaw_branch_selects_the_epochs_of_its_branch():
    # Jiang et al. (2023): the B1C (and GPS L1) maps change with the yaw attitude mode, B2a and
    # L2 do not - a map with a yaw_branch is added only on the epochs of that branch
    below = np.array([False, False, True, True])
    every = _map("bds3_patchy", "C1P")
    above = _map("bds3_patchy", "C1P", yaw_branch="above_flip", seed=2)
    under = _map("bds3_patchy", "C1P", yaw_branch="below_flip", seed=3)
    assert every.applies(below) is True and every.applies(None) is True
    np.testing.assert_array_equal(above.applies(below), ~below)
    np.testing.assert_array_equal(under.applies(below), below)
    assert [m.key for m in (every, above, under)] == ["C1P", "C1P_above_flip", "C1P_below_flip"]
    assert under.grid().attrs["yaw_branch"] == "below_flip"
    with pytest.raises(ValueError, match="needs a satellite with the yaw_steering law"):
        under.applies(None)
    with pytest.raises(ValueError, match="unknown yaw_branch"):
        CodeBiasMap("none", "C1P", yaw_branch="sideways")
    with pytest.raises(WorkflowError):
        _map("none", "C1P", yaw_branch="sideways")
