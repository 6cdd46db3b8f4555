"""Statistics of orbit differences in radial, along-track, cross-track and 3D, and flat tables.

Statistics convention: for R, T and N the mean, the (population) STD and the RMS of the
component; for "3D" those of the distance ``|d|``, so ``RMS² = mean² + STD²`` holds for every
component and the 3D RMS equals ``sqrt(RMS_R² + RMS_T² + RMS_N²)``.

Input: the ``diff_rtn_m`` of :func:`leopod.validation.compare.compare_orbits` (Wang et al.
2024, Table 4; Jiang et al. 2023, Fig. 18) or the overlap summaries of
:mod:`leopod.validation.overlap`.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import xarray as xr

__all__ = ["COMPONENTS", "component_statistics", "orbit_statistics", "statistics_table"]

#: Components of the statistics: radial, along-track, cross-track and the 3D distance.
COMPONENTS = ("R", "T", "N", "3D")


def component_statistics(diff_rtn_m) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """Mean, STD, RMS of R, T, N and 3D distance over the finite rows of RTN differences.

    Parameters
    ----------
    diff_rtn_m : array_like, shape (n, 3)
        Differences [m]; rows with any non-finite value are skipped.

    Returns
    -------
    mean, std, rms : ndarray, shape (4,)
        Per :data:`COMPONENTS` [m] (population STD, ``rms² = mean² + std²``); NaN if no row.
    n : int
        Number of rows used.
    """
    d = np.asarray(diff_rtn_m, dtype=float).reshape(-1, 3)
    d = d[np.isfinite(d).all(axis=1)]
    if d.shape[0] == 0:
        nan = np.full(len(COMPONENTS), np.nan)
        return nan, nan.copy(), nan.copy(), 0
    x = np.column_stack([d, np.linalg.norm(d, axis=1)])
    return x.mean(axis=0), x.std(axis=0), np.sqrt(np.mean(x * x, axis=0)), int(d.shape[0])


def _stats_variables(rows: list[tuple], dim: str) -> dict:
    mean, std, rms, n = (np.array(v) for v in zip(*rows, strict=True))
    what = {"mean_m": ("mean", mean), "std_m": ("standard deviation", std),
            "rms_m": ("root mean square", rms)}
    out = {name: ((dim, "component"), values,
                  {"units": "m", "long_name": f"{label} of the differences (3D: of the distance)"})
           for name, (label, values) in what.items()}
    out["n_epochs"] = (dim, n.astype(np.int64), {"units": "1", "long_name": "epochs used"})
    return out


def orbit_statistics(diff: xr.Dataset, *, daily: bool = True) -> xr.Dataset:
    """Mean, STD and RMS of R, T, N and 3D per GPS day and in total.

    Parameters
    ----------
    diff : xarray.Dataset
        ``diff_rtn_m`` (time, rtn) [m], e.g. from :func:`compare_orbits` (several arcs may be
        concatenated along ``time``).
    daily : bool
        Include one row per GPS day (00:00–24:00 of the time labels) before ``"total"``.

    Returns
    -------
    xarray.Dataset
        Dims ``period`` (str: ``"YYYY-MM-DD"`` days and ``"total"``) and ``component``
        (R, T, N, 3D): ``mean_m``, ``std_m``, ``rms_m`` [m], ``n_epochs`` (period).
    """
    d = diff.diff_rtn_m.transpose("time", "rtn").values
    days = diff.time.values.astype("datetime64[D]")
    labels, rows = [], []
    if daily:
        for day in np.unique(days):
            labels.append(str(day))
            rows.append(component_statistics(d[days == day]))
    labels.append("total")
    rows.append(component_statistics(d))
    return xr.Dataset(_stats_variables(rows, "period"),
                      coords={"period": labels, "component": list(COMPONENTS)})


def statistics_table(stats: xr.Dataset) -> pd.DataFrame:
    """Flat table (one row per period or pair) of :func:`orbit_statistics` or overlap summaries.

    Columns ``mean_<c>_m``, ``std_<c>_m``, ``rms_<c>_m`` for c in R, T, N, 3D and ``n_epochs``.
    A summary with ``campaign_rms_mean_m``/``campaign_rms_std_m``
    (:mod:`leopod.validation.overlap`) gets two
    more rows, ``"campaign mean"`` and ``"campaign std"``, holding those values in the
    ``rms_*`` columns (other columns NaN).
    """
    dim = stats.mean_m.dims[0]
    columns = {}
    for comp in stats.component.values:
        for name in ("mean", "std", "rms"):
            columns[f"{name}_{comp}_m"] = stats[f"{name}_m"].sel(component=comp).values
    columns["n_epochs"] = pd.array(stats.n_epochs.values, dtype="Int64")
    table = pd.DataFrame(columns, index=pd.Index([str(v) for v in stats[dim].values], name=dim))
    if "campaign_rms_mean_m" in stats:
        for label, name in (("campaign mean", "campaign_rms_mean_m"),
                            ("campaign std", "campaign_rms_std_m")):
            row = {f"rms_{c}_m": float(stats[name].sel(component=c))
                   for c in stats.component.values}
            table.loc[label] = pd.Series(row)
    return table
