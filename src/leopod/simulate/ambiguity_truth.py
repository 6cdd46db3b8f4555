"""True integer single-difference ambiguities of a simulated arc (to count wrong fixes).

The simulator keeps the integer ambiguity of every observation (``amb_<phase>_cyc`` on
(obs_time, sv) in ``<date>_truth.nc``; satellite and receiver phase biases lie in ±0.5 cycles,
so they never move the integers). A POD pass has one ambiguity; its true ``N1`` and
``N_WL = N1 − N2`` are taken from the truth at the pass's epochs (the median, which is the
value itself unless a pass wrongly spans a slip), with the phase pair of the pass's system:
a combined arc (e.g. GPS L1C/L2W with BDS-3 L1P/L5P) takes each system's own pair, as its
ambiguity resolution does (:func:`leopod.ambiguity.resolve.resolve_systems`), and its
single differences are always within one system.

The phase wind-up (equal in cycles on both frequencies) is continuous in the simulator from
the first epoch of the day, in the estimator from the first epoch of its arc
(:func:`leopod.gnss.corrections.unwrap_windup` over the arc's observations): the two differ by
a whole number of cycles ``k`` per satellite once the wind-up has wandered beyond ±0.5 cycles
since the day began (a yaw-steering LEO sweeps its yaw by up to 180° every orbit). The
estimated ``N1`` and ``N2`` are then the simulated ones plus ``k`` (``N_WL`` keeps nothing of
it), so the true integers refer to the wind-up unwrapped as the estimator does, from the truth
file's ``windup_cyc`` when it has it.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import xarray as xr

from leopod.gnss.corrections import unwrap_windup
from leopod.signals import system_of

__all__ = ["true_single_differences", "wrong_fix_counts", "wrong_fixes", "wrong_fixes_per_system"]


def _group_medians(groups: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Median of the finite ``values`` of each group label (NaN for a group without any),
    as ``np.nanmedian`` of each group, in one sort.

    Returns
    -------
    keys, medians : ndarray, shape (n_group,)
    """
    order = np.lexsort((values, groups))            # NaN last within a group
    g, v = groups[order], values[order]
    keys, first = np.unique(g, return_index=True)
    n = np.add.reduceat(np.isfinite(v).astype(int), first) if g.size else np.zeros(0, int)
    lo, hi = first + np.maximum(n - 1, 0) // 2, first + n // 2   # the middle one or two
    return keys, np.where(n > 0, 0.5 * (v[lo] + v[hi]), np.nan)


def _per_pass_truth(pid: xr.DataArray, truth: xr.Dataset, names) -> dict:
    """``{"n1": {pass: N1}, "nwl": {pass: N1 − N2}}`` of the passes in ``pid`` (time, sv):
    the median over the pass's epochs."""
    tr = truth[names].reindex(time=pid.time, sv=pid.sv)
    p = pid.values.ravel()
    n1 = tr[names[0]].values.ravel()
    nwl = n1 - tr[names[1]].values.ravel()
    ok = p >= 0
    return {name: dict(zip(*_group_medians(p[ok], v[ok]), strict=True))
            for name, v in (("n1", n1), ("nwl", nwl))}


def true_single_differences(table: xr.Dataset, residuals: xr.Dataset, truth_days,
                            phases=("L1C", "L2W")) -> tuple[np.ndarray, np.ndarray]:
    """True ``ΔN_WL`` and ``ΔN1`` of every single difference of an ambiguity table.

    Parameters
    ----------
    table : xarray.Dataset
        Output of :func:`leopod.ambiguity.resolve.resolve_arc` or
        :func:`~leopod.ambiguity.resolve.resolve_systems` (``pass_i``, ``pass_j``,
        ``sv_i`` for a combined arc).
    residuals : xarray.Dataset
        Float POD residuals (``pass_index`` on (time, sv)).
    truth_days : list of xarray.Dataset
        Simulator truth files of the arc's days.
    phases : two str, or mapping of str to two str
        Phase signals of the pair; for a combined arc the pair of each system letter
        (e.g. ``{"G": ("L1C", "L2W"), "C": ("L1P", "L5P")}``). Satellites of a system
        without a pair get no truth.

    Returns
    -------
    wl, nl : ndarray of float, shape (n_pair,)
        True integers (NaN where the truth has no value).

    Raises
    ------
    KeyError
        If the truth files have no ``amb_<phase>_cyc`` of a requested phase.
    """
    pairs = dict(phases) if isinstance(phases, Mapping) else None
    needed = sorted({f"amb_{p}_cyc" for pair in (pairs.values() if pairs else [phases])
                     for p in pair})
    missing = [n for n in needed if any(n not in t for t in truth_days)]
    if missing:
        raise KeyError(f"simulator truth without {', '.join(missing)} (the phases of the "
                       "ambiguity resolution must be simulated)")
    windup = all("windup_cyc" in t for t in truth_days)
    keep = needed + ["windup_cyc"] * windup
    truth = xr.concat([t[keep].rename(obs_time="time") for t in truth_days], dim="time")
    pid = residuals.pass_index
    if windup:
        truth = truth.reindex(time=pid.time, sv=pid.sv).transpose(*pid.dims)
        k = _windup_offset_cyc(truth["windup_cyc"].values, _arc_observations(residuals))
        truth = truth[needed] + xr.DataArray(k, coords=pid.coords, dims=pid.dims)
    per_pass = {"n1": {}, "nwl": {}}
    if pairs is None:
        groups = [(pid, [f"amb_{p}_cyc" for p in phases])]
    else:
        letters = system_of(pid.sv.values)
        groups = [(pid.isel(sv=np.flatnonzero(letters == x)), [f"amb_{p}_cyc" for p in pair])
                  for x, pair in pairs.items() if np.any(letters == x)]
    for part, names in groups:
        for name, values in _per_pass_truth(part, truth, names).items():
            per_pass[name].update(values)

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
    """Counts of fixed single differences whose integer differs from the truth (a fix
    without a true value counts as wrong)."""
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


def wrong_fixes_per_system(table: xr.Dataset, true_wl: np.ndarray,
                           true_nl: np.ndarray) -> dict[str, dict]:
    """:func:`wrong_fixes` of the single differences of each system (first letter of
    ``sv_i``; single differences are formed within a system): ``{system: counts}``."""
    letters = system_of(table.sv_i.values)
    true_wl, true_nl = np.asarray(true_wl), np.asarray(true_nl)
    return {str(x): wrong_fixes(table.isel(pair=sel), true_wl[sel], true_nl[sel])
            for x in np.unique(letters) for sel in [np.flatnonzero(letters == x)]}


def wrong_fix_counts(table: xr.Dataset, residuals: xr.Dataset, truth_days,
                     phases: Mapping) -> dict[str, dict]:
    """Wrong fixes of an ambiguity table against the simulated truth, all single
    differences together (key ``"all"``) and per system (keys ``G``, ``C``, ...).

    Parameters
    ----------
    table, residuals, truth_days
        As for :func:`true_single_differences`.
    phases : mapping of str to two str
        Phase pair of each system of the arc (``signals.<S>.phase``).

    Returns
    -------
    dict
        ``{"all": counts, system: counts}``, counts of :func:`wrong_fixes`.
    """
    wl, nl = true_single_differences(table, residuals, truth_days,
                                     {x: tuple(p) for x, p in phases.items()})
    return {"all": wrong_fixes(table, wl, nl)} | wrong_fixes_per_system(table, wl, nl)
