"""The float POD's last linearisation, handed to the fixed POD so that it need not integrate.

The ambiguity-fixed solution (:class:`leopod.estimation.float_pod.FixedPod`) is linearised
at the converged float solution: the float orbit at the reception epochs of the float
receiver clocks, and the partials ``G(t)`` of the arc parameters there and at the output
epochs. The float POD already has both: its orbit is its last integration ``y(t; x)`` plus
the last correction ``G(t) Δx`` through the partials of that integration
(:class:`leopod.estimation.orbit_correction.CorrectedOrbit`). Integrating again at
``x + Δx`` (what the fixed POD did) gives the same orbit to ``|Δr|²/r`` (1e-13 m for the
float POD's last correction below 1 mm) and partials that change by a relative amount of the
order of ``|Δr|/r`` (1e-10): ~1 s of computing for nothing. Measured: the fixed solutions
from the stored and from a new integration agree to 3e-9 m
(tests/estimation/test_fixed_pod.py), 4e-9 m on the default campaign.

So the float POD writes its last integration sampled at the epochs the fixed POD evaluates
— the reception epochs of its final receiver clocks (nominal epochs minus the clock, as
:meth:`leopod.estimation.float_pod._Problem.linearise` forms them from the clocks the fixed
POD reads back), the output epochs and the pulse epochs — with the last correction
(:func:`linearisation_dataset`); the fixed POD reads it back as a
:func:`leopod.dynamics.integrator.sampled_trajectory` plus that correction
(:func:`read_linearisation`), which answers at exactly those epochs (the same bits as the
float POD's interpolant) and refuses any other.

Size: the state, the 6×6 transition matrix and the 6×P sensitivities at ~2 m epochs (m
observation epochs; pulse partials follow from the transition matrix, Jäggi et al. 2006):
for a 30-h arc at 30 s with 51 force parameters, (2 × 3600 + 119) × 6 × 58 doubles = 20 MB
(stored without compression: zlib level 1 with shuffle makes it 9.3 MB but took 0.83 s to
write and 0.19 s to read instead of 0.03 and 0.04 s, measured on a busy machine).
It is a regular product of the float POD, not a temporary file, so that the fixed POD can run
again alone (after a change of an ambiguity setting) and always from the same linearisation.

Dataset (dims ``epoch``, ``row``, ``column``, ``correction``)
    ``t_s`` (epoch) [s since ``t_ref``], ``augmented`` (epoch, row, column)
    ``[y | Φ | S]``, ``initial`` (row, column) the same at ``t0_s``, ``correction``
    (correction) the float POD's last ``Δx`` (initial state, estimated force parameters,
    pulses); attributes ``t_ref`` (ISO, GPS time), ``t0_s``, ``parameters`` (names of the
    sensitivity columns, space-separated).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from leopod.constants import C_LIGHT_M_S
from leopod.dynamics.integrator import Trajectory, sampled_trajectory
from leopod.estimation.float_pod import PodObservations, PodResult
from leopod.time.calendar import seconds_since

__all__ = ["FloatLinearisation", "linearisation_dataset", "read_linearisation",
           "reception_epochs_s"]


@dataclass(eq=False)
class FloatLinearisation:
    """The float POD's last integration at the epochs of the fixed POD and its last
    correction: the float orbit is ``CorrectedOrbit(trajectory, pulses, estimated,
    correction)``.

    Attributes
    ----------
    trajectory : Trajectory
        Sampled (:func:`leopod.dynamics.integrator.sampled_trajectory`).
    correction : ndarray, shape (6 + p + 3 n,)
        ``Δx`` of the float POD's last solution.
    t_ref : datetime64
        Time origin of ``trajectory`` (the arc's first observation epoch).
    source : str
        The file it was read from (for messages).
    """

    trajectory: Trajectory
    correction: np.ndarray
    t_ref: np.datetime64
    source: str = "float POD linearisation"

    def check(self, t_ref: np.datetime64, reception_s: np.ndarray,
              output_s: np.ndarray | None = None) -> None:
        """Refuse (``ValueError`` naming the file) a linearisation of another arc: another
        time origin, or reception or output epochs [s] the trajectory was not sampled at."""
        if self.t_ref != t_ref:
            raise ValueError(f"{self.source}: float POD linearisation of an arc from "
                             f"{self.t_ref}, not {t_ref}: not that of this float solution")
        missing = ~np.isin(reception_s, self.trajectory.t_s)
        if missing.any():
            raise ValueError(f"{self.source}: {int(missing.sum())} reception epochs of the "
                             "float solution are not among its epochs: not that of this float "
                             "solution")
        if output_s is not None and not (np.isin(output_s, self.trajectory.t_s)
                                         | (output_s == self.trajectory.t0_s)).all():
            raise ValueError(f"{self.source}: the output epochs of the arc are not all among "
                             "its epochs: written for other output epochs (run the float POD "
                             "again)")


def reception_epochs_s(t_nominal_s: np.ndarray, clk_rx_m: np.ndarray,
                       apriori_clk_rx_m: np.ndarray) -> np.ndarray:
    """Reception epochs [s] of a solution continued from receiver clocks ``clk_rx_m`` [m]
    (NaN: unknown, the a-priori ``apriori_clk_rx_m`` is taken; NaN there too: 0), at the
    nominal epochs ``t_nominal_s`` [s], shape (m,): as the fixed POD forms them
    (:meth:`leopod.estimation.float_pod._Problem.load` and ``linearise``)."""
    clk = np.where(np.isfinite(clk_rx_m), clk_rx_m, apriori_clk_rx_m)
    return t_nominal_s - np.nan_to_num(clk) / C_LIGHT_M_S


def linearisation_dataset(result: PodResult, obs: PodObservations,
                          output_times: np.ndarray) -> xr.Dataset:
    """The float POD's last linearisation at the epochs the fixed POD evaluates (module
    docstring).

    Parameters
    ----------
    result : PodResult
        The float solution (its ``orbit``: last integration and correction).
    obs : PodObservations
        Its observations (nominal epochs, a-priori receiver clocks).
    output_times : ndarray of datetime64, shape (o,)
        Epochs of the orbit datasets.
    """
    traj = result.orbit.trajectory
    t_nominal = seconds_since(obs.times, result.t_ref)
    epochs = [reception_epochs_s(t_nominal, result.clk_rx_m, obs.clk_rx_m),
              seconds_since(np.asarray(output_times, dtype="datetime64[ns]"), result.t_ref)]
    if result.pulses is not None:
        epochs.append(result.pulses.epochs_s)
    t = np.unique(np.concatenate(epochs))
    t = t[t != traj.t0_s]              # the initial state is stored on its own
    sampled = traj.at(t)
    return xr.Dataset(
        {
            "t_s": ("epoch", t, {"units": "s", "long_name": "epoch in seconds since t_ref "
                                 "(GPS time scale)"}),
            "augmented": (("epoch", "row", "column"), sampled.augmented,
                          {"units": "1", "long_name": "GCRF state [m, m/s], state transition "
                           "matrix and sensitivities [SI] of the float POD's last "
                           "integration"}),
            "initial": (("row", "column"), traj.initial,
                        {"units": "1", "long_name": "the same at t0_s"}),
            "correction": ("correction", result.orbit.correction,
                           {"units": "1", "long_name": "last correction of the initial state, "
                            "estimated force parameters and pulses [SI]"}),
        },
        attrs={"t_ref": str(np.datetime64(result.t_ref, "ns")), "t0_s": float(traj.t0_s),
               "parameters": " ".join(traj.parameters)},
    )


def read_linearisation(ds: xr.Dataset) -> FloatLinearisation:
    """:class:`FloatLinearisation` of a :func:`linearisation_dataset` read back."""
    traj = sampled_trajectory(ds.t_s.values, ds.augmented.values, float(ds.attrs["t0_s"]),
                              str(ds.attrs["parameters"]).split(), ds.initial.values)
    return FloatLinearisation(trajectory=traj, correction=ds.correction.values.copy(),
                              t_ref=np.datetime64(ds.attrs["t_ref"], "ns"),
                              source=str(ds.encoding.get("source", "float POD linearisation")))
