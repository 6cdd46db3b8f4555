"""Tests of leopod.simulate.truth_orbit: the truth LEO orbit of the closed-loop simulator.

Authorities: the published HY-2 orbit (sun-synchronous, 99.34° at ~971 km: Peng et al. 2021 and
Wang et al. 2024, ILRS HY-2B mission page); the analytic sun-synchronous condition (node rate of
360° per tropical year, Vallado 2013 ch. 11) measured on the integrated GCRF orbit itself;
spherical trigonometry of the orbit normal and the Sun (local time of the ascending node);
circular-orbit identities; sample statistics of the random draws (standard errors
σ/sqrt(2n) of a sample standard deviation); direct evaluation of the built force model
(projections onto the RTN axes); the inverse frame transformation
(:func:`leopod.frames.earth_rotation.itrf_to_gcrf`); the SP3-d resolution (1 mm, 1e-7 m/s;
Hilla 2016) for the file round trip.
"""

from __future__ import annotations

import erfa
import numpy as np
import pytest
import xarray as xr

from leopod.astro.ephemeris import Ephemeris
from leopod.constants import (
    GM_EARTH_M3_S2,
    GPST_MINUS_TAI_S,
    OMEGA_EARTH_RAD_S,
    R_EARTH_EQUATOR_M,
    TT_MINUS_TAI_S,
)
from leopod.dynamics.drag import Drag
from leopod.dynamics.empirical import Empirical
from leopod.dynamics.force_config import ForceModelSettings, build_force_model
from leopod.dynamics.forces import apriori_parameters
from leopod.dynamics.integrator import integrate
from leopod.frames.earth_rotation import itrf_to_gcrf
from leopod.frames.rtn import rtn_matrix
from leopod.io.sp3 import read_sp3
from leopod.simulate.truth_forces import TruthDynamics, default_models, truth_force_config
from leopod.simulate.truth_orbit import (
    HY2B_ALTITUDE_M,
    SUN_SYNCHRONOUS_NODE_RATE_RAD_S,
    initial_state_sun_synchronous,
    simulate_truth_orbit,
    sun_synchronous_inclination_deg,
    write_truth_files,
)
from leopod.time.calendar import J2000_TT, seconds_since
from leopod.time.scales import jd_tt

T0 = np.datetime64("2019-01-01T00:00:00", "ns")
ARC_S = 3600.0
SEED = 7
#: Low-degree truth for fast tests (the physics of the other forces is unchanged).
LOW = TruthDynamics.from_config({"gravity_degree": 12})
DAY_S = 86_400.0
#: Standard deviations of the stochastic accelerations in R, T, N [m/s²] (the assignment).
SIGMA_RTN_M_S2 = np.array([2e-8, 5e-8, 3e-8])


@pytest.fixture(scope="module")
def truth() -> xr.Dataset:
    return simulate_truth_orbit(T0, T0 + np.timedelta64(int(ARC_S), "s"), seed=SEED,
                                dynamics=LOW)


@pytest.fixture(scope="module")
def one_day():
    """The HY-2B initial state integrated for one day in ITU_GRACE16 to degree 8 (60-s outputs)."""
    model = build_force_model(ForceModelSettings.from_config({"gravity": {"field": default_models()["gravity_field"],
                                           "max_degree": 8}}), T0, 0.0, DAY_S)
    state0 = initial_state_sun_synchronous(T0)
    return integrate(model, 0.0, state0, apriori_parameters(model),
                     np.arange(0.0, DAY_S + 1.0, 60.0), step_s=30.0, with_partials=False)


# ------------------------------------------------------------------------- initial state


def test_sun_synchronous_inclination_of_hy2b():
    # authority: published HY-2A/B orbit, 99.34° at 971 km (Wang et al. 2024, sec. 1;
    # Peng et al. 2021: ~970 km and 99.34°; ILRS: 99.35°)
    inc = sun_synchronous_inclination_deg(R_EARTH_EQUATOR_M + HY2B_ALTITUDE_M)
    assert abs(inc - 99.34) < 0.02


def test_no_sun_synchronous_orbit_above_12000_km():
    # authority: analytic — |cos i| would exceed 1 (J2 too weak so far out)
    with pytest.raises(ValueError):
        sun_synchronous_inclination_deg(R_EARTH_EQUATOR_M + 8.0e6)


def test_initial_state_is_circular_at_the_altitude():
    state = initial_state_sun_synchronous(T0, 971e3, 18.0, u0_deg=37.0)
    pos, vel = state[:3], state[3:]
    a_m = R_EARTH_EQUATOR_M + 971e3
    # authority: circular orbit, |r| = a, |v| = sqrt(GM/a), r ⟂ v
    assert abs(np.linalg.norm(pos) - a_m) < 1e-6
    assert abs(np.linalg.norm(vel) - np.sqrt(GM_EARTH_M3_S2 / a_m)) < 1e-9
    assert abs(pos @ vel) / (np.linalg.norm(pos) * np.linalg.norm(vel)) < 1e-14
    h = _true_equator(T0) @ np.cross(pos, vel)
    inc = np.degrees(np.arccos(h[2] / np.linalg.norm(h)))
    # the inclination is to the true equator (of the CIP), ERFA's frame to 1 mas
    assert abs(inc - sun_synchronous_inclination_deg(a_m)) < 1e-6


def _true_equator(epoch) -> np.ndarray:
    """GCRF -> celestial intermediate frame (CIP equator, CIO origin), straight from ERFA:
    IAU 2006/2000A X, Y, s (erfa.xys06a) and erfa.c2ixys (IERS 2010 eq. 5.7)."""
    return erfa.c2ixys(*erfa.xys06a(*jd_tt(np.atleast_1d(epoch))))[0]


@pytest.mark.parametrize("ltan_h, sign", [(18.0, 1.0), (6.0, -1.0), (12.0, 0.0)])
def test_local_time_of_ascending_node(ltan_h, sign):
    state = initial_state_sun_synchronous(T0, 971e3, ltan_h)
    to_cirs = _true_equator(T0)
    h = to_cirs @ np.cross(state[:3], state[3:])
    h /= np.linalg.norm(h)
    inc = np.arccos(h[2])
    tt_s = seconds_since(T0, J2000_TT) + TT_MINUS_TAI_S - GPST_MINUS_TAI_S
    sun = to_cirs @ Ephemeris().sun_m(np.atleast_1d(tt_s))[0]
    sun /= np.linalg.norm(sun)
    dec = np.arcsin(sun[2])
    # authority: spherical trigonometry. With the node 90° east (18 h), west (6 h) of the Sun
    # or at the Sun (12 h): h·ŝ = ±sin i cos δ + cos i sin δ (sign 0 for noon)
    expected = sign * np.sin(inc) * np.cos(dec) + np.cos(inc) * np.sin(dec)
    assert abs(h @ sun - expected) < 1e-12
    # authority: local solar time of the node = 12 h + (RA(node) − RA(Sun)) · 12 h/π
    node = np.arctan2(h[0], -h[1])
    hour = ((node - np.arctan2(sun[1], sun[0])) * 12.0 / np.pi + 12.0) % 24.0
    assert abs(hour - ltan_h) < 1e-9
    # authority: published HY-2 inclination (99.34°) to the true equator
    assert abs(np.degrees(inc) - 99.34) < 0.02


@pytest.mark.parametrize("ltan_h", [18.0, 12.0, 3.0])
def test_integrated_node_rate_is_sun_synchronous(ltan_h):
    model = build_force_model(ForceModelSettings.from_config({"gravity": {"field": default_models()["gravity_field"],
                                           "max_degree": 8}}), T0, 0.0, DAY_S)
    traj = integrate(model, 0.0, initial_state_sun_synchronous(T0, ltan_h=ltan_h),
                     apriori_parameters(model), np.arange(0.0, DAY_S + 1.0, 60.0), step_s=30.0,
                     with_partials=False)
    # node on the true equator (J2 precesses the orbit about the CIP, which moves 0.05"/day)
    h = np.cross(traj.states[:, :3], traj.states[:, 3:]) @ _true_equator(T0).T
    node = np.unwrap(np.arctan2(h[:, 0], -h[:, 1]))
    rate = np.polyfit(traj.t_s, node, 1)[0]
    # authority: analytic sun-synchronous condition, 360° per tropical year = 0.9856°/d.
    # Tolerance 0.5%: the J2 formula ignores J2², J4 and the osculating-to-mean differences
    # of a and i (measured: +0.1 to +0.36% in EGM96 to degree 8, +0.40% with J2 alone, for
    # any LTAN); ignoring the 0.1° between the CIP and the GCRF pole would
    # change it by up to ±1.5%.
    assert rate == pytest.approx(SUN_SYNCHRONOUS_NODE_RATE_RAD_S, rel=5e-3)
    assert np.degrees(rate) * DAY_S == pytest.approx(0.9856, abs=0.005)


def test_mean_altitude(one_day):
    radius = np.linalg.norm(one_day.states[:, :3], axis=1)
    # authority: the requested altitude; tolerance 10 km = J2 short-period terms of the
    # osculating circular start (3/2 J2 R²/a ≈ 9 km), HY-2B eccentricity 0.00117 (≈ 9 km)
    assert abs(radius.mean() - R_EARTH_EQUATOR_M - HY2B_ALTITUDE_M) < 10e3
    assert radius.max() - radius.min() < 30e3


# ----------------------------------------------------------------------- truth forces


def test_stochastic_accelerations_have_the_prescribed_sigma():
    forces = truth_force_config(60 * DAY_S, seed=11)
    acc = forces.stochastic_acc_rtn_m_s2
    n = acc.shape[0]
    assert n == 60 * 144                       # 10-min intervals
    # authority: sample statistics of N(0, σ²): relative standard error of the sample std
    # 1/sqrt(2n) = 0.6%, of the mean σ/sqrt(n); bounds at ~5 standard errors
    assert np.allclose(acc.std(axis=0) / SIGMA_RTN_M_S2, 1.0, atol=0.03)
    assert np.all(np.abs(acc.mean(axis=0)) < 5.0 * SIGMA_RTN_M_S2 / np.sqrt(n))
    # independent components: correlation coefficients within 5/sqrt(n)
    corr = np.corrcoef(acc.T)
    assert np.all(np.abs(corr[np.triu_indices(3, 1)]) < 5.0 / np.sqrt(n))


def test_drag_scale_follows_its_model():
    forces = truth_force_config(60 * DAY_S, seed=12)
    edges = forces.drag_edges_s
    assert np.allclose(np.diff(edges), 5400.0)
    mid = 0.5 * (edges[:-1] + edges[1:])
    design = np.column_stack([np.ones_like(mid), np.sin(2 * np.pi * mid / DAY_S)])
    coef, *_ = np.linalg.lstsq(design, forces.drag_scale, rcond=None)
    resid = forces.drag_scale - design @ coef
    n = mid.size
    # authority: s = 1 + 0.15 sin(2π t/1 d) + N(0, 0.05²); least-squares standard errors
    # 0.05/sqrt(n) (mean) and 0.05 sqrt(2/n) (amplitude), bounds at ~5 of them
    assert abs(coef[0] - 1.0) < 5 * 0.05 / np.sqrt(n)
    assert abs(coef[1] - 0.15) < 5 * 0.05 * np.sqrt(2.0 / n)
    assert abs(resid.std() / 0.05 - 1.0) < 5.0 / np.sqrt(2 * n)


def test_truth_parameters_reach_the_force_model(truth):
    forces = truth_force_config(ARC_S, seed=SEED, dynamics=LOW)
    model = build_force_model(ForceModelSettings.from_config(forces.config), T0, 0.0, ARC_S)
    params = forces.parameter_vector(model)
    # the Dataset documents the values used
    assert np.array_equal(truth.stochastic_acc_rtn_m_s2.values, forces.stochastic_acc_rtn_m_s2)
    assert np.array_equal(truth.drag_scale.values, forces.drag_scale)
    names = model.parameters
    state = np.concatenate([truth.pos_gcrf_m.values[200], truth.vel_gcrf_m_s.values[200]])
    t_s = 200 * 10.0
    for force in model.forces:
        sl = [names.index(p) for p in force.parameters]
        if isinstance(force, Empirical):
            acc = force.evaluate(t_s, state[:3], state[3:], params[sl])[0]
            k = int(t_s // 600.0)
            # authority: RTN projection of the evaluated acceleration (empirical.rtn_matrix)
            assert np.allclose(rtn_matrix(state[:3], state[3:]) @ acc,
                               forces.stochastic_acc_rtn_m_s2[k], rtol=0, atol=1e-22)
        elif isinstance(force, Drag):
            acc, _, _, da_dp = force.evaluate(t_s, state[:3], state[3:], params[sl])
            k = int(t_s // 5400.0)
            # authority: the acceleration is s_k times the unscaled drag (∂a/∂s_k)
            assert np.allclose(acc, forces.drag_scale[k] * da_dp[:, k], rtol=1e-14, atol=0)
            assert np.linalg.norm(acc) > 0.0


def test_parameter_vector_needs_a_matching_arc():
    forces = truth_force_config(2 * ARC_S, seed=SEED, dynamics=LOW)
    model = build_force_model(ForceModelSettings.from_config(forces.config), T0, 0.0, ARC_S)
    # authority: the 2-h truth has intervals the 1-h force model does not have
    with pytest.raises(ValueError, match="not in the force model"):
        forces.parameter_vector(model)


# ------------------------------------------------------------------------------ orbit


def test_truth_dataset_layout(truth):
    n = int(ARC_S / 10.0) + 1
    # authority: the requested sampling, 10 s from t_start to t_end inclusive
    assert truth.sizes["time"] == n
    assert truth.time.values[0] == T0
    assert truth.time.values[-1] == T0 + np.timedelta64(int(ARC_S), "s")
    assert truth.sizes["stochastic_interval_start"] == 6
    assert truth.stochastic_interval_start.values[1] == T0 + np.timedelta64(600, "s")
    for name in ("pos_gcrf_m", "vel_gcrf_m_s", "pos_itrf_m", "vel_itrf_m_s"):
        assert truth[name].dims == ("time", "xyz")
        assert {"units", "long_name"} <= set(truth[name].attrs)
    assert truth.attrs["gravity_max_degree"] == 12
    # authority: the initial state of initial_state_sun_synchronous at t_start
    assert np.array_equal(truth.pos_gcrf_m.values[0],
                          initial_state_sun_synchronous(T0, HY2B_ALTITUDE_M, 18.0)[:3])


def test_truth_is_deterministic(truth):
    end = T0 + np.timedelta64(int(ARC_S), "s")
    again = simulate_truth_orbit(T0, end, seed=SEED, dynamics=LOW)
    # authority: same inputs, same seed -> bit-identical orbit
    assert np.array_equal(again.pos_gcrf_m.values, truth.pos_gcrf_m.values)
    assert np.array_equal(again.vel_itrf_m_s.values, truth.vel_itrf_m_s.values)
    other = simulate_truth_orbit(T0, end, seed=SEED + 1, dynamics=LOW)
    # another seed -> other stochastic accelerations; ½ a t² ≈ 0.1 m after an hour
    assert np.abs(other.pos_gcrf_m.values[-1] - truth.pos_gcrf_m.values[-1]).max() > 1e-3


def test_itrf_and_gcrf_are_consistent(truth):
    pos, vel = itrf_to_gcrf(truth.time.values, truth.pos_itrf_m.values,
                            truth.vel_itrf_m_s.values)
    # authority: the inverse transformation (IERS 2010 eq. 5.1 with its derivative)
    assert np.abs(pos - truth.pos_gcrf_m.values).max() < 1e-6
    assert np.abs(vel - truth.vel_gcrf_m_s.values).max() < 1e-9
    # Earth-fixed speed ≈ |v − ω × r| (rotation about the CIP ≈ GCRF z to 0.15°): ~1 m/s
    omega = np.array([0.0, 0.0, OMEGA_EARTH_RAD_S])
    v_rel = truth.vel_gcrf_m_s.values - np.cross(omega, truth.pos_gcrf_m.values)
    speed = np.linalg.norm(truth.vel_itrf_m_s.values, axis=1)
    assert np.abs(speed - np.linalg.norm(v_rel, axis=1)).max() < 2.0


def test_sp3_round_trip_matches_netcdf(truth, tmp_path):
    sp3_path, nc_path = tmp_path / "truth.sp3", tmp_path / "truth.nc"
    write_truth_files(truth, sp3_path, nc_path, "L01")
    sp3 = read_sp3(sp3_path)
    with xr.open_dataset(nc_path) as nc:
        nc = nc.load()
    # authority: netCDF is lossless
    assert np.array_equal(nc.pos_itrf_m.values, truth.pos_itrf_m.values)
    assert np.array_equal(nc.time.values, truth.time.values)
    assert np.array_equal(nc.stochastic_interval_start.values,
                          truth.stochastic_interval_start.values)
    assert nc.attrs["time_system"] == "GPS"
    assert np.array_equal(sp3.time.values, nc.time.values)
    assert sp3.attrs["coordinate_system"] == "ITRF"
    d_pos = sp3.pos_m.sel(sv="L01").values - nc.pos_itrf_m.values
    d_vel = sp3.vel_m_s.sel(sv="L01").values - nc.vel_itrf_m_s.values
    # authority: SP3-d resolution — km with 6 decimals (rounding ≤ 0.5 mm per coordinate,
    # < 1 mm in 3D) and dm/s with 6 decimals (≤ 5e-8 m/s)
    assert np.abs(d_pos).max() <= 0.5e-3 + 1e-9
    assert np.linalg.norm(d_pos, axis=1).max() < 1e-3
    assert np.abs(d_vel).max() <= 0.5e-7 + 1e-12


def test_rejects_an_empty_arc():
    with pytest.raises(ValueError, match="t_end > t_start"):
        simulate_truth_orbit(T0, T0, seed=1, dynamics=LOW)
