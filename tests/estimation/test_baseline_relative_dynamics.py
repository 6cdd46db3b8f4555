"""Relative dynamics and the reference-fixed mode of a formation pair's baseline
(leopod.estimation.baseline: relative_rows, constraint_residuals, reference_fixed_solve,
fixed_correction).

Authorities: analytic least squares (Koch 1999, Parameter Estimation, sec. 3.2: constraint
rows are further weighted observations; adding observations never increases a variance);
the pairing rules of the module docstring (pulses by epoch, force-model parameters by name on
the same arc; initial states and burn accelerations free).
"""

import numpy as np

from leopod.estimation.baseline import (
    BaselineSettings,
    constraint_residuals,
    fixed_correction,
    joint_solve,
    reference_fixed_solve,
    relative_rows,
)
from leopod.estimation.float_pod import ArcNormals
from leopod.estimation.normals import NormalEquations

T_REF = np.datetime64("2022-07-13T21:00:00", "ns")
SETTINGS = BaselineSettings.from_config({"dynamics": "relative",
                                         "relative_pulse_sigma_m_s": [1e-6, 2e-6, 3e-6],
                                         "relative_empirical_sigma_m_s2": 1e-9,
                                         "relative_drag_scale_sigma": 0.002,
                                         "relative_srp_scale_sigma": 0.01})


def _arc(names, values, matrix, rhs, pulse_epochs_s, t_ref=T_REF, n_amb=0):
    n = len(names) + n_amb
    ne = NormalEquations(matrix=np.asarray(matrix, float).reshape(n, n),
                         rhs=np.asarray(rhs, float), ltpl=0.0, n_rows=n)
    return ArcNormals(normals=ne, k=len(names), active=np.arange(n_amb),
                      ambiguity_m=np.zeros(n_amb), _solution=None, _state=None,
                      names=tuple(names), values=np.asarray(values, float), t_ref=t_ref,
                      pulse_epochs_s=np.asarray(pulse_epochs_s, float))


def _pulse_names(n):
    return [f"pulse_{x}_{i}" for i in range(n) for x in "RTN"]


def test_pairs_pulses_by_epoch_and_force_parameters_by_name():
    names_a = ["x0_m", "drag_scale_0", "srp_scale_0", "emp_const_T_0", *_pulse_names(2)]
    names_b = ["x0_m", "drag_scale_0", "srp_scale_0", "emp_const_T_0", "man_T_0",
               *_pulse_names(3)]
    va = np.arange(len(names_a), dtype=float)
    vb = 10.0 + np.arange(len(names_b), dtype=float)
    # B's pulses at 900, 1800, 2700 s; A's at 1800, 2700 s: two epochs in common
    a = _arc(names_a, va, np.eye(len(names_a)), np.zeros(len(names_a)), [1800.0, 2700.0])
    b = _arc(names_b, vb, np.eye(len(names_b)), np.zeros(len(names_b)),
             [900.0, 1800.0, 2700.0])
    design, misclosure, weight, counts = relative_rows(a, b, SETTINGS)
    assert counts == {"pulse": 6, "empirical": 1, "drag_scale": 1, "srp_scale": 1}
    n_a = len(names_a)
    for row, mis, w in zip(design, misclosure, weight):
        (ia,), (ib,) = np.flatnonzero(row[:n_a]), np.flatnonzero(row[n_a:])
        assert row[ia] == -1.0 and row[n_a + ib] == 1.0
        na, nb = names_a[ia], names_b[ib]
        if na.startswith("pulse"):
            axis, ka = na.split("_")[1], int(na.split("_")[2])
            assert nb == f"pulse_{axis}_{ka + 1}"      # the same epoch, the same axis
            assert w == 1.0 / SETTINGS.relative_pulse_sigma_m_s["RTN".index(axis)] ** 2
        else:
            assert na == nb
        assert mis == -(vb[ib] - va[ia])
    # the initial state and the burn stay free
    assert not design[:, [0, n_a]].any() and not design[:, n_a + names_b.index("man_T_0")].any()


def test_other_reference_epoch_ties_only_pulses():
    names = ["x0_m", "drag_scale_0", *_pulse_names(1)]
    a = _arc(names, np.zeros(5), np.eye(5), np.zeros(5), [1800.0])
    # B's reference 900 s later: its pulse at 900 s is A's at 1800 s
    b = _arc(names, np.zeros(5), np.eye(5), np.zeros(5), [900.0],
             t_ref=T_REF + np.timedelta64(900, "s"))
    _, _, _, counts = relative_rows(a, b, SETTINGS)
    assert counts == {"pulse": 3, "empirical": 0, "drag_scale": 0, "srp_scale": 0}


def test_common_dynamics_recovers_the_baseline_more_precisely():
    """Two 'satellites' r(t) = x0 + t v: the same velocity parameter (the common force)
    with different offsets. Noise-free data give the true offsets with or without relative
    dynamics; the tied velocities make the baseline's formal variance smaller."""
    t = np.linspace(0.0, 1.0, 11)
    h = np.column_stack([np.ones_like(t), t, np.zeros_like(t), np.zeros_like(t)])
    names = ["x0_m", *_pulse_names(1)]              # the 'pulse_R_0' column is the velocity
    x_a, x_b = np.array([1.0, 0.3, 0.0, 0.0]), np.array([3.5, 0.3, 0.0, 0.0])
    lin_a, lin_b = np.array([0.9, 0.2, 0.0, 0.0]), np.array([3.3, 0.1, 0.0, 0.0])
    w = 1.0 / 0.01**2
    reg = np.diag([0.0, 0.0, 1.0, 1.0])            # T, N columns unobserved: damped

    def arc(x_true, x_lin):
        y = h @ (x_true - x_lin)                     # misclosures at the linearisation
        return _arc(names, x_lin, w * h.T @ h + reg, w * h.T @ y, [0.5])

    a, b = arc(x_a, lin_a), arc(x_b, lin_b)
    design, misclosure, weight, _ = relative_rows(a, b, SETTINGS)
    tied = joint_solve(a, b, design, misclosure, weight)
    free = joint_solve(a, b, np.zeros((0, 8)), np.zeros(0), np.zeros(0))
    for sol in (tied, free):
        np.testing.assert_allclose(lin_a + sol.dx_a, x_a, atol=1e-9)
        np.testing.assert_allclose(lin_b + sol.dx_b, x_b, atol=1e-9)
    # baseline at t = 1: (x0_B + v_B) - (x0_A + v_A)
    g = np.array([-1.0, -1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0])
    var_tied, var_free = g @ tied.covariance @ g, g @ free.covariance @ g
    assert var_tied < 0.6 * var_free
    # the constraint rows are satisfied: noise-free data agree with them exactly
    res = constraint_residuals(design, misclosure, tied.dx_a, tied.dx_b)
    np.testing.assert_allclose(res * np.sqrt(weight), 0.0, atol=1e-6)


def test_hard_dd_constraint_has_zero_residual():
    """A DD-like row on the ambiguities of A and B with a sigma far below the data noise is
    met to a small fraction of that sigma after the solve (constraint_residuals): the
    residual is the misclosure times σ_c² / (σ_c² + σ_amb²) (σ_amb ~ 2 mm here)."""
    rng = np.random.default_rng(5)
    n = 3                                            # 2 arc parameters + 1 ambiguity each
    arcs = []
    for _ in range(2):
        h = rng.normal(size=(20, n))
        y = rng.normal(scale=0.005, size=20)
        arcs.append(_arc(["x0_m", "y0_m"], np.zeros(2), 4e4 * h.T @ h, 4e4 * h.T @ y, [],
                         n_amb=1))
    design = np.array([[0.0, 0.0, -1.0, 0.0, 0.0, 1.0]])
    misclosure = np.array([0.004])      # float minus fixed DD: a few mm
    weight = np.array([1.0 / 1e-5**2])
    sol = joint_solve(*arcs, design, misclosure, weight)
    res = constraint_residuals(design, misclosure, sol.dx_a, sol.dx_b)
    assert abs(res[0]) < 0.1 * 1e-5


def test_reference_fixed_recovers_a_known_offset():
    """Leader held at a (slightly wrong) fixed solution: the follower, tied to it by a
    precise differential observation (a DD-like row on x0) and by relative dynamics, takes
    the leader's value plus the true offset — the baseline is right even where the leader's
    orbit is not (authority: the conditional least-squares solution, Koch 1999 sec. 3.2)."""
    t = np.linspace(0.0, 1.0, 11)
    h = np.column_stack([np.ones_like(t), t, np.zeros_like(t), np.zeros_like(t)])
    names = ["x0_m", *_pulse_names(1)]
    offset = 2.5
    x_a = np.array([1.0, 0.3, 0.0, 0.0])
    x_b = x_a + np.array([offset, 0.0, 0.0, 0.0])
    lin = np.zeros(4)
    reg = np.diag([0.0, 0.0, 1.0, 1.0])
    w_loose = 1.0 / 1.0**2                           # the follower's own data: 1 m noise

    def arc(x_true, w):
        return _arc(names, lin, w * h.T @ h + reg, w * h.T @ (h @ x_true), [0.5])

    a, b = arc(x_a, 1e4), arc(x_b, w_loose)
    leader_error = np.array([0.004, -0.002, 0.0, 0.0])  # the leader's fixed solution, 4 mm off
    dx_a = x_a + leader_error - lin
    rel_d, rel_m, rel_w, _ = relative_rows(a, b, SETTINGS)
    # x0_B − x0_A = offset ± 1e-5 (the differential data)
    dd = np.zeros((1, 8))
    dd[0, 0], dd[0, 4] = -1.0, 1.0
    design = np.vstack([dd, rel_d])
    misclosure = np.concatenate([[offset - (lin[0] - lin[0])], rel_m])
    weight = np.concatenate([[1e10], rel_w])
    sol = reference_fixed_solve(a, b, design, misclosure, weight, dx_a)
    np.testing.assert_array_equal(sol.dx_a, dx_a)
    x_b_est = lin + sol.dx_b
    # the follower follows the leader's error: the baseline is exact to the weights' level
    np.testing.assert_allclose(x_b_est[0] - (lin[0] + dx_a[0]), offset, atol=1e-5)
    np.testing.assert_allclose(x_b_est[1], x_a[1] + leader_error[1], atol=1e-5)
    # the leader has no covariance
    assert not sol.covariance[:4].any() and not sol.covariance[:, :4].any()
    assert np.all(np.diag(sol.covariance)[4:] > 0)


def test_fixed_correction_by_name_and_pass():
    import xarray as xr

    names = ["x0_m", "drag_scale_0"]
    a = _arc(names, np.array([10.0, 1.0]), np.eye(4), np.zeros(4), [], n_amb=2)
    a.active = np.array([3, 7])
    a.ambiguity_m = np.array([0.5, -1.0])
    params = xr.Dataset({"estimate": (("parameter",), [1.02, 10.5, 9.9])},
                        coords={"parameter": ["drag_scale_0", "x0_m", "isb_C_m"]})
    amb = xr.Dataset({"pass_index": (("ambiguity",), [7, 3, 5]),
                      "value_m": (("ambiguity",), [-1.1, 0.7, 3.0])})
    np.testing.assert_allclose(fixed_correction(a, params, amb), [0.5, 0.02, 0.2, -0.1])
