"""True integer single-difference ambiguities of a simulated arc (to count wrong fixes).

The simulator keeps the integer ambiguity of every observation (``amb_<phase>_cyc`` on
(obs_time, sv) in ``<date>_truth.nc``; satellite and receiver phase biases lie in ±0.5 cycles,
so they never move the integers). A POD pass has one ambiguity; its true ``N1`` and
``N_WL = N1 − N2`` are taken from the truth at the pass's epochs (the median, which is the
value itself unless a pass wrongly spans a slip). A combined arc of several systems takes
each satellite's integers from its own system's phase pair (GPS L1C/L2W, Galileo L1C/L5Q:
the truth file's ``amb_L1C_cyc`` holds both systems, each on its own satellites).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import xarray as xr

__all__ = ["true_single_differences", "wrong_fixes"]


def true_single_differences(table: xr.Dataset, residuals: xr.Dataset, truth_days,
                            phases=("L1C", "L2W")) -> tuple[np.ndarray, np.ndarray]:
    """True ``ΔN_WL`` and ``ΔN1`` of every single difference of an ambiguity table.

    Parameters
    ----------
    table : xarray.Dataset
        Output of :func:`leopod.ambiguity.resolve.resolve_arc` or, for a combined arc,
        :func:`leopod.ambiguity.resolve.resolve_systems` (``pass_i``, ``pass_j``).
    residuals : xarray.Dataset
        Float POD residuals (``pass_index`` on (time, sv)).
    truth_days : list of xarray.Dataset
        Simulator truth files of the arc's days.
    phases : two str, or mapping of str to two str
        Phase signals of the pair, or of each system's pair (system letter -> pair, e.g.
        ``{"G": ("L1C", "L2W"), "E": ("L1C", "L5Q")}``: each satellite's integers are those
        of its system's pair; satellites of other systems get NaN).

    Returns
    -------
    wl, nl : ndarray of float, shape (n_pair,)
        True integers (NaN where the truth has no value).
    """
    pairs = phases if isinstance(phases, Mapping) else None
    names = sorted({f"amb_{p}_cyc" for pair in (pairs.values() if pairs else [phases])
                    for p in pair})
    truth = xr.concat([t[names].rename(obs_time="time") for t in truth_days], dim="time")
    pid = residuals.pass_index
    tr = truth.reindex(time=pid.time, sv=pid.sv).transpose(*pid.dims)
    n1_grid = np.full(pid.shape, np.nan)
    n2_grid = np.full(pid.shape, np.nan)
    axis = pid.dims.index("sv")
    for k, sv in enumerate(pid.sv.values.astype(str)):
        pair = pairs.get(sv[0]) if pairs else phases
        if pair is None:
            continue
        col = [slice(None)] * pid.ndim
        col[axis] = k
        n1_grid[tuple(col)] = tr[f"amb_{pair[0]}_cyc"].values[tuple(col)]
        n2_grid[tuple(col)] = tr[f"amb_{pair[1]}_cyc"].values[tuple(col)]
    p = pid.values.ravel()
    n1 = n1_grid.ravel()
    nwl = n1 - n2_grid.ravel()
    ok = p >= 0
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
