"""True integer double differences of a simulated formation pair (to count wrong DD fixes).

A DD of receivers A and B (:mod:`leopod.ambiguity.double_difference`),
``(N_B,b_i − N_A,a_i) − (N_B,b_j − N_A,a_j)``, is the difference of two between-satellite
single differences of the receivers, ``(N_B,b_i − N_B,b_j) − (N_A,a_i − N_A,a_j)``, whose
true integers :func:`leopod.simulate.ambiguity_truth.true_single_differences` gives for each
receiver from its own truth and float residuals (wind-up unwrapped as its estimator does).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import xarray as xr

from leopod.simulate.ambiguity_truth import true_single_differences, wrong_fixes

__all__ = ["true_double_differences", "wrong_dd_fixes"]


def true_double_differences(table: xr.Dataset, residuals_a: xr.Dataset,
                            residuals_b: xr.Dataset, truth_a, truth_b,
                            phases: Mapping) -> tuple[np.ndarray, np.ndarray]:
    """True ``ΔN_WL`` and ``ΔN1`` (float arrays, NaN: no truth) of every DD of a table.

    Parameters
    ----------
    table : xarray.Dataset
        DD table (:func:`~leopod.ambiguity.double_difference.resolve_dd_systems`: ``pass_a_i``,
        ``pass_a_j``, ``pass_b_i``, ``pass_b_j``, ``sv_i``; dim ``dd``).
    residuals_a, residuals_b : xarray.Dataset
        Float POD residuals of the two receivers.
    truth_a, truth_b : list of xarray.Dataset
        Simulator truth files of the arc's days of each receiver.
    phases : mapping of str to two str
        Phase pair of each system.
    """
    pairs = {x: tuple(p) for x, p in phases.items()}
    out = []
    for key, res, truth in (("a", residuals_a, truth_a), ("b", residuals_b, truth_b)):
        sd = xr.Dataset({"pass_i": table[f"pass_{key}_i"], "pass_j": table[f"pass_{key}_j"],
                         "sv_i": table["sv_i"]})
        out.append(true_single_differences(sd, res, truth, pairs))
    (wl_a, nl_a), (wl_b, nl_b) = out
    return wl_b - wl_a, nl_b - nl_a


def wrong_dd_fixes(table: xr.Dataset, true_wl: np.ndarray, true_nl: np.ndarray) -> dict:
    """:func:`~leopod.simulate.ambiguity_truth.wrong_fixes` of all DDs (key ``"all"``) and of
    each system (``table.system``)."""
    counts = {"all": wrong_fixes(table, true_wl, true_nl)}
    for x in np.unique(table.system.values):
        sel = np.flatnonzero(table.system.values == x)
        counts[str(x)] = wrong_fixes(table.isel(dd=sel), true_wl[sel], true_nl[sel])
    return counts
