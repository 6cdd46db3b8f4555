"""Compiled pulse partials vs the direct formula.

Authority: the direct formula of :func:`leopod.dynamics.integrator.pulse_partials` (Jäggi et
al. 2006; Montenbruck & Gill 2000 sec. 7.2), evaluated densely with numpy:
``±Φ(t, t0) Φ(t_i, t0)⁻¹ [0; M(t_i)]`` times the mask of the epochs where pulse i acts
(``t ≥ t_i`` for a pulse after t0, ``t < t_i`` with a minus sign for one before t0). Its
agreement with integrations with pulses is tested in test_integrator.py.
"""

import numpy as np
import pytest

from leopod.dynamics.forces import (
    ConstantAcceleration,
    ForceModel,
    PointMassGravity,
    PseudoStochasticPulses,
)
from leopod.dynamics.integrator import integrate, pulse_partials, sampled_trajectory
from leopod.frames.rtn import rtn_basis

#: Near-circular LEO at 6878 km, inclined 87° (GCRF) [m, m/s].
STATE0 = np.array([6_878_000.0, 0.0, 0.0, 0.0, 7612.6 * np.cos(1.52), 7612.6 * np.sin(1.52)])


def _direct(trajectory, epochs, t_out):
    at_pulse = trajectory.at(epochs)
    rhs = np.zeros((epochs.size, 6, 3))
    for i, state in enumerate(at_pulse.states):
        rhs[i, 3:] = rtn_basis(state[:3], state[3:])
    back = np.linalg.solve(at_pulse.stm, rhs)
    out = trajectory.at(t_out)
    after = epochs > trajectory.t0_s
    sign = np.where(after[None, :], (t_out[:, None] >= epochs[None, :]).astype(float),
                    -(t_out[:, None] < epochs[None, :]).astype(float))
    partials = np.einsum("mab,nbc->mnac", out.stm, back) * sign[:, :, None, None]
    acts = np.repeat(sign != 0.0, 3, axis=1)                            # (m, 3 n)
    return partials.transpose(0, 2, 1, 3).reshape(t_out.size, 6, 3 * epochs.size), acts


@pytest.mark.parametrize("t0_s", [0.0, 7200.0])      # all pulses after t0; some before it
def test_pulse_partials_equal_direct_formula(t0_s):
    model = ForceModel([PointMassGravity(), ConstantAcceleration([0.0, 5400.0, 10800.0])])
    params = np.array([1e-8, -2e-8, 3e-8, 0.0, 1e-8, 0.0])
    rng = np.random.default_rng(2)
    epochs = np.arange(900.0, 21600.0, 900.0)               # 23 pulses, 15 min apart
    epochs = epochs[epochs != t0_s]
    # unsorted output epochs: random ones, the pulse epochs themselves and t0
    t_out = np.concatenate([rng.uniform(0.0, 21600.0, 300), epochs, [t0_s, 0.0]])
    rng.shuffle(t_out)
    traj = integrate(model, t0_s, STATE0, params, [0.0, 21600.0], step_s=30.0)
    ref, acts = _direct(traj, epochs, t_out)
    assert 0 < acts.mean() < 1
    for got, n_rows in ((pulse_partials(traj, PseudoStochasticPulses(epochs), t_out), 6),
                        (pulse_partials(traj.at(t_out), epochs), 6),
                        (pulse_partials(traj, epochs, t_out, position_only=True), 3)):
        assert got.shape == (t_out.size, n_rows, ref.shape[2])
        assert not got.transpose(0, 2, 1)[~acts].any()       # exact zeros where no pulse acts
        np.testing.assert_allclose(got, ref[:, :n_rows], rtol=1e-13,
                                   atol=1e-13 * np.abs(ref).max())


def test_sampled_trajectory_answers_at_its_epochs_only():
    # authority: the integrated trajectory itself. A trajectory sampled at some epochs (the
    # float POD's, stored for the fixed POD) gives the same bits there - states, partials and
    # the pulse partials built from them - and refuses any other epoch
    model = ForceModel([PointMassGravity(), ConstantAcceleration([0.0, 5400.0, 10800.0])])
    params = np.array([1e-8, -2e-8, 3e-8, 0.0, 1e-8, 0.0])
    epochs = np.arange(900.0, 21600.0, 900.0)
    t0_s = 7200.0
    epochs = epochs[epochs != t0_s]
    traj = integrate(model, t0_s, STATE0, params, [0.0, 21600.0], step_s=30.0)
    t = np.unique(np.concatenate([np.linspace(0.0, 21600.0, 97) + 0.25, epochs]))
    t = t[(t <= 21600.0) & (t != t0_s)]
    at = traj.at(t)
    sampled = sampled_trajectory(t, at.augmented, t0_s, traj.parameters, traj.initial)
    ask = np.concatenate([t[::-3], [t0_s]])
    np.testing.assert_array_equal(sampled.at(ask).augmented, traj.at(ask).augmented)
    np.testing.assert_array_equal(pulse_partials(sampled, epochs, ask),
                                  pulse_partials(traj, epochs, ask))
    with pytest.raises(ValueError, match="known at its epochs only"):
        sampled.at([t[3] + 1e-6])
    with pytest.raises(ValueError, match="outside the integrated span"):
        sampled.at([t[-1] + 1.0])
