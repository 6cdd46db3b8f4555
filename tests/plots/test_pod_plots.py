"""Figures of the float POD step: PNGs written, byte-identical on reruns, robust to NaN/rejections."""

from __future__ import annotations

import struct

import numpy as np
import pytest
import xarray as xr

from leopod.plots import pod

pytestmark = pytest.mark.filterwarnings("error")

N_EPOCHS = 120
SVS = ["G01", "G05", "G12", "E07", "C21"]


def _residuals() -> xr.Dataset:
    """Small residual Dataset: 20 min at 10 s across midnight, 5 satellites, last one unused."""
    rng = np.random.default_rng(1)
    time = np.datetime64("2024-03-10T23:50:00", "ns") + np.arange(N_EPOCHS) * np.timedelta64(10, "s")
    shape = (N_EPOCHS, len(SVS))
    el = rng.uniform(-5.0, 90.0, shape)
    az = rng.uniform(0.0, 360.0, shape)
    code = rng.normal(0.0, 0.5, shape)
    phase = rng.normal(0.0, 0.005, shape)
    code_rej = np.zeros(shape, dtype=np.int8)
    phase_rej = np.zeros(shape, dtype=np.int8)
    code_rej[10, 0] = code_rej[50, 2] = 1
    phase_rej[70, 1] = 1
    code[code_rej == 1] = np.nan
    phase[phase_rej == 1] = np.nan
    code[:, -1] = phase[:, -1] = el[:, -1] = az[:, -1] = np.nan  # satellite never observed
    return xr.Dataset(
        {"code_residual_m": (("time", "sv"), code), "phase_residual_m": (("time", "sv"), phase),
         "el_deg": (("time", "sv"), el), "az_deg": (("time", "sv"), az),
         "code_rejected": (("time", "sv"), code_rej), "phase_rejected": (("time", "sv"), phase_rej),
         "clk_rx_m": ("time", rng.normal(0.0, 100.0, N_EPOCHS))},
        coords={"time": time, "sv": SVS})


def _orbit(no_apriori: bool = False) -> xr.Dataset:
    """Small orbit Dataset: 30 h at 5 min from 21:00 of the previous day."""
    time = np.datetime64("2024-03-09T21:00", "ns") + np.arange(361) * np.timedelta64(5, "m")
    hours = np.arange(time.size) / 12.0
    diff = np.stack([0.3 * np.sin(hours), 0.8 * np.cos(hours), 0.1 * np.ones_like(hours)], axis=1)
    diff[:20] = np.nan  # a-priori missing at the start
    if no_apriori:
        diff[:] = np.nan
    sigma = np.stack([0.01 + 0.0 * hours, 0.02 + 0.001 * hours, 0.015 + 0.0 * hours], axis=1)
    sigma[-5:, 2] = np.nan
    return xr.Dataset(
        {"pos_itrf_m": (("time", "xyz"), np.full((time.size, 3), 7.0e6)),
         "sigma_rtn_m": (("time", "rtn"), sigma), "apriori_diff_rtn_m": (("time", "rtn"), diff)},
        coords={"time": time, "xyz": ["x", "y", "z"], "rtn": ["R", "T", "N"]})


def _png_chunk_types(data: bytes) -> list[bytes]:
    """Chunk types of a PNG file (PNG specification, ISO/IEC 15948, section 5.3)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    types, pos = [], 8
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        types.append(data[pos + 4:pos + 8])
        pos += 12 + length
    return types


RES_PLOTS = [pod.plot_residuals_time, pod.plot_residuals_elevation, pod.plot_residual_skymap]


def _check_deterministic_png(plot, ds, tmp_path) -> None:
    first, second = tmp_path / "a.png", tmp_path / "b.png"
    plot(ds, first, title="SAT 2024-070")
    plot(ds, second, title="SAT 2024-070")
    data = first.read_bytes()
    assert len(data) > 1000
    assert data == second.read_bytes()
    # no time stamp (tIME) and no text chunks (Software) that could differ between runs
    assert not {b"tIME", b"tEXt", b"iTXt", b"zTXt"} & set(_png_chunk_types(data))


@pytest.mark.parametrize("plot", RES_PLOTS)
def test_residual_plots_deterministic(plot, tmp_path):
    _check_deterministic_png(plot, _residuals(), tmp_path)


@pytest.mark.parametrize("plot", RES_PLOTS)
def test_residual_plots_all_nan(plot, tmp_path):
    res = _residuals()
    for name in ("code_residual_m", "phase_residual_m"):
        res[name][:] = np.nan
    res["code_rejected"][:] = 1
    plot(res, tmp_path / "nan.png")
    assert (tmp_path / "nan.png").stat().st_size > 0


def test_apriori_difference_deterministic(tmp_path):
    _check_deterministic_png(pod.plot_apriori_difference, _orbit(), tmp_path)


def test_apriori_difference_without_apriori_or_sigmas(tmp_path):
    orbit = _orbit(no_apriori=True)
    orbit["sigma_rtn_m"][:] = np.nan
    pod.plot_apriori_difference(orbit, tmp_path / "nan.png")
    assert (tmp_path / "nan.png").stat().st_size > 0


def test_rms_by_bin_hand_computed():
    values = np.array([1.0, -1.0, 3.0, np.nan, 2.0, 4.0, 2.0, 9.0])
    coord = np.array([1.0, 4.0, 6.0, 7.0, np.nan, 10.0, 15.0, -1.0])
    centres, rms, counts = pod.rms_by_bin(values, coord, [0.0, 5.0, 10.0, 15.0])
    # analytic truth: [0,5): {1,-1} -> 1; [5,10): {3} -> 3 (NaN value and NaN coordinate
    # ignored); [10,15] (last bin closed): {4, 2} -> sqrt((16+4)/2); coordinate -1 outside
    np.testing.assert_allclose(centres, [2.5, 7.5, 12.5])
    np.testing.assert_allclose(rms, [1.0, 3.0, np.sqrt(10.0)], rtol=1e-15)
    np.testing.assert_array_equal(counts, [2, 1, 2])


def test_rms_by_bin_empty_bin_is_nan():
    _, rms, counts = pod.rms_by_bin(np.array([[3.0, -4.0]]), np.array([[1.0, 2.0]]),
                                    np.array([0.0, 5.0, 10.0]))
    # analytic truth: sqrt((9 + 16) / 2); the second bin holds nothing
    np.testing.assert_allclose(rms[0], np.sqrt(12.5), rtol=1e-15)
    assert np.isnan(rms[1])
    np.testing.assert_array_equal(counts, [2, 0])


def test_rms_by_bin_shape_mismatch():
    with pytest.raises(ValueError):
        pod.rms_by_bin(np.ones(3), np.ones(4), [0.0, 1.0])


def test_cell_means_hand_computed():
    values = np.array([1.0, 3.0, -2.0, np.nan, 5.0])
    az = np.array([2.0, 4.0, 362.0, 3.0, 100.0])  # 362° wraps into the first azimuth cell
    el = np.array([7.0, 8.0, 6.0, 7.0, 89.0])
    means = pod._cell_means(values, az, el, np.arange(0.0, 361.0, 5.0), np.arange(0.0, 91.0, 5.0))
    # analytic truth: cell (0–5° az, 5–10° el) holds 1, 3, -2 -> mean 2/3; (100–105°, 85–90°): 5
    assert means.shape == (72, 18)
    np.testing.assert_allclose(means[0, 1], 2.0 / 3.0, rtol=1e-15)
    np.testing.assert_allclose(means[20, 17], 5.0)
    assert np.count_nonzero(np.isfinite(means)) == 2


def test_hours_of_day_for_a_30_h_arc():
    time = np.datetime64("2024-03-09T21:00", "ns") + np.array([0, 15, 30]) * np.timedelta64(1, "h")
    hours, label = pod._hours_of_day(time)
    # arithmetic: 21:00 of the previous day is -3 h, 03:00 of the next day is 27 h
    np.testing.assert_allclose(hours, [-3.0, 12.0, 27.0])
    assert "2024-03-10" in label


def test_robust_axis_ignores_a_few_outliers():
    # issue 23 item 5: 7-mm residuals and one 300-mm outlier get an axis of the residuals
    rng = np.random.default_rng(1)
    values = np.concatenate([rng.normal(0.0, 7.0, 20000), [300.0]])
    lim = pod.robust_limit(values, 1.0)
    # analytic: the 99.9th percentile of |N(0, 7)| is 7 x 3.29 = 23 mm; times 1.2
    assert 20.0 < lim < 35.0
    assert pod.robust_limit([0.0, np.nan], 5.0) == 5.0
    assert pod.robust_limit([1.0, -2.0], 1.0) == pytest.approx(2.1)   # at most max + 5 %


def test_sky_map_cells_of_about_equal_area():
    # issue 23 item 5 (starburst at the zenith): cells per ring follow cos(elevation)
    assert pod.ring_azimuth_cells(0.0, 5.0) == 72
    assert pod.ring_azimuth_cells(85.0, 90.0) == 3
    counts = [pod.ring_azimuth_cells(e, e + 5.0) for e in range(0, 90, 5)]
    assert counts == sorted(counts, reverse=True)

