"""Manoeuvres: one constant radial, along-track, cross-track acceleration per listed burn.

The thrust of a station-keeping burn is modelled as a constant acceleration in the RTN frame of
the satellite (frame of :mod:`leopod.dynamics.empirical`) from the burn's start to its end, zero
outside; one set of three accelerations per manoeuvre is estimated, its a-priori value the one
of the manoeuvre file and its a-priori sigma a setting (Mao et al. 2023, GPS Solutions,
"GNSS-based precise orbit determination for maneuvering LEO satellites": constant thrust
acceleration over the burn interval; Lutan-1 processing of paper 003, "one set of constant
R/T/N accelerations per manoeuvre")::

    a(t) = Mᵀ [a_R,k, a_T,k, a_N,k]   for start_k ≤ t < end_k,   0 otherwise

with M the rows R, T, N of the current state. Partials: ``∂a/∂a_X,k = Mᵀ e_X`` inside burn k
(exact), ``∂a/∂r`` and ``∂a/∂v`` through the frame neglected as in
:mod:`leopod.dynamics.empirical` (|a|/|r| ≈ 1e-11 s⁻² for |a| ≈ 1e-4 m/s², five orders below
the gravity gradient). Burn starts and ends are breakpoints, at which the integrator restarts
(:mod:`leopod.dynamics.integrator`), so the thrust switches exactly at the listed epochs.

Parameter layout: ``man_{X}_{k}`` [m/s²], burn k major, X in R, T, N.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from leopod.dynamics.empirical import _local_partials
from leopod.dynamics.forces import Force
from leopod.io.manoeuvre import Manoeuvre
from leopod.time.calendar import seconds_since

__all__ = ["Manoeuvres"]

#: Direction indices (R, T, N) and the single constant term of :func:`_local_partials`.
_RTN = np.arange(3, dtype=np.int64)
_CONST = np.zeros(1, dtype=np.int64)


class Manoeuvres(Force):
    """Constant RTN accelerations over the burns of a manoeuvre list (module docstring).

    Parameters
    ----------
    start_s, end_s : array_like, shape (K,)
        Start and end of each burn [TT s since the reference epoch of the arc], increasing,
        not overlapping.
    apriori_rtn_m_s2 : array_like, shape (K, 3)
        A-priori accelerations R, T, N [m/s²] (the manoeuvre file's).
    estimate : bool
        Whether the accelerations are estimated.
    sigma : float or None
        A-priori sigma of every acceleration [m/s²] (None: free).
    """

    def __init__(self, start_s, end_s, apriori_rtn_m_s2, *, estimate: bool = True,
                 sigma: float | None = None):
        start = np.atleast_1d(np.asarray(start_s, dtype=float))
        end = np.atleast_1d(np.asarray(end_s, dtype=float))
        acc = np.asarray(apriori_rtn_m_s2, dtype=float).reshape(-1, 3)
        if start.shape != end.shape or acc.shape[0] != start.size:
            raise ValueError("manoeuvres: start_s, end_s and apriori_rtn_m_s2 must describe "
                             "the same burns")
        if np.any(end <= start) or np.any(start[1:] < end[:-1]):
            raise ValueError("manoeuvres must be increasing, non-overlapping burns")
        self.start_s, self.end_s = start, end
        self.parameters = [f"man_{x}_{k}" for k in range(start.size) for x in "RTN"]
        self.apriori = acc.ravel().copy()
        self.estimate = bool(estimate)
        self.sigma = np.full(acc.size, np.inf if sigma is None else float(sigma))

    @classmethod
    def of(cls, burns: Sequence[Manoeuvre], t_ref, t_start_s: float, t_end_s: float,
           **kwargs) -> Manoeuvres | None:
        """The burns of a list that act inside ``[t_start_s, t_end_s]`` [s since ``t_ref``,
        a GPS-time label], or None if there are none (keywords as the class)."""
        if not burns:
            return None
        start = seconds_since(np.array([b.start for b in burns]), t_ref)
        end = seconds_since(np.array([b.end for b in burns]), t_ref)
        inside = (end > t_start_s) & (start < t_end_s)
        if not inside.any():
            return None
        acc = np.array([b.acc_rtn_m_s2 for b in burns])[inside]
        return cls(start[inside], end[inside], acc, **kwargs)

    @property
    def breakpoints_s(self) -> np.ndarray:
        return np.concatenate([self.start_s, self.end_s])

    def burn(self, t_s: float) -> int:
        """Index of the burn acting at ``t_s``, −1 if none."""
        k = int(np.searchsorted(self.start_s, t_s, side="right")) - 1
        return k if k >= 0 and t_s < self.end_s[k] else -1

    def kernel_data(self) -> tuple:
        """``(start_s, end_s)`` (compiled force model)."""
        return self.start_s, self.end_s

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        da_dp = np.zeros((3, len(self.parameters)))
        acc = np.zeros(3)
        k = self.burn(t_s)
        if k >= 0:
            local = _local_partials(np.asarray(pos_m, dtype=float),
                                    np.asarray(vel_m_s, dtype=float), _RTN, _CONST)
            da_dp[:, 3 * k:3 * k + 3] = local
            acc = local @ np.asarray(params, dtype=float)[3 * k:3 * k + 3]
        return acc, np.zeros((3, 3)), np.zeros((3, 3)), da_dp
