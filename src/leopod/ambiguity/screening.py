"""Fixes that make the fit worse: passes whose phase residuals grow in the fixed solution.

A wrong integer forces the ionosphere-free ambiguity of its passes off the value the data
want by a multiple of the narrow-lane wavelength (~10.7 cm for GPS): the phase residuals of
those passes grow far above the ~mm noise, while a right fix leaves them at the float level
(issue 7: "iterate or reject fixes that raise the residuals"; Peng et al. 2021 warns that wrong
fixes degrade the orbit). The fixed POD compares every constrained pass's phase residual RMS with
its float value, drops the constraints of the passes that degraded and solves again.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

__all__ = ["degraded_passes", "drop_constraints"]


def _pass_rms(residuals: xr.Dataset) -> dict[int, tuple[float, int]]:
    res = residuals.phase_residual_m.values
    pid = residuals.pass_index.values
    ok = np.isfinite(res) & (pid >= 0)
    ids, inverse, counts = np.unique(pid[ok], return_inverse=True, return_counts=True)
    sums = np.bincount(inverse, weights=res[ok] ** 2)
    return {int(i): (float(np.sqrt(s / n)), int(n)) for i, s, n in zip(ids, sums, counts,
                                                                         strict=True)}


def degraded_passes(float_residuals: xr.Dataset, fixed_residuals: xr.Dataset, *,
                    ratio: float = 1.5, floor_m: float = 0.002,
                    min_obs: int = 10) -> np.ndarray:
    """Passes whose phase residual RMS grew by more than ``ratio`` (and ``floor_m``).

    Parameters
    ----------
    float_residuals, fixed_residuals : xarray.Dataset
        Residual datasets (``phase_residual_m``, ``pass_index`` on (time, sv)) of the float
        and the fixed solution of the same arc.
    ratio : float
        RMS growth factor above which a pass counts as degraded.
    floor_m : float
        Minimum absolute growth of the RMS [m] (ignores sub-mm changes of quiet passes).
    min_obs : int
        Passes with fewer phase residuals are not judged.

    Returns
    -------
    ndarray of int
        Pass indices (sorted).
    """
    before, after = _pass_rms(float_residuals), _pass_rms(fixed_residuals)
    bad = [p for p, (rms, n) in after.items()
           if p in before and n >= min_obs
           and rms > ratio * before[p][0] and rms - before[p][0] > floor_m]
    return np.array(sorted(bad), dtype=int)


def drop_constraints(constraints, passes):
    """Constraints ``(pass_i, pass_j, value_m, sigma_m)`` without those touching ``passes``."""
    pass_i, pass_j, value, sigma = (np.asarray(c) for c in constraints)
    keep = ~(np.isin(pass_i, passes) | np.isin(pass_j, passes))
    return pass_i[keep], pass_j[keep], value[keep], sigma[keep]
