"""Station-keeping manoeuvres of a simulated satellite: daily constant-thrust arcs.

A burn is a constant acceleration in the satellite's own radial, along-track, cross-track frame
(:func:`leopod.frames.rtn.rtn_matrix`) between two epochs; its size is given as the velocity
change ``Δv`` [m/s] it produces over its duration ``T`` (``a = Δv / T``), the way operators
size station-keeping burns. The truth integration adds the acceleration to the piecewise
constant stochastic accelerations of :mod:`leopod.simulate.truth_forces` (the ``empirical``
force with ``directions: [R, T, N]``, ``terms: [const]``): the burn epochs become interval
boundaries, hence breakpoints at which the integrator restarts
(:mod:`leopod.dynamics.integrator`), so the thrust switches on and off exactly at the listed
epochs. The burns go to the manoeuvre file of the satellite (:mod:`leopod.io.manoeuvre`), the
list that baseline determination reads to estimate one set of R/T/N accelerations per burn
(Mao et al. 2023; Zhang et al. 2024, Table 1).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from leopod.dynamics.empirical import Empirical, EmpiricalModel
from leopod.dynamics.forces import ForceModel
from leopod.io.manoeuvre import Manoeuvre
from leopod.time.calendar import seconds_since

__all__ = ["daily_manoeuvres", "with_manoeuvres"]

_NS_PER_S = 1_000_000_000
_DAY = np.timedelta64(86_400, "s")


def _time_of_day(text: str) -> np.timedelta64:
    """``HH:MM:SS`` (seconds may have decimals) as a timedelta [ns]."""
    try:
        h, m, s = text.split(":")
        seconds = int(h) * 3600 + int(m) * 60 + float(s)
    except ValueError:
        raise ValueError(f"manoeuvre time_of_day {text!r} is not HH:MM:SS") from None
    if not 0.0 <= seconds < 86_400.0:
        raise ValueError(f"manoeuvre time_of_day {text!r} is not within a day")
    return np.timedelta64(round(seconds * _NS_PER_S), "ns")


def daily_manoeuvres(burns: Sequence[Mapping[str, Any]], first_day: np.datetime64,
                     n_days: int) -> tuple[Manoeuvre, ...]:
    """The burns of a daily station-keeping plan over ``n_days`` days.

    Parameters
    ----------
    burns : sequence of mapping
        Each with ``time_of_day`` (``HH:MM:SS``, GPS time), ``duration_s`` [s] and
        ``dv_rtn_m_s`` (3,) [m/s] (``satellites.<sat>.formation.manoeuvres``).
    first_day : datetime64
        00:00 of the first day.
    n_days : int
        Number of days; every burn is repeated each day.

    Returns
    -------
    tuple of Manoeuvre
        In time order, acceleration ``dv / duration``.

    Raises
    ------
    ValueError
        If a duration is not positive or two burns overlap.
    """
    out = []
    day0 = np.datetime64(first_day, "ns")
    for day in range(int(n_days)):
        for burn in burns:
            duration = float(burn["duration_s"])
            if not duration > 0.0:
                raise ValueError(f"manoeuvre duration_s must be > 0 (got {duration})")
            start = day0 + day * _DAY + _time_of_day(str(burn["time_of_day"]))
            end = start + np.timedelta64(round(duration * _NS_PER_S), "ns")
            acc = np.asarray(burn["dv_rtn_m_s"], dtype=float) / duration
            out.append(Manoeuvre(start, end, tuple(float(a) for a in acc)))
    out.sort(key=lambda m: m.start)
    for a, b in zip(out[:-1], out[1:]):
        if b.start < a.end:
            raise ValueError(f"manoeuvres overlap: {a.start}..{a.end} and {b.start}")
    return tuple(out)


def with_manoeuvres(model: ForceModel, params: np.ndarray, manoeuvres: Sequence[Manoeuvre],
                    t_ref: np.datetime64) -> tuple[ForceModel, np.ndarray]:
    """The force model and parameters with the burns added to its constant RTN accelerations.

    Parameters
    ----------
    model : ForceModel
        A model with one :class:`~leopod.dynamics.empirical.Empirical` force of directions
        R, T, N and the single term ``const`` (the truth's stochastic accelerations).
    params : ndarray, shape (P,)
        Its parameter values.
    manoeuvres : sequence of Manoeuvre
        Burns inside the empirical force's span.
    t_ref : datetime64
        Reference epoch of the force model's time argument (GPS-time label; force times are
        GPS seconds since it).

    Returns
    -------
    ForceModel
        The same forces (the same objects) but the empirical one, whose intervals now also
        break at every burn start and end.
    ndarray
        Its parameters: each new interval holds the stochastic acceleration of the old
        interval it lies in, plus the acceleration of the burn it lies in.

    Raises
    ------
    ValueError
        If the model has no such empirical force or a burn lies outside its span.
    """
    if not manoeuvres:
        return model, params
    index = [i for i, f in enumerate(model.forces) if isinstance(f, Empirical)]
    if len(index) != 1:
        raise ValueError("with_manoeuvres needs exactly one empirical force in the model")
    old_force = model.forces[index[0]]
    old = old_force.model
    if old.directions != ("R", "T", "N") or old.terms != ("const",):
        raise ValueError("with_manoeuvres needs constant R, T, N empirical accelerations")
    start_s = seconds_since(np.array([m.start for m in manoeuvres]), t_ref)
    end_s = seconds_since(np.array([m.end for m in manoeuvres]), t_ref)
    lo, hi = old.boundaries_s[0], old.boundaries_s[-1]
    if start_s.min() < lo or end_s.max() > hi:
        raise ValueError(f"manoeuvres outside the integrated arc [{lo}, {hi}] s of {t_ref}")
    edges = np.unique(np.concatenate([old.boundaries_s, start_s, end_s]))
    offset = sum(len(f.parameters) for f in model.forces[:index[0]])
    old_values = params[offset:offset + old.n_params].reshape(old.n_intervals, 3)
    mid = 0.5 * (edges[:-1] + edges[1:])
    values = old_values[[old.interval(t) for t in mid]].copy()
    for m, a, b in zip(manoeuvres, start_s, end_s):
        values[(mid > a) & (mid < b)] += np.asarray(m.acc_rtn_m_s2, dtype=float)
    new_force = Empirical(EmpiricalModel(edges, directions=old.directions, terms=old.terms),
                          estimate=False)
    forces = list(model.forces)
    forces[index[0]] = new_force
    new_params = np.concatenate([params[:offset], values.ravel(),
                                 params[offset + old.n_params:]])
    return ForceModel(forces), new_params
