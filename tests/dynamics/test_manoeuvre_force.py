"""Manoeuvre force (leopod.dynamics.manoeuvre): acceleration, partials, compiled form, and a
closed loop: a dynamic orbit fitted to positions of a simulated orbit with a burn.

Authorities:
- the RTN frame of the acceleration: analytic (e_R = r/|r|, e_N = r x v/|r x v|);
- ∂a/∂p: the acceleration is linear in the parameters, so finite differences are exact;
- the compiled right-hand side: the Python evaluation of the same force (same formulas);
- closed loop: the truth orbit of the simulator (leopod.simulate.truth_orbit), whose burns are
  an independent code path (interval-split stochastic accelerations,
  leopod.simulate.manoeuvres, checked against Clohessy-Wiltshire in
  tests/simulate/test_formation.py); the burn's acceleration is the simulator's value.
"""

from __future__ import annotations

import numpy as np
import pytest

from leopod.dynamics.compiled import CompiledForceModel
from leopod.dynamics.force_config import ForceModelSettings, build_force_model
from leopod.dynamics.forces import apriori_parameters
from leopod.dynamics.integrator import integrate
from leopod.dynamics.manoeuvre import Manoeuvres
from leopod.dynamics.model_files import resolve_model_paths
from leopod.dynamics.orbit_fit import fit_orbit
from leopod.frames.rtn import rtn_matrix
from leopod.io.manoeuvre import Manoeuvre
from leopod.simulate.truth_forces import TruthDynamics, truth_force_config
from leopod.simulate.truth_orbit import simulate_truth_orbit

T0 = np.datetime64("2022-07-14T00:00:00", "ns")
STATE = np.array([6.9e6, 1.0e5, -2.0e5, 100.0, 1.0e3, 7.5e3])


def _burns():
    return Manoeuvres([100.0, 500.0], [160.0, 620.0], [[1e-6, 5e-5, -2e-6], [0.0, -5e-5, 0.0]],
                      sigma=1e-5)


def test_acceleration_inside_and_outside_the_burns():
    force = _burns()
    params = force.apriori
    m = rtn_matrix(STATE[:3], STATE[3:])
    for t, k in ((99.9, -1), (100.0, 0), (159.9, 0), (160.0, -1), (400.0, -1), (619.0, 1)):
        acc, da_dr, da_dv, da_dp = force.evaluate(t, STATE[:3], STATE[3:], params)
        expected = np.zeros(3) if k < 0 else m.T @ params[3 * k:3 * k + 3]
        np.testing.assert_allclose(acc, expected, rtol=0, atol=1e-20)
        # linear in the parameters: finite differences are exact to round-off
        for j in range(6):
            step = np.zeros(6)
            step[j] = 1e-5
            fd = (force.evaluate(t, STATE[:3], STATE[3:], params + step)[0] - acc) / 1e-5
            np.testing.assert_allclose(da_dp[:, j], fd, atol=1e-9)
    assert list(force.breakpoints_s) == [100.0, 500.0, 160.0, 620.0]
    assert force.parameters[:3] == ["man_R_0", "man_T_0", "man_N_0"]
    with pytest.raises(ValueError, match="non-overlapping"):
        Manoeuvres([0.0, 50.0], [60.0, 100.0], np.zeros((2, 3)))


def test_compiled_force_sum_equals_the_python_model():
    settings = ForceModelSettings.from_config({
        "gravity": False, "manoeuvre": {"sigma": 1e-5}})
    burns = [Manoeuvre(T0 + np.timedelta64(100, "s"), T0 + np.timedelta64(160, "s"),
                       (1e-6, 5e-5, -2e-6))]
    # a model the compiled form accepts needs EarthGravity: compare the force alone
    model = build_force_model(settings, T0, 0.0, 600.0, manoeuvres=burns)
    force = model.forces[-1]
    assert isinstance(force, Manoeuvres) and model.parameters[-3:] == force.parameters
    np.testing.assert_array_equal(apriori_parameters(model)[-3:], [1e-6, 5e-5, -2e-6])
    gravity = ForceModelSettings.from_config(resolve_model_paths({
        "gravity": {"field": "satkit:ITU_GRACE16.gfc", "max_degree": 4}, "manoeuvre": {}}))
    full = build_force_model(gravity, T0, 0.0, 600.0, manoeuvres=burns)
    compiled = CompiledForceModel.of(full)
    assert compiled is not None
    params = apriori_parameters(full)
    for t in (50.0, 130.0):
        py = full.evaluate(t, STATE[:3], STATE[3:], params)
        nb = compiled.evaluate(t, STATE[:3], STATE[3:], params)
        for a, b in zip(py, nb):
            np.testing.assert_allclose(b, a, rtol=1e-13, atol=1e-22)


def test_fit_of_a_manoeuvring_orbit():
    """Closed loop: 3 h of a simulated 607-km orbit with a 60-s burn of 3 mm/s along-track
    (the lt1-sim station-keeping burn) fitted from 1-cm positions every 30 s with the truth's
    force model, drag scales estimated; the manoeuvre file's a-priori acceleration is 20 % off
    the flown one (thrust uncertainty).

    * the POD's empirical accelerations of config/lt1-sim.yaml (T, N constant and
      once-per-revolution per 90 min, 1e-7 m/s² constraint) instead of the truth's stochastic
      accelerations: the orbit without the burn model is off by a dm, with it by mm;
    * the truth's stochastic accelerations estimated with their a-priori sigma (the largest of
      R, T, N), so that the formal sigmas are realistic: the estimated burn acceleration is the
      flown one within 3 sigma.
    """
    span_s, seed = 10_800.0, 7
    dyn = TruthDynamics.from_config({"gravity_degree": 12})
    acc_true = np.array([2e-6, 5e-5, -4e-6])
    start = T0 + np.timedelta64(5_400, "s")
    flown = Manoeuvre(start, start + np.timedelta64(60, "s"), tuple(acc_true))
    listed = Manoeuvre(flown.start, flown.end, tuple(0.8 * acc_true))
    truth = simulate_truth_orbit(T0, T0 + np.timedelta64(int(span_s), "s"), seed=seed,
                                 step_s=30.0, altitude_m=607e3, ltan_h=6.0, dynamics=dyn,
                                 manoeuvres=[flown])
    config = truth_force_config(span_s, seed=seed, dynamics=dyn).config
    config["drag"] = {**config["drag"], "estimate": True}
    pod_empirical = {"interval_s": 5400.0, "directions": ["T", "N"],
                     "terms": ["const", "cos", "sin"], "sigma": 1e-7}
    stochastic = {**config["empirical"], "estimate": True,
                  "sigma": max(dyn.stochastic_sigma_rtn_m_s2)}
    pos = truth.pos_gcrf_m.values
    noisy = pos + np.random.default_rng(1).normal(0.0, 0.01, pos.shape)
    state0 = np.concatenate([pos[0], truth.vel_gcrf_m_s.values[0]])

    def fit(empirical: dict, manoeuvre: dict | None):
        cfg = {**config, "empirical": empirical, "manoeuvre": manoeuvre}
        res = fit_orbit(truth.time.values, noisy, ForceModelSettings.from_config(cfg),
                        frame="gcrf", state0_gcrf=state0, manoeuvres=[listed])
        err = res.trajectory.states[:, :3] - pos
        return res, np.sqrt(np.mean(np.sum(err**2, axis=1)))

    _, rms_without = fit(pod_empirical, None)
    _, rms_with = fit(pod_empirical, {"sigma": 1e-5})
    res, rms_stochastic = fit(stochastic, {"sigma": 1e-5})
    idx = [res.parameter_names.index(n) for n in ("man_R_0", "man_T_0", "man_N_0")]
    est, sig = res.estimates[idx], res.sigmas[idx]
    print(f"orbit 3D RMS without the burn model {rms_without:.4f} m, with {rms_with:.4f} m, "
          f"stochastic model {rms_stochastic:.4f} m; burn {est} +- {sig}, truth {acc_true}")
    assert rms_without > 0.1          # unmodelled burn: dm
    assert rms_with < 0.01            # modelled: mm
    assert rms_stochastic < 0.01
    assert np.all(np.abs(est - acc_true) < 3.0 * sig)
    assert np.all(sig < 0.02 * np.abs(acc_true[1]))   # determined by the data, not the a priori


def test_integrated_sensitivities_equal_finite_differences():
    """The burn sensitivities integrated with the variational equations (compiled path, the
    integrator restarting at the burn start and end) equal the difference of two orbits
    integrated with the accelerations changed by 1e-4 m/s² (a step large enough for the
    difference to stand above the 1e-9 m round-off of the positions; the orbit is linear in
    the accelerations up to the neglected frame partials, |a|/|r| ~ 1e-11 s⁻²)."""
    settings = ForceModelSettings.from_config(resolve_model_paths({
        "gravity": {"field": "satkit:ITU_GRACE16.gfc", "max_degree": 4}, "manoeuvre": {}}))
    burns = [Manoeuvre(T0 + np.timedelta64(100, "s"), T0 + np.timedelta64(163, "s"),
                       (1e-6, 5e-5, -2e-6))]
    model = build_force_model(settings, T0, 0.0, 900.0, manoeuvres=burns)
    assert CompiledForceModel.of(model) is not None
    params = apriori_parameters(model)
    t_out = np.array([0.0, 90.0, 130.0, 600.0, 900.0])
    base = integrate(model, 0.0, STATE, params, t_out, step_s=10.0)
    for j in range(3):
        step = np.zeros_like(params)
        step[-3 + j] = 1e-4
        moved = integrate(model, 0.0, STATE, params + step, t_out, step_s=10.0)
        fd = (moved.states - base.states) / 1e-4
        np.testing.assert_allclose(base.sensitivity[:, :, -3 + j], fd, rtol=1e-5, atol=1e-6)
    # nothing before the burn, a position change of a t²/2 order within it
    assert np.all(base.sensitivity[:2, :, -3:] == 0.0)
    assert 100.0 < np.linalg.norm(base.sensitivity[2, :3, -2]) < 30.0**2
