"""BDS-2 satellite-induced code bias (SCB): simulated onboard B1I/B3I passes, closed loop.

The simulator (leopod.simulate.observations, ``bds2_scb``) adds the SCB of Wanninger & Beer
(2015) to the B1I/B3I codes of the BDS-2 IGSO and MEO satellites of a nominal BDS-2
constellation, as seen by a 500-km LEO over one day (integer ambiguities, code and phase
biases, white noise). The correction (leopod.codebias.scb) is computed on another path: the
nadir angles from the satellites' positions at the nominal epochs (no light time) and the
nominal orbit radii, as the quality step does from the ingest outputs.

Authority (issue 19, "Done when"; BDS SCB-AR paper, eqs. 4-5): the HMW pass means minus the
true wide-lane biases are the integer wide-lane ambiguities within 0.1 cycle only with the
correction, since the SCB adds ``(f1 d1 + f2 d2)/((f1 + f2) λ_WL)`` cycles to the HMW
combination. The simulator's SCB and the correction use the same published table: the test
checks the geometry (nadir angle at the BDS satellite, equivalent elevation), the bands, the
satellite types and the sign convention end to end, not the table itself
(tests/gnss/test_scb.py does that).
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
import xarray as xr

from leopod.codebias.scb import NADIR_VARIABLE, correct_bds2_scb
from leopod.constants import C_LIGHT_M_S, R_EARTH_EQUATOR_M
from leopod.gnss.combinations import melbourne_wuebbena, wide_lane_wavelength_m
from leopod.gnss.scb import BDS2_ORBIT_TYPE, nadir_angle_deg
from leopod.simulate.biases import SimulatedBiases, wide_lane_bias_cyc
from leopod.simulate.observations import GnssWorld, ObservationSettings, simulate_observations
from leopod.simulate.world import CircularOrbit, RandomWalkClock, beidou2_constellation
from leopod.workflow.config import with_defaults

EPOCH = np.datetime64("2019-01-01T00:00:00", "ns")
F1, F3 = 1561.098e6, 1268.52e6                      # B1I, B3I (BDS-SIS-ICD)
CODES = ("C2I", "C6I")
PHASES = ("L2I", "L6I")
#: Assumed onboard B1I/B3I code noise at 30° antenna elevation [m] (no published onboard
#: value at hand; of the order of the BDS-3 defaults of the simulator).
NOISE_M = {"C2I": 0.15, "C6I": 0.15, "L2I": 0.0015, "L6I": 0.0015}
#: Shortest pass used: 20 min of 30-s epochs (BDS SCB-AR paper: "any DD ambiguity with
#: observation segment longer than 20 min is considered").
MIN_EPOCHS = 40


def _biases(svs, rng) -> SimulatedBiases:
    """Random satellite and receiver code (±1 m) and phase (±0.5 cycle) biases."""
    n = len(svs)
    return SimulatedBiases(
        code_sat_m=xr.DataArray(rng.uniform(-1, 1, (n, 2)), dims=("sv", "code_signal"),
                                coords={"sv": svs, "code_signal": list(CODES)}),
        phase_sat_cyc=xr.DataArray(rng.uniform(-0.5, 0.5, (n, 2)), dims=("sv", "phase_signal"),
                                   coords={"sv": svs, "phase_signal": list(PHASES)}),
        phase_drift_sat_cyc_s=xr.DataArray(np.zeros(n), dims="sv", coords={"sv": svs}),
        code_rx_m=xr.DataArray(rng.uniform(-1, 1, (1, 2)), dims=("system", "code_signal"),
                               coords={"system": ["C"], "code_signal": list(CODES)}),
        phase_rx_cyc=xr.DataArray(rng.uniform(-0.5, 0.5, (1, 2)), dims=("system", "phase_signal"),
                                  coords={"system": ["C"], "phase_signal": list(PHASES)}),
        epoch=EPOCH, phase_pairs={"C": PHASES})


def _truth(leo: CircularOrbit, hours: float) -> xr.Dataset:
    t = np.arange(-300.0, hours * 3600.0 + 301.0, 10.0)
    pos, vel = leo.inertial(t)
    return xr.Dataset({"pos_gcrf_m": (("time", "xyz"), pos),
                       "vel_gcrf_m_s": (("time", "xyz"), vel)},
                      coords={"time": EPOCH + (t * 1e9).astype("timedelta64[ns]")})


@functools.lru_cache(maxsize=1)
def simulated_day(hours: float = 24.0):
    """Simulated observations, the LEO truth and the biases of one day (cached)."""
    rng = np.random.default_rng(2015)
    orbits = beidou2_constellation()
    svs = sorted(orbits)
    world = GnssWorld(EPOCH, orbits, {sv: RandomWalkClock(rng.uniform(-1e-4, 1e-4), 0.0, 1e-12,
                                                         k) for k, sv in enumerate(svs)})
    leo = CircularOrbit(R_EARTH_EQUATOR_M + 500e3, 97.4, 30.0, 0.0)
    truth = _truth(leo, hours)
    biases = _biases(svs, rng)
    settings = ObservationSettings.from_config(
        with_defaults("simulate_observations", {"noise_m": NOISE_M}))
    assert settings.bds2_scb                          # the schema's default
    times = EPOCH + np.arange(int(hours * 120)) * np.timedelta64(30, "s")
    obs = simulate_observations(times, truth, world, RandomWalkClock(1e-6, 0.0, 1e-10, 99),
                                biases, {"C": [*CODES, *PHASES]},
                                {"B1I": [0.0, 0.0, -0.3], "B3I": [0.0, 0.0, -0.3]}, (),
                                settings, rng)
    return obs, truth, world, leo, biases


def _scb_corrected(obs, world, leo):
    """The observations with the SCB correction at the nadir angles of this geometry, and the
    correction's summary (computed apart from the simulator's own geometry)."""
    svs = [str(s) for s in obs.sv.values]
    t = (obs.time.values - EPOCH) / np.timedelta64(1, "s")
    sv_pos, _ = world.state_gcrf(svs, np.repeat(t[:, None], len(svs), axis=1))
    leo_pos, _ = leo.inertial(t)
    nadir = xr.Dataset({NADIR_VARIABLE: (("time", "sv"),
                                         nadir_angle_deg(sv_pos, leo_pos[:, None, :]))},
                       coords={"time": obs.time, "sv": obs.sv})
    return correct_bds2_scb(obs, nadir)


def pass_offsets(corrected: bool):
    """HMW pass mean − true WL biases − true integer [cycles] per pass, with the satellite of
    each pass; the SCB correction applied to the codes first if ``corrected``."""
    obs, _, world, leo, biases = simulated_day()
    svs = [str(s) for s in obs.sv.values]
    if corrected:
        obs, summary = _scb_corrected(obs, world, leo)
        assert set(summary) == set(CODES)
    hmw = melbourne_wuebbena(obs.L2I.values * C_LIGHT_M_S / F1, obs.L6I.values * C_LIGHT_M_S / F3,
                             obs.C2I.values, obs.C6I.values, F1, F3) / wide_lane_wavelength_m(F1, F3)
    w_sat = wide_lane_bias_cyc(*(biases.code_sat_m.sel(code_signal=c).values for c in CODES),
                               *(biases.phase_sat_cyc.sel(phase_signal=p).values for p in PHASES),
                               F1, F3)
    w_rx = float(wide_lane_bias_cyc(*(biases.code_rx_m.sel(code_signal=c).values[0] for c in CODES),
                                    *(biases.phase_rx_cyc.sel(phase_signal=p).values[0]
                                      for p in PHASES), F1, F3))
    n_wl = obs.amb_L2I_cyc.values - obs.amb_L6I_cyc.values
    passes = obs.pass_true.values
    offsets, sats = [], []
    for p in np.unique(passes[passes >= 0]):
        sel = (passes == p) & np.isfinite(hmw)
        if sel.sum() < MIN_EPOCHS:
            continue
        col = np.nonzero(sel)[1][0]
        offsets.append(np.mean(hmw[sel]) - w_sat[col] - w_rx - n_wl[sel][0])
        sats.append(svs[col])
    return np.array(offsets), np.array(sats)


def test_scb_puts_hmw_pass_means_off_the_integers_and_the_correction_brings_them_back():
    raw, sats = pass_offsets(corrected=False)
    fixed, sats_fixed = pass_offsets(corrected=True)
    np.testing.assert_array_equal(sats, sats_fixed)
    scb = np.array([s in BDS2_ORBIT_TYPE for s in sats])
    kinds = {BDS2_ORBIT_TYPE[s] for s in sats[scb]}
    assert kinds == {"IGSO", "MEO"} and scb.sum() >= 10 and (~scb).sum() >= 3
    # without the correction: IGSO/MEO pass means off the integers by more than 0.1 cycle
    assert np.sum(np.abs(raw[scb]) > 0.1) >= 5
    assert np.max(np.abs(raw[scb])) > 0.2
    # and not by a constant per satellite that a satellite wide-lane bias would absorb: the
    # pass-to-pass variation alone exceeds 0.1 cycle for many passes
    spread = np.concatenate([raw[sats == s] - raw[sats == s].mean() for s in set(sats[scb])])
    assert np.sum(np.abs(spread) > 0.1) >= 10
    # with it: every pass mean within 0.1 cycle of its integer
    assert np.max(np.abs(fixed)) < 0.1
    # GEO passes carry no SCB and are left alone
    np.testing.assert_array_equal(raw[~scb], fixed[~scb])
    assert np.max(np.abs(raw[~scb])) < 0.1


def test_simulated_scb_is_minus_the_correction():
    """The simulator adds −Δ (codes too short where Δ > 0); the correction adds +Δ back: the
    corrected codes minus the uncorrected ones are −(the simulated SCB) on every tracked
    BDS-2 IGSO/MEO code, within the difference of the two geometries (< 1 mm)."""
    obs, _, world, leo, _ = simulated_day()
    fixed, _ = _scb_corrected(obs, world, leo)
    for code in CODES:
        applied = fixed[code].values - obs[code].values
        simulated = obs[f"scb_{code}_m"].values
        ok = np.isfinite(simulated)
        assert ok.sum() > 1000
        np.testing.assert_allclose(applied[ok], -simulated[ok], atol=1e-3)
        assert np.nanmax(np.abs(simulated)) > 0.3
    with pytest.raises(KeyError, match=NADIR_VARIABLE):
        correct_bds2_scb(obs, xr.Dataset())
