"""Orbit integrator with variational equations, force-model interface, pseudo-stochastic pulses.

Authorities: the analytic two-body solution (Kepler's equation solved here by Newton's method,
Montenbruck & Gill 2000 sec. 2.2), exact polynomial solutions, finite differences of
independent integrations (STM, sensitivities, pulse partials, RTN partials; the J2 test force
differentiates itself by complex steps: a noisy finite-difference gradient of ~1e-9 relative
spoils Φ at the 1e-7..1e-6 level, so force models need analytic partials), the energy
integral of time-independent potentials (two-body, axisymmetric J2), a run with a 2× smaller
step, and scipy's DOP853 (an independent integrator).
"""

import numpy as np
import pytest

from leopod.constants import GM_EARTH_M3_S2, OMEGA_EARTH_RAD_S, R_EARTH_EQUATOR_M
from leopod.dynamics.forces import (
    ConstantAcceleration,
    Force,
    ForceModel,
    PointMassGravity,
    PseudoStochasticPulses,
)
from leopod.dynamics.integrator import (
    DEFAULT_STEP_S,
    apply_pulses,
    integrate,
    pulse_partials,
)
from leopod.frames.rtn import rtn_basis, rtn_vector_partials

HOUR_S = 3600.0
#: J2 of the test force (≈ Earth's, EGM2008 −√5 C̄20); any value serves an integrator test.
J2_TEST = 1.0826e-3
#: Test orbit (brief: LEO a = 6878 km, e = 0.001): a [m], e, i, Ω, ω, M0 [rad].
ELEMENTS = (6_878_000.0, 0.001, np.radians(97.4), np.radians(30.0), np.radians(60.0), 0.3)


def kepler_state(elements, t_s, gm=GM_EARTH_M3_S2):
    """Two-body state (m, 6) at times t_s from Keplerian elements (M&G 2000, sec. 2.2)."""
    a, e, inc, raan, argp, m0 = elements
    t = np.atleast_1d(np.asarray(t_s, dtype=float))
    mean = m0 + np.sqrt(gm / a**3) * t
    ecc = mean.copy()
    for _ in range(30):                                     # Newton on E − e sin E = M
        ecc -= (ecc - e * np.sin(ecc) - mean) / (1.0 - e * np.cos(ecc))
    r = a * (1.0 - e * np.cos(ecc))
    b = np.sqrt(1.0 - e * e)
    pos_pf = np.stack([a * (np.cos(ecc) - e), a * b * np.sin(ecc), 0 * t], axis=1)
    vel_pf = np.sqrt(gm * a) / r[:, None] * np.stack([-np.sin(ecc), b * np.cos(ecc), 0 * t], 1)

    def rot_z(x):
        return np.array([[np.cos(x), -np.sin(x), 0], [np.sin(x), np.cos(x), 0], [0, 0, 1]])

    rot_x = np.array([[1, 0, 0], [0, np.cos(inc), -np.sin(inc)], [0, np.sin(inc), np.cos(inc)]])
    m = rot_z(raan) @ rot_x @ rot_z(argp)
    return np.hstack([pos_pf @ m.T, vel_pf @ m.T])


STATE0 = kepler_state(ELEMENTS, 0.0)[0]


def j2_acceleration(pos_m):
    """Point mass + J2 (zonal, axisymmetric) acceleration [m/s²] (M&G 2000, sec. 3.2)."""
    x, y, z = pos_m
    r2 = pos_m @ pos_m
    k = 1.5 * J2_TEST * (R_EARTH_EQUATOR_M**2 / r2)
    zz = 5.0 * z * z / r2
    f = -GM_EARTH_M3_S2 / (r2 * np.sqrt(r2))
    return f * np.array([x * (1 + k * (1 - zz)), y * (1 + k * (1 - zz)), z * (1 + k * (3 - zz))])


def j2_potential(pos_m):
    """Potential U (a = ∇U) of :func:`j2_acceleration` [m²/s²]."""
    r = np.linalg.norm(pos_m, axis=-1)
    sin2 = (pos_m[..., 2] / r) ** 2
    return GM_EARTH_M3_S2 / r * (1 - 0.5 * J2_TEST * (R_EARTH_EQUATOR_M / r) ** 2
                                 * (3 * sin2 - 1))


class J2Gravity(Force):
    """Test force: point mass + J2, gradient by complex-step differentiation (exact to round-off
    for an analytic function; Squire & Trapp 1998, SIAM Rev. 40:110)."""

    def __init__(self):
        self.parameters = []

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        step = 1e-3 * np.eye(3)
        grad = np.column_stack([j2_acceleration(pos_m + 1j * step[j]).imag / 1e-3
                                for j in range(3)])
        return j2_acceleration(pos_m), grad, np.zeros((3, 3)), np.zeros((3, 0))


class PolynomialInTime(Force):
    """Test force ``a = c (t/τ)^k`` (independent of the state): exact solution by quadrature."""

    def __init__(self, k, tau_s=1000.0, c=(1e-3, -2e-3, 3e-3)):
        self.k, self.tau_s, self.c = k, tau_s, np.array(c)
        self.parameters = []

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        zero = np.zeros((3, 3))
        return self.c * (t_s / self.tau_s) ** self.k, zero, zero.copy(), np.zeros((3, 0))

    def exact(self, state0, t_s):
        t = np.asarray(t_s)[:, None]
        k, tau = self.k, self.tau_s
        pos = state0[:3] + state0[3:] * t + self.c * tau**2 * (t / tau) ** (k + 2) / ((k + 1)
                                                                                  * (k + 2))
        vel = state0[3:] + self.c * tau * (t / tau) ** (k + 1) / (k + 1)
        return np.hstack([pos, vel])


def _fd_columns(force_model, t_out, perturb, deltas, **kw):
    """Central-difference columns (m, 6, n) of the state w.r.t. the perturbations."""
    cols = []
    for j, d in enumerate(deltas):
        plus = integrate(force_model, *perturb(j, d), t_out, with_partials=False, **kw).states
        minus = integrate(force_model, *perturb(j, -d), t_out, with_partials=False, **kw).states
        cols.append((plus - minus) / (2 * d))
    return np.stack(cols, axis=2)


def _relative_error(test, truth):
    """Max over columns of |test − truth| / |truth| (column norms), positions and velocities
    separately."""
    out = 0.0
    for rows in (slice(0, 3), slice(3, 6)):
        err = np.linalg.norm(test[:, rows] - truth[:, rows], axis=1)
        ref = np.linalg.norm(truth[:, rows], axis=1)
        mask = ref > 0
        out = max(out, float(np.max(err[mask] / ref[mask])))
    return out


# ---------------------------------------------------------------------------------------------
# Force-model interface


def test_force_model_concatenates_parameters_and_partials():
    emp_a = ConstantAcceleration([0.0, 100.0], prefix="a")
    emp_b = ConstantAcceleration([50.0, 200.0, 300.0], prefix="b")
    model = ForceModel([PointMassGravity(), emp_a, emp_b])
    assert model.parameters == ["a_R_0", "a_T_0", "a_N_0", "b_R_0", "b_T_0", "b_N_0",
                                "b_R_1", "b_T_1", "b_N_1"]
    np.testing.assert_array_equal(model.breakpoints_s, [0.0, 50.0, 100.0, 200.0, 300.0])
    params = np.arange(1.0, 10.0) * 1e-8
    acc, _, _, da_dp = model.evaluate(60.0, STATE0[:3], STATE0[3:], params)
    basis = rtn_basis(STATE0[:3], STATE0[3:])
    # authority: sum of the individual forces (point mass + both interval-0 accelerations)
    expected = -GM_EARTH_M3_S2 * STATE0[:3] / np.linalg.norm(STATE0[:3]) ** 3
    expected = expected + basis @ params[0:3] + basis @ params[3:6]
    np.testing.assert_allclose(acc, expected, rtol=0, atol=1e-14)
    np.testing.assert_allclose(da_dp[:, 0:3], basis, atol=1e-15)
    np.testing.assert_allclose(da_dp[:, 3:6], basis, atol=1e-15)
    assert np.all(da_dp[:, 6:] == 0.0)                  # b interval 1 inactive at t = 60 s
    with pytest.raises(ValueError, match="unique"):
        ForceModel([emp_a, ConstantAcceleration([0.0, 1.0], prefix="a")])


def test_constant_acceleration_is_zero_outside_its_intervals():
    emp = ConstantAcceleration([0.0, 10.0, 20.0])
    params = np.full(6, 1e-7)
    for t in (-1.0, 20.0, 25.0):
        acc, da_dr, da_dv, da_dp = emp.evaluate(t, STATE0[:3], STATE0[3:], params)
        assert not acc.any() and not da_dr.any() and not da_dv.any() and not da_dp.any()
    assert emp.interval(10.0) == 1 and emp.interval(0.0) == 0
    with pytest.raises(ValueError):
        ConstantAcceleration([0.0, 0.0])


def test_rtn_basis_is_orthonormal_with_t_along_velocity():
    m = rtn_basis(STATE0[:3], STATE0[3:])
    np.testing.assert_allclose(m.T @ m, np.eye(3), atol=1e-15)
    assert np.linalg.det(m) == pytest.approx(1.0)
    assert m[:, 1] @ STATE0[3:] / np.linalg.norm(STATE0[3:]) > 0.999    # e ≈ 0: T ≈ v/|v|


def test_rtn_vector_partials_against_finite_differences():
    vec = np.array([3e-8, -5e-8, 7e-8])
    d_dr, d_dv = rtn_vector_partials(STATE0[:3], STATE0[3:], vec)
    for j in range(3):                                  # authority: central differences
        for delta, analytic, slot in ((10.0, d_dr, 0), (0.01, d_dv, 3)):
            plus, minus = STATE0.copy(), STATE0.copy()
            plus[slot + j] += delta
            minus[slot + j] -= delta
            fd = (rtn_basis(plus[:3], plus[3:]) @ vec - rtn_basis(minus[:3], minus[3:]) @ vec)
            np.testing.assert_allclose(analytic[:, j], fd / (2 * delta), rtol=1e-6,
                                       atol=1e-9 * np.abs(analytic).max())


def test_point_mass_gradient_against_finite_differences():
    grav = PointMassGravity()
    _, grad, _, _ = grav.evaluate(0.0, STATE0[:3], STATE0[3:], np.empty(0))
    for j in range(3):                                  # authority: central differences (1 m)
        d = np.zeros(3)
        d[j] = 1.0
        fd = (grav.evaluate(0, STATE0[:3] + d, STATE0[3:], [])[0]
              - grav.evaluate(0, STATE0[:3] - d, STATE0[3:], [])[0]) / 2.0
        np.testing.assert_allclose(grad[:, j], fd, rtol=1e-7, atol=1e-15)


# ---------------------------------------------------------------------------------------------
# Integration accuracy


def test_two_body_30h_both_directions_against_kepler():
    """Brief (a): 30 h forward and 30 h backward from t0, < 0.1 mm, default settings."""
    t_out = np.linspace(-30 * HOUR_S, 30 * HOUR_S, 1441) + 7.3       # off the step grid too
    traj = integrate(ForceModel([PointMassGravity()]), 0.0, STATE0, [], t_out,
                     with_partials=False)
    truth = kepler_state(ELEMENTS, t_out)                # authority: analytic two-body
    # requirement 0.1 mm; measured 0.0002 mm, so guard at 0.002 mm (plain instead of
    # compensated summation of the Gauss–Jackson sums gives 0.007 mm here)
    assert np.linalg.norm(traj.states[:, :3] - truth[:, :3], axis=1).max() < 2e-6    # m
    assert np.linalg.norm(traj.states[:, 3:] - truth[:, 3:], axis=1).max() < 1e-8    # m/s


@pytest.mark.parametrize(("order", "pece"), [(8, False), (12, False), (10, True)])
def test_other_orders_and_pece_against_kepler(order, pece):
    t_out = np.arange(0.0, 30 * HOUR_S + 1, 600.0)
    traj = integrate(ForceModel([PointMassGravity()]), 0.0, STATE0, [], t_out, step_s=30.0,
                     order=order, pece=pece, with_partials=False)
    truth = kepler_state(ELEMENTS, t_out)                # authority: analytic two-body
    assert np.linalg.norm(traj.states[:, :3] - truth[:, :3], axis=1).max() < 1e-5    # m
    assert traj.n_evaluations < (2 if pece else 1) * 3600 + 200


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_polynomial_acceleration_of_the_method_order_is_integrated_exactly(sign):
    force = PolynomialInTime(k=10)
    t_out = sign * np.array([0.0, 3.0, 17.5, 50.0, 333.3, 1000.0, 1999.0, 2000.0])
    traj = integrate(ForceModel([force]), 0.0, STATE0, [], t_out, with_partials=False)
    # authority: exact double quadrature of a degree-10 polynomial (Gauss–Jackson q = 10)
    truth = force.exact(STATE0, t_out)
    np.testing.assert_allclose(traj.states[:, :3], truth[:, :3], rtol=0, atol=1e-7)
    np.testing.assert_allclose(traj.states[:, 3:], truth[:, 3:], rtol=0, atol=1e-10)


@pytest.mark.parametrize("gravity", [PointMassGravity(), J2Gravity()],
                         ids=["two-body", "j2"])
def test_energy_integral_conserved_over_30h(gravity):
    """Brief (e): v²/2 − U(r) of a time-independent potential, relative drift < 1e-12."""
    t_out = np.arange(0.0, 30 * HOUR_S + 1, 300.0)
    traj = integrate(ForceModel([gravity]), 0.0, STATE0, [], t_out, with_partials=False)
    pos, vel = traj.states[:, :3], traj.states[:, 3:]
    potential = (GM_EARTH_M3_S2 / np.linalg.norm(pos, axis=1)
                 if isinstance(gravity, PointMassGravity) else j2_potential(pos))
    energy = 0.5 * np.sum(vel**2, axis=1) - potential
    assert np.max(np.abs(energy / energy[0] - 1.0)) < 1e-12


def test_default_step_against_halved_step_and_dop853_j2_30h():
    """Brief (f): 30-h error of the default settings against a tighter run < 0.1 mm."""
    model = ForceModel([J2Gravity()])
    t_out = np.arange(0.0, 30 * HOUR_S + 1, 60.0)
    default = integrate(model, 0.0, STATE0, [], t_out, with_partials=False)
    tight = integrate(model, 0.0, STATE0, [], t_out, step_s=DEFAULT_STEP_S / 2,
                      with_partials=False)
    assert np.linalg.norm(default.states[:, :3] - tight.states[:, :3], axis=1).max() < 1e-4
    # authority: an independent integrator (scipy DOP853, adaptive, rtol 1e-13)
    rk = integrate(model, 0.0, STATE0, [], t_out, method="dop853", with_partials=False)
    assert np.linalg.norm(default.states[:, :3] - rk.states[:, :3], axis=1).max() < 1e-4


class RotatingField(Force):
    """Test force: an Earth-fixed field rotating at the nominal Earth rate (no EOP)."""

    def __init__(self, field):
        self.field = field
        self.parameters = []

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        c, s = np.cos(OMEGA_EARTH_RAD_S * t_s), np.sin(OMEGA_EARTH_RAD_S * t_s)
        to_ef = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
        acc = to_ef.T @ self.field.acceleration(to_ef @ pos_m)
        zero = np.zeros((3, 3))
        return acc, zero, zero.copy(), np.zeros((3, 0))


@pytest.mark.shared
def test_default_step_resolves_a_degree_120_field_over_30h(shared):
    """Brief (f) with the field that sets the step: EGM2008 to degree 120, 30 h."""
    from leopod.dynamics.gravity_field import GravityField
    from leopod.io.icgem import read_icgem

    field = GravityField(read_icgem(shared / "models/gravity/EGM2008_120.gfc"), 120)
    model = ForceModel([RotatingField(field)])
    t_out = np.arange(0.0, 30 * HOUR_S + 1, 30.0)
    default = integrate(model, 0.0, STATE0, [], t_out, with_partials=False)
    tight = integrate(model, 0.0, STATE0, [], t_out, step_s=DEFAULT_STEP_S / 2,
                      with_partials=False)
    assert np.linalg.norm(default.states[:, :3] - tight.states[:, :3], axis=1).max() < 1e-4


# ---------------------------------------------------------------------------------------------
# Variational equations


@pytest.mark.parametrize("gravity", [PointMassGravity(), J2Gravity()],
                         ids=["two-body", "j2"])
def test_stm_against_finite_differences_30h_both_directions(gravity):
    """Brief (b): Φ(t, t0) vs central differences of perturbed initial states, < 1e-6."""
    model = ForceModel([gravity])
    t_out = np.array([-30, -11.3, -1, 0.5, 7, 19.9, 30]) * HOUR_S
    kw = {"step_s": 30.0}
    traj = integrate(model, 0.0, STATE0, [], t_out, **kw)

    def perturb(j, d):
        y = STATE0.copy()
        y[j] += d
        return 0.0, y, []

    fd = _fd_columns(model, t_out, perturb, [1.0] * 3 + [1e-3] * 3, **kw)
    assert _relative_error(traj.stm, fd) < 1e-6
    np.testing.assert_array_equal(integrate(model, 0.0, STATE0, [], [0.0]).stm[0], np.eye(6))


def test_empirical_sensitivity_against_finite_differences():
    """Brief (c): S = ∂y/∂p of piecewise-constant RTN accelerations vs central differences;
    zero before the interval (forward) or after it (backward); restarts at the edges."""
    edges = np.array([-3.0, 0.0, 2.0, 7.0]) * HOUR_S
    model = ForceModel([J2Gravity(), ConstantAcceleration(edges)])
    params = np.tile([2e-8, -5e-8, 3e-8], 3)
    t_out = np.array([-5, -3, -1, 1, 2, 4, 7, 12]) * HOUR_S
    kw = {"step_s": 30.0}
    traj = integrate(model, 0.0, STATE0, params, t_out, **kw)

    def perturb(j, d):
        p = params.copy()
        p[j] += d
        return 0.0, STATE0, p

    # steps per axis R, T, N [m/s²]: responses of >= 100 m, far above the integration noise
    # (~1e-7 m) and still linear (central differences cancel the second order)
    fd = _fd_columns(model, t_out, perturb, np.tile([1e-5, 1e-7, 1e-4], 3), **kw)
    assert _relative_error(traj.sensitivity, fd) < 1e-6
    # interval 2 = [2 h, 7 h): no effect up to 2 h; interval 0 = [−3 h, 0): none after t0
    assert not traj.sensitivity[t_out <= 2 * HOUR_S][:, :, 6:9].any()
    assert not traj.sensitivity[t_out >= 0][:, :, 0:3].any()
    assert traj.sensitivity[t_out > 2 * HOUR_S][:, :, 6:9].all()


def test_dop853_partials_agree_with_gauss_jackson():
    """Independent integrator (scipy DOP853) for the state, Φ and S over 6 h."""
    model = ForceModel([J2Gravity(), ConstantAcceleration([0.0, 2 * HOUR_S, 6 * HOUR_S])])
    params = np.tile([2e-8, -5e-8, 3e-8], 2)
    t_out = np.linspace(0.0, 6 * HOUR_S, 25)
    gj = integrate(model, 0.0, STATE0, params, t_out)
    rk = integrate(model, 0.0, STATE0, params, t_out, method="dop853")
    assert np.linalg.norm(gj.states[:, :3] - rk.states[:, :3], axis=1).max() < 5e-5
    assert _relative_error(gj.stm[1:], rk.stm[1:]) < 1e-9
    assert _relative_error(gj.sensitivity[1:], rk.sensitivity[1:]) < 1e-9


# ---------------------------------------------------------------------------------------------
# Pulses


def test_pulse_partials_against_integration_with_pulses():
    """Brief (d): partials from the STM vs central differences of integrations with pulses
    (one pulse before t0, two after)."""
    model = ForceModel([J2Gravity()])
    pulses = PseudoStochasticPulses(np.array([-5.0, 2.0, 10.0]) * HOUR_S)
    assert pulses.parameters[:4] == ["pulse_R_0", "pulse_T_0", "pulse_N_0", "pulse_R_1"]
    t_out = np.array([-9, -5, -4, 1, 2, 3, 9.9, 10, 15, 30]) * HOUR_S
    kw = {"step_s": 30.0}
    traj = integrate(model, 0.0, STATE0, [], t_out, **kw)
    partials = pulse_partials(traj, pulses)
    # steps per axis R, T, N [m/s]: responses well above the integration noise, still linear
    steps = [1e-2, 1e-3, 1e-2]
    fd = []
    for j in range(9):
        runs = []
        for sign in (1.0, -1.0):
            dv = np.zeros((3, 3))
            dv.flat[j] = sign * steps[j % 3]
            runs.append(apply_pulses(model, 0.0, STATE0, [], t_out, pulses, dv,
                                     with_partials=False, **kw).states)
        fd.append((runs[0] - runs[1]) / (2 * steps[j % 3]))
    fd = np.stack(fd, axis=2)
    assert _relative_error(partials, fd) < 1e-6
    # zero where the pulse has no effect: forward pulses before their epoch, backward after
    assert not partials[t_out < 2 * HOUR_S][:, :, 3:6].any()
    assert not partials[t_out >= -5 * HOUR_S][:, :, 0:3].any()


def test_apply_pulses_jumps_the_velocity_by_the_rtn_vector():
    model = ForceModel([PointMassGravity()])
    t_i = 1234.0
    dv_rtn = np.array([[0.01, -0.02, 0.03]])
    t_out = [t_i - 1e-6, t_i]
    pulsed = apply_pulses(model, 0.0, STATE0, [], t_out, [t_i], dv_rtn, with_partials=False)
    plain = integrate(model, 0.0, STATE0, [], [t_i], with_partials=False)
    basis = rtn_basis(plain.states[0, :3], plain.states[0, 3:])
    # right-continuous: the state at t_i is after the pulse (authority: definition, eq. 1 of
    # Wang et al. 2024); before it the orbit is the unpulsed one
    np.testing.assert_allclose(pulsed.states[1, 3:] - plain.states[0, 3:], basis @ dv_rtn[0],
                               rtol=0, atol=1e-11)
    np.testing.assert_allclose(pulsed.states[1, :3], plain.states[0, :3], rtol=0, atol=1e-6)
    with pytest.raises(ValueError, match="t0"):
        apply_pulses(model, 0.0, STATE0, [], t_out, [0.0], dv_rtn)


# ---------------------------------------------------------------------------------------------
# Trajectory


def test_trajectory_interpolant_matches_direct_output_and_checks_span():
    model = ForceModel([J2Gravity(), ConstantAcceleration([-HOUR_S, 0.0, HOUR_S])])
    params = np.full(6, 1e-8)
    t_out = np.array([-2 * HOUR_S, -1234.567, 0.0, 2222.2, 2 * HOUR_S])
    traj = integrate(model, 0.0, STATE0, params, t_out[[0, -1]])
    direct = integrate(model, 0.0, STATE0, params, t_out)
    later = traj.at(t_out)
    # same arcs: the interpolant reproduces the direct outputs (nodes there) to < 1 µm
    np.testing.assert_allclose(later.states[:, :3], direct.states[:, :3], rtol=0, atol=1e-6)
    np.testing.assert_allclose(later.stm, direct.stm, rtol=1e-9, atol=1e-12)
    np.testing.assert_array_equal(later.stm[2], np.eye(6))
    assert not later.sensitivity[2].any()
    assert traj.span_s == (-2 * HOUR_S, 2 * HOUR_S)
    with pytest.raises(ValueError, match="span"):
        traj.at([3 * HOUR_S])
    with pytest.raises(ValueError, match="params"):
        integrate(model, 0.0, STATE0, [], t_out)
