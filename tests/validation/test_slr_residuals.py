"""Tests of the SLR residuals: closed loop with the simulator (truth orbit -> noise, shifted
orbit -> offset on the line of sight), each model term, epoch events and CRD flags,
screening, statistics (Peng et al. 2021, Table IV / Figs. 17-18; Wang et al. 2024, Table 5), real
CRD and SINEX files."""

from __future__ import annotations

import dataclasses

import erfa
import numpy as np
import pytest
import xarray as xr

from leopod.constants import (
    C_LIGHT_M_S,
    OMEGA_EARTH_RAD_S,
    R_EARTH_EQUATOR_M,
    WGS84_A_M,
    WGS84_INV_F,
)
from leopod.frames.rtn import rtn_matrix
from leopod.io.blq import BLQ_COMPONENTS, BLQ_CONSTITUENTS
from leopod.io.crd import read_crd
from leopod.io.sinex import read_sinex_eccentricities, read_sinex_stations
from leopod.io.sinex_write import write_sinex_eccentricities
from leopod.simulate.slr import (
    DEFAULT_STATIONS,
    SlrSettings,
    simulate_normal_points,
    write_slr_files,
)
from leopod.simulate.world import CircularOrbit, earth_fixed
from leopod.validation.slr import (
    REJECTION_REASONS,
    SlrResidualSettings,
    line_of_sight_orbit_difference,
    slr_residuals,
    station_reference_points,
)
from leopod.validation.slr_statistics import (
    elevation_statistics,
    rtn_projection,
    station_statistics,
)
from leopod.workflow.config import section_defaults, with_defaults

#: Default laser-ranging settings (the campaign schema's defaults).
SLR = SlrResidualSettings.from_config(section_defaults("validation")["slr"])

T0 = np.datetime64("2021-03-01T00:00:00", "ns")
THETA0_RAD = 0.4
#: HY-2B-like orbit: 970 km, sun-synchronous inclination 99.35°.
LEO = CircularOrbit(R_EARTH_EQUATOR_M + 970e3, 99.35, 25.0, 50.0)
OFFSET_BODY_M = np.array([-1.07215, -0.22228, 0.98418])
NOISE_M = 0.005
STATIONS = {s.pad_id: s for s in DEFAULT_STATIONS}


def _truth() -> xr.Dataset:
    t_s = np.arange(-600.0, 86400.0 + 630.0, 30.0)
    pos, vel = earth_fixed(t_s, *LEO.inertial(t_s), THETA0_RAD)
    return xr.Dataset({"pos_itrf_m": (("time", "xyz"), pos),
                       "vel_itrf_m_s": (("time", "xyz"), vel)},
                      coords={"time": T0 + (t_s * 1e9).astype("timedelta64[ns]"),
                              "xyz": ["x", "y", "z"]})


def _shifted(orbit: xr.Dataset, offset_rtn_m) -> xr.Dataset:
    """The orbit moved by a constant offset in its RTN axes (inertial velocity)."""
    pos = orbit["pos_itrf_m"].values
    vel_in = orbit["vel_itrf_m_s"].values + np.cross([0.0, 0.0, OMEGA_EARTH_RAD_S], pos)
    shift = np.einsum("nji,j->ni", rtn_matrix(pos, vel_in), np.asarray(offset_rtn_m))
    return orbit.assign(pos_itrf_m=(("time", "xyz"), pos + shift))


@pytest.fixture(scope="module")
def truth():
    return _truth()


def _files(tmp_path_factory, truth, noise_m, seed):
    settings = SlrSettings.from_config(with_defaults(
        "simulate_slr", {"clear_sky_probability": 1.0, "noise_m": noise_m}))
    sim = simulate_normal_points(truth, OFFSET_BODY_M, settings=settings,
                                 rng=np.random.default_rng(seed))
    d = tmp_path_factory.mktemp(f"slr{seed}")
    write_slr_files(sim, DEFAULT_STATIONS, d / "np.crd", d / "sta.snx", "2021-03-01",
                    ecc_path=d / "ecc.snx")
    return (sim, read_crd(d / "np.crd"), read_sinex_stations(d / "sta.snx"),
            read_sinex_eccentricities(d / "ecc.snx"))


@pytest.fixture(scope="module")
def noisy(tmp_path_factory, truth):
    """Simulated day (every visible bin tracked, 5 mm noise) written to and read from
    CRD 2 + SINEX + eccentricity SINEX: (simulation, normal points, stations, ecc)."""
    return _files(tmp_path_factory, truth, NOISE_M, 11)


@pytest.fixture(scope="module")
def clean(tmp_path_factory, truth):
    """As ``noisy`` without noise."""
    return _files(tmp_path_factory, truth, 0.0, 12)


@pytest.fixture(scope="module")
def res_noisy(truth, noisy):
    _, nps, sta, ecc = noisy
    return slr_residuals(truth, nps, sta, ecc, retro_offset_body_m=OFFSET_BODY_M, settings=SLR)


# --------------------------------------------------------------------------- closed loop
def test_truth_orbit_reproduces_the_noise(noisy, res_noisy):
    # Closed loop: residuals of the true orbit = simulated noise, to the 1-ps resolution of
    # the CRD file (0.15 mm one way); mean and STD within 1 mm of those of the noise and STD
    # within 1 mm of the nominal 5 mm (sample of ~1400 points: relative error 2 %).
    sim, nps, _, _ = noisy
    assert nps.sizes["point"] > 1000
    assert np.all(res_noisy["flag"].values == 0)
    res = res_noisy["residual_m"].values
    noise = sim["noise_m"].values
    np.testing.assert_allclose(res, noise, rtol=0, atol=1.5e-4)
    assert abs(res.mean() - noise.mean()) < 1e-3
    assert abs(res.std(ddof=1) - noise.std(ddof=1)) < 1e-3
    total = station_statistics(res_noisy).sel(station="total")
    assert abs(float(total["std_m"]) - NOISE_M) < 1e-3
    assert abs(float(total["mean_m"])) < 1e-3


def test_model_terms_equal_simulation_truth(noisy, res_noisy):
    # The simulator builds its stations from DEFAULT_STATIONS (marker + ecc + tides); the
    # residual model from the SINEX and eccentricity files: same reference points (files to
    # 1e-4 m: eccentricities are written to 0.1 mm), troposphere, Shapiro delay, elevation.
    sim = noisy[0]
    np.testing.assert_allclose(res_noisy["pos_station_itrf_m"], sim["pos_station_itrf_m"],
                               rtol=0, atol=1e-4)
    for ours, theirs in (("tropo_delay_m", "tropo_delay_m"),
                         ("relativity_delay_m", "relativity_delay_m"),
                         ("elevation_deg", "elevation_deg")):
        np.testing.assert_allclose(res_noisy[ours], sim[theirs], rtol=0, atol=1e-6)
    # Shapiro delay of a LEO range: a few mm (IERS 2010 eq. 11.17)
    assert 0.0 < res_noisy["relativity_delay_m"].min() < res_noisy["relativity_delay_m"].max() \
        < 0.02


def _assert_term(change, term):
    """``change`` equals ``term`` up to the light-time coupling |ρ̇|/c < 2.5e-5 (relative)
    and the second-order term d²/(2ρ) < 6 µm (d = 3.2 m, ρ > 970 km)."""
    change, term = np.asarray(change), np.asarray(term)
    bad = np.abs(change - term) > 3e-5 * np.abs(term) + 6e-6
    assert not bad.any(), (change[bad], term[bad])


def test_range_terms_are_the_range_changes(truth, noisy, res_noisy):
    # Each stored term is the change of the computed range when the effect is switched off
    # (independent route: a second model run), to first order: moving the station by d
    # changes the light time, hence the bounce epoch, which adds (û·v/c)(û·d) (relative
    # |ρ̇|/c < 2.5e-5); the second-order term d²/(2ρ) is < 6 µm. The runs are without
    # troposphere: moving the station or the reflector by metres also tilts the line of
    # sight and moves the delay at 10° elevation by up to 0.2 mm.
    _, nps, sta, ecc = noisy

    def run(ecc_ds=ecc, offset=OFFSET_BODY_M, **switches):
        return slr_residuals(truth, nps, sta, ecc_ds, retro_offset_body_m=offset,
                             settings=dataclasses.replace(SLR, troposphere=False, **switches))

    base = run()
    ref = base["residual_m"].values
    _assert_term(run(ecc_ds=None)["residual_m"] - ref, base["eccentricity_range_m"])
    for switch, term in (("solid_tide", "solid_tide_range_m"),
                         ("pole_tide", "pole_tide_range_m")):
        off = run(**{switch: False})
        _assert_term(off["residual_m"] - ref, base[term])
        np.testing.assert_array_equal(off[term], 0.0)
    _assert_term(ref - run(offset=np.zeros(3))["residual_m"], -base["reflector_offset_range_m"])
    # the terms do not depend on the troposphere switch
    for term in ("eccentricity_range_m", "solid_tide_range_m", "reflector_offset_range_m"):
        np.testing.assert_allclose(base[term], res_noisy[term], rtol=0, atol=1e-9)
    # magnitudes: eccentricities of up to 3.2 m (ILRS ecc_xyz.snx), solid tide < 0.45 m,
    # pole tide < 2.5 cm (IERS 2010 ch. 7), offset < |offset| = 1.47 m
    assert np.abs(res_noisy["eccentricity_range_m"]).max() > 1.0
    assert 0.02 < np.abs(res_noisy["solid_tide_range_m"]).max() < 0.45
    assert np.abs(res_noisy["pole_tide_range_m"]).max() < 0.025
    assert np.abs(res_noisy["reflector_offset_range_m"]).max() < np.linalg.norm(OFFSET_BODY_M)


@pytest.mark.parametrize("offset_rtn_m", [(0.02, 0.0, 0.0), (0.01, -0.03, 0.02)])
def test_shifted_orbit_gives_offset_on_line_of_sight(truth, clean, offset_rtn_m):
    # Noise-free closed loop with an orbit moved by a constant RTN offset δ: residual =
    # −e·δ (e = unit line of sight station -> satellite, Wang et al. 2024, eq. 16) within 0.2 mm
    # (CRD 1-ps resolution 0.15 mm), and the least-squares RTN offset recovers δ (0.5 mm).
    _, nps, sta, ecc = clean
    shifted = _shifted(truth, offset_rtn_m)
    res = slr_residuals(shifted, nps, sta, ecc, retro_offset_body_m=OFFSET_BODY_M,
                        settings=dataclasses.replace(SLR, outlier_k=50.0))
    assert np.all(res["flag"].values == 0)
    projected = -res["los_rtn"].values @ np.asarray(offset_rtn_m)
    np.testing.assert_allclose(res["residual_m"], projected, rtol=0, atol=2e-4)
    proj = rtn_projection(res)
    np.testing.assert_allclose(proj["offset_m"], offset_rtn_m, rtol=0, atol=5e-4)
    assert np.all(proj["sigma_offset_m"] < 1e-3)
    # Wang et al. (2024) Table 5: components ρ e_R, ρ e_T, ρ e_N add in quadrature to the range RMS
    assert float(np.sqrt((proj["rms_component_m"] ** 2).sum())) == \
        pytest.approx(float(proj["rms_range_m"]), rel=1e-12)


def test_time_varying_orbit_error_on_line_of_sight(truth, noisy, res_noisy):
    # Closed loop with an orbit error that varies along the orbit (once-per-revolution
    # along-track and radial, drifting cross-track, up to 4 cm): the residuals minus the
    # orbit error projected on the line of sight are the simulated noise (0.2 mm: CRD
    # resolution and the 3-ms difference between transmit and bounce epochs).
    sim, nps, sta, ecc = noisy
    t_s = (truth["time"].values - T0) / np.timedelta64(1, "s")
    phase = 2 * np.pi * t_s / 6300.0
    err = np.stack([0.01 * np.sin(phase), 0.03 * np.cos(phase), 0.02 * t_s / 86400.0], axis=1)
    pos = truth["pos_itrf_m"].values
    vel_in = truth["vel_itrf_m_s"].values + np.cross([0.0, 0.0, OMEGA_EARTH_RAD_S], pos)
    moved = truth.assign(pos_itrf_m=(("time", "xyz"), pos + np.einsum(
        "nji,nj->ni", rtn_matrix(pos, vel_in), err)))
    res = slr_residuals(moved, nps, sta, ecc, retro_offset_body_m=OFFSET_BODY_M, settings=SLR)
    assert np.all(res["flag"].values == 0)
    explained = line_of_sight_orbit_difference(res, moved, truth)
    assert np.abs(explained).max() > 0.02
    np.testing.assert_allclose(res["residual_m"] - explained, sim["noise_m"], rtol=0,
                               atol=2e-4)


def test_rtn_offset_with_noise(truth, noisy):
    # With 5 mm noise the estimate stays within 4 formal sigmas of the true offset, and the
    # a-posteriori sigma of unit weight is the noise (within 10 %).
    _, nps, sta, ecc = noisy
    offset = np.array([0.0, 0.02, -0.01])
    res = slr_residuals(_shifted(truth, offset), nps, sta, ecc,
                        retro_offset_body_m=OFFSET_BODY_M, settings=SLR)
    proj = rtn_projection(res)
    assert np.all(np.abs(proj["offset_m"].values - offset) < 4 * proj["sigma_offset_m"].values)
    assert float(proj["sigma0_m"]) == pytest.approx(NOISE_M, rel=0.1)


# ------------------------------------------------------------------- epochs and CRD flags
def test_epoch_events(truth, noisy, res_noisy):
    # CRD 2.01 epoch events: 0 = ground receive time (transmit + tof), 1 = spacecraft bounce
    # time (transmit + uplink light time of the simulation truth). Same residuals as for
    # event 2 within 0.02 mm (the epochs are rounded to 1 ns: 7 µm at 7 km/s).
    sim, nps, sta, ecc = noisy
    tof_ns = np.round(nps["tof_s"].values * 1e9).astype("timedelta64[ns]")
    up_ns = np.round(sim["light_time_up_s"].values * 1e9).astype("timedelta64[ns]")
    event = np.arange(nps.sizes["point"]) % 3
    time = nps["time"].values + np.where(event == 0, tof_ns, np.where(event == 1, up_ns,
                                                                       np.timedelta64(0)))
    moved = nps.assign(epoch_event=("point", event)).assign_coords(time=("point", time))
    res = slr_residuals(truth, moved, sta, ecc, retro_offset_body_m=OFFSET_BODY_M, settings=SLR)
    assert np.all(res["flag"].values == 0)
    np.testing.assert_allclose(res["residual_m"], res_noisy["residual_m"], rtol=0, atol=2e-5)
    # the transmit epoch is recovered (to the iteration tolerance and the 1-ns rounding)
    diff = (res["time_transmit_gps"].values - res_noisy["time_transmit_gps"].values)
    assert np.abs(diff.astype(np.int64)).max() <= 3


def test_refraction_and_centre_of_mass_flags(truth, noisy, res_noisy):
    # CRD H4 flags: with refraction applied the range holds no tropospheric delay (none is
    # modelled); with the centre-of-mass correction applied the range refers to the centre
    # of mass (no reflector offset). Ranges corrected accordingly give the same residuals,
    # within 0.15 mm: moving the target by the 1.5-m offset tilts the line of sight by up to
    # 1e-6 rad, which changes the delay at 10° elevation (78 m/rad) by up to 0.1 mm.
    _, nps, sta, ecc = noisy
    n = nps.sizes["point"]
    refr = np.arange(n) % 2 == 0
    com = np.arange(n) % 3 == 0
    one_way = (0.5 * C_LIGHT_M_S * nps["tof_s"].values
               - np.where(refr, res_noisy["tropo_delay_m"].values, 0.0)
               - np.where(com, res_noisy["reflector_offset_range_m"].values, 0.0))
    pressure = np.where(refr, np.nan, nps["pressure_hpa"].values)  # not needed there
    changed = nps.assign(tof_s=("point", 2 * one_way / C_LIGHT_M_S),
                         refraction_applied=("point", refr.astype(np.int8)),
                         com_applied=("point", com.astype(np.int8)),
                         pressure_hpa=("point", pressure))
    res = slr_residuals(truth, changed, sta, ecc, retro_offset_body_m=OFFSET_BODY_M, settings=SLR)
    assert np.all(res["flag"].values == 0)
    np.testing.assert_allclose(res["residual_m"], res_noisy["residual_m"], rtol=0,
                               atol=1.5e-4)
    np.testing.assert_allclose(res["residual_m"].values[~com], res_noisy["residual_m"].values[
        ~com], rtol=0, atol=1e-9)
    np.testing.assert_array_equal(res["tropo_delay_m"].values[refr], 0.0)


def _une(ecc_xyz: np.ndarray, pos: np.ndarray) -> np.ndarray:
    """XYZ eccentricity in up, north, east: axes from finite differences of erfa.gd2gc."""
    lon, lat, h = erfa.gc2gde(WGS84_A_M, 1.0 / WGS84_INV_F, pos)
    axes = []
    for dlon, dlat, dh in ((0, 0, 1.0), (0, 1e-7, 0), (1e-7, 0, 0)):
        d = (erfa.gd2gce(WGS84_A_M, 1.0 / WGS84_INV_F, lon + dlon, lat + dlat, h + dh)
             - erfa.gd2gce(WGS84_A_M, 1.0 / WGS84_INV_F, lon - dlon, lat - dlat, h - dh))
        axes.append(d / np.linalg.norm(d))
    return np.array(axes) @ ecc_xyz


def test_une_eccentricities(tmp_path, truth, noisy, res_noisy):
    # ILRS eccentricities may be given as up/north/east: the same vectors expressed in UNE
    # (axes built independently by finite differences of erfa.gd2gce) give the same
    # residuals (files to 0.1 mm).
    _, nps, sta, _ = noisy
    une = np.array([_une(np.array(s.ecc_xyz_m), np.array(s.pos_itrf_m))
                    for s in DEFAULT_STATIONS])
    ds = xr.Dataset({"site": ("record", [s.pad_id for s in DEFAULT_STATIONS]),
                     "ref_system": ("record", ["UNE"] * len(DEFAULT_STATIONS)),
                     "ecc_m": (("record", "component"), une)})
    write_sinex_eccentricities(ds, tmp_path / "une.snx")
    ecc = read_sinex_eccentricities(tmp_path / "une.snx")
    assert ecc.attrs["ref_system"] == "UNE"
    res = slr_residuals(truth, nps, sta, ecc, retro_offset_body_m=OFFSET_BODY_M, settings=SLR)
    np.testing.assert_allclose(res["residual_m"], res_noisy["residual_m"], rtol=0, atol=2e-4)


def test_ocean_loading_applied(truth, noisy, res_noisy):
    # BLQ coefficients for one station (found by its CRD station name): its residuals change
    # by minus the loading's range term, the others not at all.
    _, nps, sta, ecc = noisy
    blq = xr.Dataset(
        {"amplitude_m": (("site", "component", "constituent"), np.full((1, 3, 11), 0.01)),
         "phase_deg": (("site", "component", "constituent"), np.full((1, 3, 11), 40.0))},
        coords={"site": ["YARL"], "component": list(BLQ_COMPONENTS),
                "constituent": list(BLQ_CONSTITUENTS)})
    res = slr_residuals(truth, nps, sta, ecc, retro_offset_body_m=OFFSET_BODY_M,
                        ocean_loading=blq, settings=SLR)
    at = res["station"].values == "7090"
    term = res["ocean_loading_range_m"].values
    assert np.abs(term[at]).max() > 1e-3 and np.all(term[~at] == 0.0)
    _assert_term(res_noisy["residual_m"] - res["residual_m"], term)


# ------------------------------------------------------------------------------ screening
def test_screening(truth, noisy):
    # Each rejection reason on purpose-made points; the robust test (5 robust sigmas of
    # 5 mm) rejects +0.3 m, the hard limit (0.5 m, BDS SCB-AR paper) +1 m.
    _, nps, sta, ecc = noisy
    nps = nps.copy(deep=True)
    tof = nps["tof_s"].values
    tof[[10, 20, 30]] += 2 * 0.3 / C_LIGHT_M_S
    tof[[40, 50]] += 2 * 1.0 / C_LIGHT_M_S
    nps["station"].values[60] = "9999"
    nps["pressure_hpa"].values[70] = np.nan
    nps["epoch_event"].values[80] = 3
    nps["range_type"].values[90] = 1
    time = nps["time"].values.copy()
    time[100] += np.timedelta64(2, "D")
    nps = nps.assign_coords(time=("point", time))
    settings = dataclasses.replace(SLR, elevation_cut_off_deg=15.0)
    res = slr_residuals(truth, nps, sta, ecc, retro_offset_body_m=OFFSET_BODY_M,
                        settings=settings)
    reason = res["reason"].values
    expected = {10: "outlier", 20: "outlier", 30: "outlier", 40: "hard_limit",
                50: "hard_limit", 60: "no_station", 70: "no_meteo", 80: "epoch_event",
                90: "range_type", 100: "no_orbit"}
    low = res["elevation_deg"].values < 15.0
    for i, why in expected.items():
        assert reason[i] == why or (low[i] and reason[i] == "elevation"), i
    others = np.setdiff1d(np.arange(reason.size), list(expected))
    np.testing.assert_array_equal(reason[others], np.where(low[others], "elevation", "used"))
    assert np.isnan(res["residual_m"].values[[60, 70, 80, 90, 100]]).all()
    codes = {v: k for k, v in REJECTION_REASONS.items()}
    np.testing.assert_array_equal(res["flag"].values, [codes[r] for r in reason])
    used = res["flag"].values == 0
    assert int(station_statistics(res).sel(station="total")["n_np"]) == used.sum()


def test_missing_crd_fields_default():
    # Only tof_s and station are required (CRD epoch event 2 and two-way ranges assumed).
    with pytest.raises(ValueError, match="tof_s"):
        slr_residuals(_truth(), xr.Dataset({"station": ("point", ["7090"])},
                                           coords={"time": ("point", [T0])}),
                      xr.Dataset(), retro_offset_body_m=np.zeros(3), settings=SLR)


# ----------------------------------------------------------------------------- statistics
def test_station_and_elevation_statistics(res_noisy):
    # Definitions (Peng et al. 2021, Table IV; Figs. 17-18): per station count, mean, sample STD,
    # RMS of the used residuals, recomputed here with numpy; 5° bins partition the points.
    st = station_statistics(res_noisy)
    res = res_noisy["residual_m"].values
    sites = res_noisy["station"].values
    assert list(st["station"].values[:-1]) == sorted(set(sites))
    for s in sorted(set(sites)):
        r = res[sites == s]
        row = st.sel(station=s)
        assert int(row["n_np"]) == r.size
        assert float(row["mean_m"]) == pytest.approx(r.mean(), abs=1e-15)
        assert float(row["std_m"]) == pytest.approx(r.std(ddof=1), abs=1e-15)
        assert float(row["rms_m"]) == pytest.approx(np.sqrt(np.mean(r**2)), abs=1e-15)
    assert int(st.sel(station="total")["n_np"]) == res.size
    el = elevation_statistics(res_noisy, bin_deg=5.0)
    np.testing.assert_allclose(el["elevation_deg"], np.arange(2.5, 90.0, 5.0))
    assert int(el["n_np"].sum()) == res.size
    in_bin = (res_noisy["elevation_deg"] >= 20) & (res_noisy["elevation_deg"] < 25)
    assert float(el.sel(elevation_deg=22.5)["std_m"]) == \
        pytest.approx(res[in_bin.values].std(ddof=1), abs=1e-15)
    assert int(el.sel(elevation_deg=2.5)["n_np"]) == 0
    assert np.isnan(float(el.sel(elevation_deg=2.5)["std_m"]))


def test_statistics_of_nothing(res_noisy):
    # No used point: NaN statistics, no warning (pyproject turns RuntimeWarnings into errors).
    none = res_noisy.assign(flag=("point", np.full(res_noisy.sizes["point"], 7, np.int8)))
    assert int(station_statistics(none)["n_np"].sum()) == 0
    assert np.isnan(rtn_projection(none)["offset_m"]).all()
    assert int(elevation_statistics(none)["n_np"].sum()) == 0


# ------------------------------------------------------------------------------ real data
@pytest.mark.shared
def test_real_crd_and_slrf_stations(shared_data):
    # Real CRD 1 and 2 normal points (LAGEOS, Jason-1, ...) with the ILRS SLRF2020 station
    # file and eccentricities: every real station is found; SLRF2014 (independent solution)
    # gives markers within 2 cm at the epochs for the core stations; Yarragadee's reference
    # point is its marker + its ILRS eccentricity (3.2 m) + tides < 0.45 m.
    slr = shared_data / "slr"
    nps = xr.concat([read_crd(slr / "crd201_all_samples"), read_crd(slr / "lageos1-test.npt"),
                     read_crd(slr / "lageos2_201802.npt.v2C")], dim="point")
    s20 = read_sinex_stations(slr / "SLRF2020_POS+VEL_2023.10.02.snx")
    s14 = read_sinex_stations(slr / "SLRF2014_POS+VEL_2030.0_180504.snx")
    ecc = read_sinex_eccentricities(slr / "ecc_xyz.snx")
    pts = station_reference_points(nps, s20, ecc, settings=SLR)
    sites = nps["station"].values
    np.testing.assert_array_equal(pts["flag"].values, np.where(sites == "9998", 2, 0))
    other = station_reference_points(nps, s14, None, settings=dataclasses.replace(
        SLR, solid_tide=False, pole_tide=False))
    core = np.isin(sites, ["7080", "7090", "7810", "7839", "7840"])
    diff = pts["pos_marker_itrf_m"].values[core] - other["pos_marker_itrf_m"].values[core]
    assert core.sum() > 50 and np.linalg.norm(diff, axis=1).max() < 0.02
    yarra = sites == "7090"
    offset = pts["pos_station_itrf_m"].values[yarra] - pts["pos_marker_itrf_m"].values[yarra]
    disp = offset - np.array([-1.2073, 2.5034, -1.5509])
    assert np.all(np.linalg.norm(disp, axis=1) < 0.45)
    np.testing.assert_allclose(disp, pts["solid_tide_itrf_m"].values[yarra]
                               + pts["pole_tide_itrf_m"].values[yarra], rtol=0, atol=1e-9)


@pytest.mark.shared
def test_eccentricity_file_round_trip(shared_data, tmp_path):
    # The ILRS eccentricity file (554 records, intervals, CDP SODs) written by
    # write_sinex_eccentricities and read back: identical records (values to 0.1 mm, the
    # resolution of the ILRS file; epochs to 1 s).
    ecc = read_sinex_eccentricities(shared_data / "slr" / "ecc_xyz.snx")
    write_sinex_eccentricities(ecc, tmp_path / "ecc.snx")
    back = read_sinex_eccentricities(tmp_path / "ecc.snx")
    for name in ("site", "pt", "soln", "ref_system", "valid_from", "valid_to", "cdp_sod"):
        np.testing.assert_array_equal(back[name].values, ecc[name].values)
    np.testing.assert_allclose(back["ecc_m"], ecc["ecc_m"], rtol=0, atol=5e-5)


def test_eccentricity_writer_rejects_bad_input(tmp_path):
    good = xr.Dataset({"site": ("record", ["7090"]), "ref_system": ("record", ["XYZ"]),
                       "ecc_m": (("record", "component"), [[1.0, 2.0, 3.0]])})
    for bad, message in ((good.assign(ref_system=("record", ["NEU"])), "neither"),
                         (good.assign(site=("record", ["70900"])), "1-4 characters"),
                         (good.assign(ecc_m=(("record", "component"), [[np.nan, 0, 0]])),
                          "finite"),
                         (good.drop_vars("ecc_m"), "ecc_m")):
        with pytest.raises(ValueError, match=message):
            write_sinex_eccentricities(bad, tmp_path / "bad.snx")
