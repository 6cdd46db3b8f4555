"""True integer single-difference ambiguities of a simulated arc (to count wrong fixes).

The simulator keeps the integer ambiguity of every observation (``amb_<phase>_cyc`` on
(obs_time, sv) in ``<date>_truth.nc``; satellite and receiver phase biases lie in ±0.5 cycles,
so they never move the integers). A POD pass has one ambiguity; its true ``N1`` and
``N_WL = N1 − N2`` are taken from the truth at the pass's epochs (the median, which is the
value itself unless a pass wrongly spans a slip).

The phase wind-up (equal in cycles on both frequencies) is continuous in the simulator from
the first epoch of the day, in the estimator from the first epoch of its arc
(:func:`leopod.gnss.corrections.unwrap_windup` over the arc's observations): the two differ by
a whole number of cycles ``k`` per satellite once the wind-up has wandered beyond ±0.5 cycles
since the day began (a yaw-steering LEO sweeps its yaw by up to 180° every orbit). The
estimated ``N1`` is then the simulated one plus ``k`` (``N_WL`` keeps nothing of it), so the
true ``N1`` refers to the wind-up unwrapped as the estimator does, from the truth file's
``windup_cyc`` when it has it.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from leopod.gnss.corrections import unwrap_windup

__all__ = ["true_single_differences", "wrong_fixes"]


def true_single_differences(table: xr.Dataset, residuals: xr.Dataset, truth_days,
                            phases=("L1C", "L2W")) -> tuple[np.ndarray, np.ndarray]:
    """True ``ΔN_WL`` and ``ΔN1`` of every single difference of an ambiguity table.

    Parameters
    ----------
    table : xarray.Dataset
        Output of :func:`leopod.ambiguity.resolve.resolve_arc` (``pass_i``, ``pass_j``).
    residuals : xarray.Dataset
        Float POD residuals (``pass_index`` on (time, sv)).
    truth_days : list of xarray.Dataset
        Simulator truth files of the arc's days.
    phases : two str
        Phase signals of the pair.

    Returns
    -------
    wl, nl : ndarray of float, shape (n_pair,)
        True integers (NaN where the truth has no value).
    """
    names = [f"amb_{p}_cyc" for p in phases]
    windup = all("windup_cyc" in t for t in truth_days)
    keep = names + ["windup_cyc"] * windup
    truth = xr.concat([t[keep].rename(obs_time="time") for t in truth_days], dim="time")
    pid = residuals.pass_index
    tr = truth.reindex(time=pid.time, sv=pid.sv)
    p = pid.values.ravel()
    n1 = tr[names[0]].values.ravel()
    nwl = n1 - tr[names[1]].values.ravel()
    ok = p >= 0
    if windup:
        offset = _windup_offset_cyc(tr["windup_cyc"].values, _arc_observations(residuals))
        n1 = n1 + offset.ravel()
    order = np.argsort(p[ok], kind="stable")
    keys, first = np.unique(p[ok][order], return_index=True)
    per_pass = {}
    for name, v in (("n1", n1), ("nwl", nwl)):
        parts = np.split(v[ok][order], first[1:])
        per_pass[name] = dict(zip(keys, (np.nanmedian(x) if np.isfinite(x).any() else np.nan
                                         for x in parts), strict=True))

    def sd(name):
        look = per_pass[name]
        return np.array([look.get(i, np.nan) - look.get(j, np.nan)
                         for i, j in zip(table.pass_i.values, table.pass_j.values, strict=True)])

    return sd("nwl"), sd("n1")


def _arc_observations(residuals: xr.Dataset) -> np.ndarray:
    """(time, sv) observations of the POD arc: those in a pass or with a code or phase
    residual (the estimator's wind-up is unwrapped over all of them)."""
    used = residuals.pass_index.values >= 0
    for name in ("code_residual_m", "phase_residual_m"):
        if name in residuals:
            used = used | np.isfinite(residuals[name].transpose(*residuals.pass_index.dims).values)
    return used


def _windup_offset_cyc(windup_cyc: np.ndarray, used: np.ndarray) -> np.ndarray:
    """Whole cycles between the simulator's wind-up and the estimator's over the arc.

    Parameters
    ----------
    windup_cyc : ndarray, shape (n, s)
        Simulated wind-up at the arc's epochs [cycles], NaN where not tracked.
    used : ndarray of bool, shape (n, s)
        Observations of the arc (:func:`_arc_observations`).

    Returns
    -------
    ndarray, shape (n, s)
        ``k`` = simulated minus re-unwrapped wind-up (integers; 0 where not used).
    """
    ep, sv = np.nonzero(used & np.isfinite(windup_cyc))
    w = windup_cyc[ep, sv]
    arc = unwrap_windup(w - np.round(w), sv, ep)
    out = np.zeros(windup_cyc.shape)
    out[ep, sv] = np.round(w - arc)
    return out


def wrong_fixes(table: xr.Dataset, true_wl: np.ndarray, true_nl: np.ndarray) -> dict:
    """Counts of fixed single differences whose integer differs from the truth."""
    wl_fixed = table.wl_fixed.values == 1
    nl_fixed = table.nl_fixed.values == 1
    constrained = table.constrained.values == 1
    return {
        "wl_fixed": int(wl_fixed.sum()),
        "wl_wrong": int(np.sum(table.wl_integer.values[wl_fixed] != true_wl[wl_fixed])),
        "nl_fixed": int(nl_fixed.sum()),
        "nl_wrong": int(np.sum((table.nl_integer.values[nl_fixed] != true_nl[nl_fixed])
                               | (table.wl_integer.values[nl_fixed] != true_wl[nl_fixed]))),
        "constrained": int(constrained.sum()),
        "constrained_wrong": int(np.sum((table.nl_integer.values[constrained]
                                         != true_nl[constrained])
                                        | (table.wl_integer.values[constrained]
                                           != true_wl[constrained]))),
    }
