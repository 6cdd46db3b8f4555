"""Tests of leopod.dynamics.orbit_fit: batch least-squares dynamic orbit fit.

Authorities: simulated truth (orbits integrated with the same force model and known
parameters; the fit must recover them: exactly without noise, within 3 formal sigmas with
white noise of the stated sigma), the analytic circular two-body orbit (initial velocity),
numpy's SVD least squares (the QR solution), and, with ../shared, the ESA Swarm-A reduced-
dynamic orbit of 2023-01-01 (SP3, GPS time, IGS20 frame), which a good force model fits to a
few centimetres.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from test_force_model import POS, VEL, egm2008_degree4

from leopod.constants import GM_EARTH_M3_S2
from leopod.dynamics.force_config import ForceModelSettings, build_force_model
from leopod.dynamics.forces import apriori_parameters, estimated_parameters
from leopod.dynamics.integrator import DEFAULT_STEP_S, integrate
from leopod.dynamics.orbit_fit import (
    STATE_NAMES,
    _solve,
    fit_orbit,
    initial_state,
    starting_forces,
    starting_step_s,
)
from leopod.frames.earth_rotation import gcrf_to_itrf
from leopod.time.calendar import from_seconds

T_REF = np.datetime64("2023-01-01T00:00:00", "ns")
ARC_S = 3 * 3600.0
SAMPLING_S = 60.0
CONFIG = {"gravity": {"field": egm2008_degree4()}, "third_body": True, "relativity": True,
          "drag": {"area_m2": 1.0, "mass_kg": 470.0, "interval_s": 5400.0},
          "srp": {"area_m2": 1.0, "mass_kg": 470.0},
          "empirical": {"interval_s": 5400.0}}
SWARM_SP3 = "SW_OPER_SP3ACOM_2__20221231T235942_20230101T235942_0201.sp3"
FORCES = ForceModelSettings.from_config(CONFIG)


@pytest.fixture(scope="module")
def simulation():
    """Truth: parameters, initial state and ITRF positions every 60 s over 3 h."""
    t_s = np.arange(0.0, ARC_S + 1.0, SAMPLING_S)
    model = build_force_model(FORCES, T_REF, t_s[0], t_s[-1])
    rng = np.random.default_rng(7)
    params = apriori_parameters(model)
    names = model.parameters
    for i, name in enumerate(names):
        if name.startswith("drag_scale"):
            params[i] = rng.uniform(0.6, 1.6)
        elif name.startswith("emp_"):
            params[i] = rng.normal(0.0, 3e-8)
    state0 = np.concatenate([POS, VEL])
    traj = integrate(model, 0.0, state0, params, t_s, with_partials=False)
    times = from_seconds(t_s, T_REF)
    pos_itrf = gcrf_to_itrf(times, traj.states[:, :3])[0]
    return times, pos_itrf, state0, params, model


def _truth_vector(model, state0, params):
    est = estimated_parameters(model)
    return np.concatenate([state0, params[est]])


def test_initial_state_of_a_circular_orbit():
    # authority: circular two-body orbit r(t) = a (cos nt, sin nt, 0), v = a n (−sin, cos, 0)
    a = 6.8e6
    n = np.sqrt(GM_EARTH_M3_S2 / a**3)
    t = np.arange(0.0, 100.0, 10.0)
    pos = a * np.column_stack([np.cos(n * t), np.sin(n * t), 0 * t])
    state = initial_state(t, pos)
    np.testing.assert_allclose(state[:3], pos[0])
    np.testing.assert_allclose(state[3:], [0.0, a * n, 0.0], atol=1e-5)


def test_solve_matches_svd_least_squares():
    rng = np.random.default_rng(3)
    design = rng.normal(size=(50, 4)) * np.array([1e3, 1.0, 1e-4, 10.0])
    y = rng.normal(size=50)
    dx, cov = _solve(design, y)
    # authority: numpy.linalg.lstsq (SVD) and the normal-equation inverse
    np.testing.assert_allclose(dx, np.linalg.lstsq(design, y, rcond=None)[0], rtol=1e-10)
    np.testing.assert_allclose(cov, np.linalg.inv(design.T @ design), rtol=1e-8)


def test_fit_recovers_noise_free_truth(simulation):
    times, pos_itrf, state0, params, model = simulation
    start = state0 + np.array([30.0, -20.0, 10.0, 0.02, -0.01, 0.03])
    result = fit_orbit(times, pos_itrf, FORCES, state0_gcrf=start)
    assert result.converged and result.iterations <= 4
    assert result.parameter_names[:6] == list(STATE_NAMES)
    truth = _truth_vector(model, state0, params)
    # exact data: the error is the integration/round-off level, far below the formal sigmas
    assert np.max(np.abs(result.estimates - truth) / result.sigmas) < 1e-2
    assert result.rms_3d_m < 1e-4
    assert result.residuals_rtn_m.shape == (times.size, 3)


def test_state_refers_to_t_ref_when_the_first_epochs_are_missing(simulation):
    # authority: the simulated truth state at T_REF; positions of the first 5 min are missing
    # (as a code-only a-priori orbit often is), yet the returned state is the one at t_ref,
    # which is where the POD starts its arc
    times, pos_itrf, state0, _, _ = simulation
    pos = pos_itrf.copy()
    pos[:5] = np.nan
    result = fit_orbit(times, pos, FORCES, t_ref=times[0])
    assert result.converged
    assert np.max(np.abs(result.state0_gcrf[:3] - state0[:3])) < 1e-3      # m
    assert np.max(np.abs(result.state0_gcrf[3:] - state0[3:])) < 1e-6      # m/s


def test_fit_with_noise_within_three_sigma(simulation):
    times, pos_itrf, state0, params, model = simulation
    sigma_m = 0.02
    noisy = pos_itrf + np.random.default_rng(11).normal(0.0, sigma_m, pos_itrf.shape)
    result = fit_orbit(times, noisy, FORCES, sigma_obs_m=sigma_m)
    truth = _truth_vector(model, state0, params)
    normalised = (result.estimates - truth) / result.sigmas
    assert np.all(np.abs(normalised) < 3.0)
    # the formal sigmas are realistic: normalised errors of unit variance (k = 20 values)
    assert 0.4 < np.sqrt(np.mean(normalised**2)) < 1.6
    # post-fit residuals: white noise of sigma_m, minus the k fitted parameters
    assert result.sigma0 == pytest.approx(1.0, abs=0.15)
    assert result.rms_3d_m == pytest.approx(np.sqrt(3) * sigma_m, rel=0.15)
    value, sigma = result.estimate("drag_scale_0")
    assert abs(value - params[model.parameters.index("drag_scale_0")]) < 3 * sigma


def test_constrained_parameter_stays_near_apriori(simulation):
    times, pos_itrf, *_ = simulation
    config = {**CONFIG, "srp": {"area_m2": 1.0, "mass_kg": 470.0, "estimate": True,
                                "apriori": 1.5, "sigma": 1e-6}}
    result = fit_orbit(times, pos_itrf, ForceModelSettings.from_config(config))
    value, sigma = result.estimate("srp_scale_0")
    assert value == pytest.approx(1.5, abs=1e-5) and sigma <= 1e-6


def test_starting_forces_are_a_cheaper_model(simulation):
    # authority: the contract of starting_forces (its docstring): the field to the given
    # degree, one drag and one SRP scale factor (estimated as configured), no empirical
    # accelerations, the other forces unchanged
    start = starting_forces(FORCES, 3)
    assert start.gravity.max_degree == 3 and start.gravity.field is FORCES.gravity.field
    assert start.drag.interval_s is None and start.srp.interval_s is None
    assert start.drag.estimate == FORCES.drag.estimate and start.empirical is None
    assert (start.third_body, start.relativity, start.tides) == (
        FORCES.third_body, FORCES.relativity, FORCES.tides)
    lower = replace(FORCES, gravity=replace(FORCES.gravity, max_degree=2, gradient_degree=2))
    assert starting_forces(lower, 3).gravity.max_degree == 2        # never above the model's
    # its step: the integrator's 5 s at degree 120 (integrator docstring), inversely
    # proportional to the degree, at most 20 s
    assert [starting_step_s(n) for n in (120, 60, 30, 10)] == [DEFAULT_STEP_S, 10.0, 20.0, 20.0]
    # the fit with it counts its integrations; the simulated orbit (degree 4, drag scale per
    # 1.5 h, empirical accelerations) is fitted to the metre level only, enough to start a
    # POD (measured: RMS R/T/N 2.7/1.0/2.6 m, initial position 5.7 m off)
    times, pos_itrf, state0, _, _ = simulation
    result = fit_orbit(times, pos_itrf, start)
    assert result.parameter_names == [*STATE_NAMES, "drag_scale_0"]
    assert result.converged and result.integrations == result.iterations + 1
    assert result.force_evaluations > 1000 * result.integrations
    assert np.max(np.abs(result.state0_gcrf[:3] - state0[:3])) < 10.0


def test_fit_input_errors(simulation):
    times, pos_itrf, *_ = simulation
    with pytest.raises(ValueError, match="increasing"):
        fit_orbit(times[::-1], pos_itrf[::-1], FORCES)
    with pytest.raises(ValueError, match="frame"):
        fit_orbit(times, pos_itrf, FORCES, frame="ecef")
    with pytest.raises(ValueError, match="shape"):
        fit_orbit(times, pos_itrf[:, :2], FORCES)


@pytest.mark.shared
def test_swarm_a_dynamic_fit_few_centimetres(shared_data, shared):
    """Acceptance test: 6 h of the Swarm-A 2023-01-01 reference orbit (30-s sampling), full
    force model, drag scale and once-per-rev T/N terms per 3 h (benchmarks/swarm_fit.py has
    the 24-h fit and the table of forces)."""
    from leopod.io.sp3 import read_sp3

    ds = read_sp3(shared_data / "swarm-a_2023-001" / SWARM_SP3)
    assert ds.attrs["time_system"] == "GPS"
    models = shared / "models"
    config = {"gravity": {"field": models / "gravity" / "EGM2008_120.gfc", "max_degree": 120},
              "tides": {"ocean": models / "ocean_tides" / "fes2004_Cnm-Snm.dat"},
              "third_body": True, "relativity": True,
              "drag": {"area_m2": 1.0, "mass_kg": 470.0, "density": "msis",
                       "space_weather": models / "space_weather" / "SW-All.csv",
                       "interval_s": 10800.0},
              "srp": {"area_m2": 1.0, "mass_kg": 470.0},
              "empirical": {"interval_s": 10800.0}}
    sel = slice(0, 6 * 360 + 1, 3)
    result = fit_orbit(ds.time.values[sel], ds.pos_m.values[sel, 0], ForceModelSettings.from_config(config),
                       vel_m_s=ds.vel_m_s.values[sel, 0])
    assert result.converged
    # measured: R 1.8, T 2.0, N 0.9 cm, 3D 2.8 cm; a force-model error (e.g. no Sun and
    # Moon: 15 cm over 24 h) would not fit at this level
    assert np.all(result.rms_rtn_m < 0.03)
    assert result.rms_3d_m < 0.04
