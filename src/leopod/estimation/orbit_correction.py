"""An integrated orbit plus the linear correction of its arc parameters (no re-integration).

Near an orbit ``y(t; x)`` integrated at the arc parameters ``x`` (initial state, estimated
force parameters, pseudo-stochastic pulses) with its variational equations, the orbit at
``x + Δx`` is, to first order (Montenbruck & Gill 2000, sec. 7.2 and 8.1)::

    y(t; x + Δx) = y(t; x) + G(t) Δx + O(|Δx|²),
    G(t) = [Φ(t, t0) | S(t) of the estimated parameters | ∂y(t)/∂Δv]

with the state transition matrix Φ, the sensitivity matrix S and the pulse partials from Φ
(:func:`leopod.dynamics.integrator.pulse_partials`; Jäggi et al. 2006). These are the
partials of the least-squares solution that produced ``Δx``, so the corrected orbit is the
solution's own linear model of the orbit, positions and velocities alike.

Size of the neglected term: of the order of ``|Δr|²/r`` for a position correction |Δr| on
an orbit of radius r (the curvature of the flow; measured 0.2 mm for a 55-m correction of
every kind of parameter over 6 h, tests/estimation/test_orbit_correction.py). For the
corrections it serves, below 1 mm (the float POD's last one) or ~1 cm (float to fixed), that
is below 1e-10 m, under the reproducibility of an integration itself (~1e-6 m: the orbit
corrected by 4 mm agrees with a re-integration at ``x + Δx`` to 2e-7 m).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from leopod.dynamics.forces import PseudoStochasticPulses
from leopod.dynamics.integrator import Trajectory, pulse_partials
from leopod.estimation.normals import leading_blocks

__all__ = ["CorrectedOrbit", "epoch_covariance"]


@dataclass(eq=False)
class CorrectedOrbit:
    """Orbit ``y(t; x) + G(t) Δx`` from a trajectory integrated at ``x`` (module docstring).

    Attributes
    ----------
    trajectory : Trajectory
        Orbit integrated at ``x`` with its partials (GCRF, dense); with pulses, integrated
        with them (:func:`leopod.dynamics.integrator.apply_pulses`).
    pulses : PseudoStochasticPulses or None
        Pulse epochs of the arc.
    estimated : ndarray of bool, shape (P,)
        Estimated force parameters (columns of ``trajectory.sensitivity``).
    correction : ndarray, shape (6 + p + 3 n,)
        ``Δx``: initial state [m, m/s], the p estimated force parameters, the n pulses in
        R, T, N [m/s], in this order.
    """

    trajectory: Trajectory
    pulses: PseudoStochasticPulses | None
    estimated: np.ndarray
    correction: np.ndarray

    def __post_init__(self):
        n_pulses = 0 if self.pulses is None else self.pulses.epochs_s.size
        k = 6 + int(np.count_nonzero(self.estimated)) + 3 * n_pulses
        if self.correction.shape != (k,):
            raise ValueError(f"correction must have shape ({k},) for the state, the estimated "
                             f"force parameters and the pulses, not {self.correction.shape}")

    def at(self, t_s) -> tuple[np.ndarray, np.ndarray]:
        """Corrected states and the partials ``G`` at epochs inside the integrated span.

        Parameters
        ----------
        t_s : array_like, shape (m,)
            Epochs [TT s since the reference epoch of the force model].

        Returns
        -------
        states : ndarray, shape (m, 6)
            GCRF position [m] and velocity [m/s] at ``x + Δx``.
        partials : ndarray, shape (m, 6, k)
            ``G(t) = ∂y(t)/∂x`` at ``x`` (columns as ``correction``).
        """
        traj = self.trajectory.at(t_s)
        parts = [traj.stm, traj.sensitivity[:, :, self.estimated]]
        if self.pulses is not None and self.pulses.epochs_s.size:
            parts.append(pulse_partials(self.trajectory, self.pulses, traj.t_s))
        g = np.concatenate(parts, axis=2)
        return traj.states + g @ self.correction, g


def epoch_covariance(partials: np.ndarray, covariance: np.ndarray) -> np.ndarray:
    """Covariance ``G_e Q G_eᵀ`` of a linear function of the parameters at each epoch.

    Summed per block of consecutive epochs over the leading columns up to the last one that
    is non-zero in the block (:func:`leopod.estimation.normals.leading_blocks`): a pulse's partials are zero before its epoch (after t0) and a
    piecewise parameter's before its interval, so the trailing columns of most blocks
    contribute exact zeros (about a third of the products of the full ``G Q Gᵀ`` for a
    30-h arc with 15-min pulses); the result differs from the full product by rounding only.

    Parameters
    ----------
    partials : ndarray, shape (m, d, k)
        ``G_e``: partials of d quantities (e.g. the GCRF position [m]) w.r.t. the k
        parameters at m epochs.
    covariance : ndarray, shape (k, k)
        ``Q``: covariance of the parameters.

    Returns
    -------
    ndarray, shape (m, d, d)
    """
    m, d, _ = partials.shape
    out = np.zeros((m, d, d))
    for block, n in leading_blocks(partials):
        g = partials[block, :, :n]
        gq = (g.reshape(-1, n) @ covariance[:n, :n]).reshape(g.shape)
        out[block] = gq @ g.transpose(0, 2, 1)
    return out
