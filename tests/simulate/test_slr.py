"""Tests of the simulated SLR normal points (visibility, bins, noise, CRD and SINEX files)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from leopod.constants import C_LIGHT_M_S, OMEGA_EARTH_RAD_S, R_EARTH_EQUATOR_M
from leopod.frames.attitude import body_to_ef, nominal_body_axes
from leopod.io.crd import read_crd
from leopod.io.sinex import (
    read_sinex_eccentricities,
    read_sinex_stations,
    station_eccentricity,
    station_position,
)
from leopod.simulate.slr import (
    DEFAULT_STATIONS,
    SlrSettings,
    simulate_normal_points,
    write_slr_files,
)
from leopod.simulate.world import CircularOrbit, earth_fixed
from leopod.validation.slr import SlrResidualSettings, slr_residuals
from leopod.validation.slr_model import elevation_rad
from leopod.workflow.config import section_defaults, with_defaults

#: Default laser-ranging settings (the campaign schema's defaults).
SLR = SlrResidualSettings.from_config(section_defaults("validation")["slr"])


def _slr_settings(**changes) -> SlrSettings:
    """The simulator's laser-ranging settings: the schema's defaults with ``changes``."""
    return SlrSettings.from_config(with_defaults("simulate_slr", changes))


#: The schema's defaults.
DEFAULT = _slr_settings()

T0 = np.datetime64("2021-03-01T00:00:00", "ns")
THETA0_RAD = 1.1
#: HY-2B-like orbit: 970 km, sun-synchronous inclination 99.35°.
LEO = CircularOrbit(R_EARTH_EQUATOR_M + 970e3, 99.35, 40.0, 10.0)
OFFSET_BODY_M = np.array([0.4, -0.3, 0.9])
STATIONS = {s.pad_id: s for s in DEFAULT_STATIONS}


def _analytic_itrf(t_s):
    return earth_fixed(t_s, *LEO.inertial(t_s), THETA0_RAD)


def _truth() -> xr.Dataset:
    t_s = np.arange(-600.0, 86400.0 + 630.0, 30.0)
    pos, vel = _analytic_itrf(t_s)
    return xr.Dataset({"pos_itrf_m": (("time", "xyz"), pos),
                       "vel_itrf_m_s": (("time", "xyz"), vel)},
                      coords={"time": T0 + (t_s * 1e9).astype("timedelta64[ns]"),
                              "xyz": ["x", "y", "z"]})


@pytest.fixture(scope="module")
def truth():
    return _truth()


@pytest.fixture(scope="module")
def nps(truth):
    return simulate_normal_points(truth, OFFSET_BODY_M, settings=DEFAULT,
                                  rng=np.random.default_rng(42))


@pytest.fixture(scope="module")
def full(truth):
    """Every visible bin tracked (no weather, no dropouts)."""
    settings = _slr_settings(clear_sky_probability=1.0, bin_fill_probability=1.0)
    return simulate_normal_points(truth, OFFSET_BODY_M, settings=settings,
                                  rng=np.random.default_rng(7))


def _seconds(times_gps):
    return (np.asarray(times_gps, dtype="datetime64[ns]") - T0).astype(np.int64) / 1e9


def _reflector_analytic(t_s):
    pos, vel = _analytic_itrf(t_s)
    return pos + body_to_ef(nominal_body_axes(pos, vel), OFFSET_BODY_M)


def _brute_force_range_m(t_s, sta):
    """Two-way vacuum range / 2 from the analytic orbit, solved in the world's inertial frame."""
    def inertial(t, x):
        th = THETA0_RAD + OMEGA_EARTH_RAD_S * t
        c, s = np.cos(th), np.sin(th)
        return np.stack([c * x[:, 0] - s * x[:, 1], s * x[:, 0] + c * x[:, 1], x[:, 2]], axis=-1)

    up = np.zeros_like(t_s)
    for _ in range(30):
        refl = inertial(t_s + up, _reflector_analytic(t_s + up))
        up = np.linalg.norm(refl - inertial(t_s, sta), axis=1) / C_LIGHT_M_S
    down = up.copy()
    for _ in range(30):
        down = np.linalg.norm(refl - inertial(t_s + up + down, sta), axis=1) / C_LIGHT_M_S
    return 0.5 * C_LIGHT_M_S * (up + down)


# ------------------------------------------------------------------------------ visibility
def test_points_above_cut_off(nps):
    # Definition of the cut-off; independent check with the analytic orbit at the transmit
    # epoch (light time moves the elevation by < 0.01°).
    cut = DEFAULT.elevation_cut_off_deg
    assert nps.sizes["point"] > 100
    assert nps["elevation_deg"].min() >= cut
    sta = np.array([STATIONS[s].pos_itrf_m for s in nps["station"].values])
    los = _reflector_analytic(_seconds(nps["time_gps"].values)) - sta
    assert np.degrees(elevation_rad(sta, los)).min() > cut - 0.01


def test_points_in_bins_aligned_to_utc_midnight(nps, full):
    # ILRS normal point rule: bins of fixed length starting at 0 h UTC, one point per bin;
    # 30 s is the ILRS bin for 800-2000 km altitude (ILRS "Normal Point Data" bin table).
    for ds in (nps, full):
        t = ds["time"].values.astype(np.int64)
        day = t - t % (86_400 * 10**9)
        bins = (t - day) // (30 * 10**9)
        keys = {(s, d, b) for s, d, b in zip(ds["station"].values, day, bins)}
        assert len(keys) == ds.sizes["point"]
        assert np.all(ds["np_window_s"].values == 30.0)
    # no dropouts inside a pass when every bin is tracked: consecutive bins
    for _, p in full.groupby("pass_id"):
        b = (p["time"].values.astype(np.int64) // (30 * 10**9))
        assert np.all(np.diff(np.sort(b)) == 1)


def test_weather_gaps(truth, full, nps):
    # Probabilities 0 / 1 are exact; the default network tracks a subset of the full set.
    none = simulate_normal_points(truth, OFFSET_BODY_M,
                                  settings=_slr_settings(clear_sky_probability=0.0),
                                  rng=np.random.default_rng(1))
    assert none.sizes["point"] == 0
    assert full.sizes["point"] > nps.sizes["point"]
    # a pass of a 970-km LEO above 10° lasts < 17 min (geometry): < 35 bins of 30 s
    for _, p in full.groupby("pass_id"):
        assert p.sizes["point"] <= 35
        assert np.unique(p["station"].values).size == 1


def test_determinism(truth, nps):
    # Same generator state -> identical output; another seed -> other points.
    again = simulate_normal_points(truth, OFFSET_BODY_M, settings=DEFAULT,
                                   rng=np.random.default_rng(42))
    xr.testing.assert_identical(nps, again)
    other = simulate_normal_points(truth, OFFSET_BODY_M, settings=DEFAULT,
                                   rng=np.random.default_rng(43))
    assert other.sizes["point"] != nps.sizes["point"] or not np.array_equal(
        other["tof_s"].values, nps["tof_s"].values)


def test_epochs_are_utc(nps):
    # IERS Bulletin C: GPS - UTC = 18 s from 2017-01-01 to at least 2025.
    diff = nps["time_gps"].values - nps["time"].values
    assert np.all(diff == np.timedelta64(18, "s"))


# ----------------------------------------------------------------------------------- truth
def test_tof_is_sum_of_truth_parts(nps):
    # Definition: c tof / 2 = geometric + troposphere + relativity + bias + noise.
    parts = sum(nps[v] for v in ("geometric_range_m", "tropo_delay_m", "relativity_delay_m",
                                 "range_bias_m", "noise_m"))
    np.testing.assert_allclose(0.5 * C_LIGHT_M_S * nps["tof_s"], parts, rtol=0, atol=1e-9)
    # zenith delay 1.7 m at 3 km height (Haleakala) to 2.45 m at sea level, times <= 5.6 at 10°
    assert np.all(nps["tropo_delay_m"] > 1.6) and np.all(nps["tropo_delay_m"] < 14.0)


def test_geometric_range_against_analytic_brute_force(nps):
    # Independent: analytic orbit (no interpolation), inertial-frame light time by plain
    # fixed-point iteration from the simulated reference point of the station (marker +
    # eccentricity + tides). Interpolation of the 30-s truth table costs < 1 µm.
    sta = nps["pos_station_itrf_m"].values
    ref = _brute_force_range_m(_seconds(nps["time_gps"].values), sta)
    np.testing.assert_allclose(nps["geometric_range_m"], ref, rtol=0, atol=1e-5)


def test_noise_and_bias_recovered(truth):
    # Statistics: the sample STD of n points has a relative standard error 1/sqrt(2n) < 3 %;
    # tolerance 10 %. The bias of station 7090 is recovered from its mean residual (4 sigma).
    settings = _slr_settings(clear_sky_probability=1.0, noise_m=0.005,
                             range_bias_m={"7090": 0.05})
    ds = simulate_normal_points(truth, np.zeros(3), settings=settings,
                                rng=np.random.default_rng(3))
    res = 0.5 * C_LIGHT_M_S * ds["tof_s"].values - (
        ds["geometric_range_m"] + ds["tropo_delay_m"] + ds["relativity_delay_m"]).values
    at_7090 = ds["station"].values == "7090"
    assert at_7090.sum() > 20 and (~at_7090).sum() > 500
    assert np.std(res[~at_7090]) == pytest.approx(0.005, rel=0.10)
    assert abs(np.mean(res[~at_7090])) < 4 * 0.005 / np.sqrt((~at_7090).sum())
    assert np.mean(res[at_7090]) == pytest.approx(0.05, abs=4 * 0.005 / np.sqrt(at_7090.sum()))


# ----------------------------------------------------------------------------------- files
def test_station_reference_points(nps):
    # Definition: reference point = SINEX marker + ILRS eccentricity + tide displacement;
    # the solid Earth tide (IERS 2010 sec. 7.1.1) stays below 0.45 m (h2 (k_Moon + k_Sun)
    # = 0.32 m radial plus the permanent part), the pole tide below 2.5 cm.
    marker = np.array([STATIONS[s].pos_itrf_m for s in nps["station"].values])
    ecc = np.array([STATIONS[s].ecc_xyz_m for s in nps["station"].values])
    disp = nps["station_displacement_itrf_m"].values
    np.testing.assert_allclose(nps["pos_station_itrf_m"].values, marker + ecc + disp,
                               rtol=0, atol=1e-9)
    size = np.linalg.norm(disp, axis=1)
    assert np.all(size < 0.45) and size.max() > 0.05
    # Yarragadee's eccentricity in the ILRS file ecc_xyz.snx (2023-03-14), valid since 2014
    np.testing.assert_allclose(STATIONS["7090"].ecc_xyz_m, (-1.2073, 2.5034, -1.5509))


def test_crd_and_sinex_round_trip(tmp_path, truth, nps):
    crd, snx, ecc = tmp_path / "hy2b.npt", tmp_path / "stations.snx", tmp_path / "ecc.snx"
    write_slr_files(nps, DEFAULT_STATIONS, crd, snx, "2021-03-01", ecc_path=ecc)
    back = read_crd(crd)
    # CRD 2 writes tof to 1 ps and epochs to 1 ns (leopod.io.crd_write.write_crd)
    assert back.sizes["point"] == nps.sizes["point"]
    np.testing.assert_allclose(back["tof_s"], nps["tof_s"], rtol=0, atol=0.5e-12)
    np.testing.assert_array_equal(back["time"].values, nps["time"].values)
    np.testing.assert_array_equal(back["station"].values, nps["station"].values)
    np.testing.assert_array_equal(back["pass_id"].values, nps["pass_id"].values)
    for name in ("pressure_hpa", "temperature_k", "humidity_pct", "wavelength_nm"):
        np.testing.assert_allclose(back[name], nps[name], rtol=0, atol=1e-9)
    # HY-2B: launched 2018-10-24, COSPAR 2018-081A (ILRS id 1808101)
    assert set(back["cospar_id"].values) == {"2018-081A"}
    assert set(back["station_name"].values) <= {s.code for s in DEFAULT_STATIONS}

    sites = read_sinex_stations(snx)
    eccs = read_sinex_eccentricities(ecc)
    for s in DEFAULT_STATIONS:
        np.testing.assert_allclose(station_position(sites, s.pad_id, "2021-03-01T12:00"),
                                   s.pos_itrf_m, rtol=0, atol=1e-6)
        # eccentricities written to 0.1 mm
        value, system = station_eccentricity(eccs, s.pad_id, "2021-03-01T12:00")
        assert system == "XYZ"
        np.testing.assert_allclose(value, s.ecc_xyz_m, rtol=0, atol=0.5e-4)

    # closed loop: the files alone (+ the true orbit) reproduce the observations up to the
    # simulated noise, to the 1-ps resolution of the file (0.15 mm one way)
    res = slr_residuals(truth, back, sites, eccs, retro_offset_body_m=OFFSET_BODY_M,
                        settings=SLR)
    assert np.all(res["flag"].values == 0)
    np.testing.assert_allclose(res["residual_m"], nps["noise_m"], rtol=0, atol=1e-4)
