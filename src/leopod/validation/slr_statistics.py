"""Statistics of SLR residuals: per station, per elevation bin, and in the RTN frame.

Input: the residual Dataset of :func:`leopod.validation.slr.slr_residuals` (``flag`` 0 = used).
Per station #NP, mean, STD and RMS, and over all stations (Peng et al. 2021, Table IV);
mean, STD and RMS per elevation bin of 5° (Peng et al. 2021, Figs. 17–18); the projection of
the residuals on the radial, along-track and cross-track directions (Wang et al. 2024, sec.
3.4.3, Table 5) with a least-squares estimate of a constant RTN orbit offset
(:func:`rtn_projection`).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import xarray as xr

from leopod.validation.slr import _RTN, _std

__all__ = ["elevation_statistics", "rtn_projection", "station_statistics"]


def _moments(values: np.ndarray) -> tuple[int, float, float, float]:
    """Count, mean, STD (n − 1) and RMS; NaN statistics for no values (no warning)."""
    v = np.asarray(values, dtype=float)
    if v.size == 0:
        return 0, float("nan"), float("nan"), float("nan")
    return v.size, float(v.mean()), _std(v), float(np.sqrt(np.mean(v * v)))


def _used(res: xr.Dataset) -> xr.Dataset:
    return res.isel(point=np.flatnonzero(res["flag"].values == 0))


def _stats_dataset(dim: str, labels, moments: list, coord_attrs: Mapping | None = None,
                   extra: Mapping | None = None) -> xr.Dataset:
    n, mean, std, rms = (np.array(col) for col in zip(*moments)) if moments else \
        (np.zeros(0, int), np.zeros(0), np.zeros(0), np.zeros(0))
    ds = xr.Dataset(
        {"n_np": (dim, n.astype(np.int64), {"units": "1", "long_name": "number of normal points"}),
         "mean_m": (dim, mean, {"units": "m", "long_name": "mean residual"}),
         "std_m": (dim, std, {"units": "m", "long_name": "standard deviation (n - 1) of the "
                              "residuals"}),
         "rms_m": (dim, rms, {"units": "m", "long_name": "root mean square residual"}),
         **dict(extra or {})},
        coords={dim: (dim, labels, dict(coord_attrs or {}))},
    )
    return ds


def station_statistics(residuals: xr.Dataset) -> xr.Dataset:
    """Statistics of the used residuals per station and over all (Peng et al. 2021, Table IV).

    Parameters
    ----------
    residuals : xarray.Dataset
        From :func:`slr_residuals`.

    Returns
    -------
    xarray.Dataset
        Dimension ``station`` (CDP pad ids in ascending order, then ``"total"``):
        ``n_np``, ``mean_m``, ``std_m`` (sample STD about the mean), ``rms_m``.
    """
    used = _used(residuals)
    sites = used["station"].values.astype(str)
    res = used["residual_m"].values
    labels = sorted(set(sites.tolist()))
    moments = [_moments(res[sites == s]) for s in labels] + [_moments(res)]
    return _stats_dataset("station", np.array(labels + ["total"], dtype=str), moments,
                          {"long_name": "CDP pad id, 'total' for all stations"})


def elevation_statistics(residuals: xr.Dataset, bin_deg: float = 5.0) -> xr.Dataset:
    """Statistics of the used residuals per elevation bin (Peng et al. 2021, Figs. 17–18).

    Parameters
    ----------
    residuals : xarray.Dataset
        From :func:`slr_residuals`.
    bin_deg : float
        Bin width [deg]; bins ``[k·w, (k + 1)·w)`` from 0° to 90°.

    Returns
    -------
    xarray.Dataset
        Dimension ``elevation_deg`` (bin centres [deg]): ``n_np``, ``mean_m``, ``std_m``,
        ``rms_m`` (NaN in empty bins), ``lower_deg``, ``upper_deg`` (bin edges).
    """
    used = _used(residuals)
    el = used["elevation_deg"].values
    res = used["residual_m"].values
    edges = np.arange(0.0, 90.0 + 0.5 * bin_deg, bin_deg)
    edges[-1] = max(edges[-1], 90.0 + 1e-9)
    k = np.digitize(el, edges) - 1
    moments = [_moments(res[k == i]) for i in range(edges.size - 1)]
    return _stats_dataset(
        "elevation_deg", 0.5 * (edges[:-1] + edges[1:]), moments,
        {"units": "degree", "long_name": "centre of the elevation bin"},
        {"lower_deg": ("elevation_deg", edges[:-1], {"units": "degree",
                                                     "long_name": "lower edge of the bin"}),
         "upper_deg": ("elevation_deg", edges[1:], {"units": "degree",
                                                    "long_name": "upper edge of the bin"})})


def rtn_projection(residuals: xr.Dataset) -> xr.Dataset:
    """Radial, along-track and cross-track view of the used residuals.

    Two views of the same residuals ``ρ`` with the unit lines of sight ``e`` (station →
    satellite) in the orbit's RTN axes:

    * Wang et al. 2024 (sec. 3.4.3, eq. 16, Table 5): the components ``ρ e_R``, ``ρ e_T``,
      ``ρ e_N`` of every residual and their RMS; since |e| = 1 the three RMS values add in
      quadrature to the RMS of the residuals;
    * a least-squares estimate of a constant orbit offset δ (orbit minus truth, RTN) from
      ``ρ = −e · δ + v``: ``δ = −(AᵀA)⁻¹ Aᵀ ρ`` with rows ``A = e``, formal covariance
      ``σ0² (AᵀA)⁻¹``, ``σ0² = vᵀv / (n − 3)``. A constant range bias of all stations is
      absorbed mostly by the radial component.

    Parameters
    ----------
    residuals : xarray.Dataset
        From :func:`slr_residuals`.

    Returns
    -------
    xarray.Dataset
        Dimension ``rtn``: ``rms_component_m``, ``offset_m``, ``sigma_offset_m``,
        ``covariance_m2`` (rtn, rtn_b); scalars ``rms_range_m``, ``sigma0_m``, ``n_np``.
        Offsets are NaN with fewer than four points or a singular geometry.
    """
    used = _used(residuals)
    a = used["los_rtn"].transpose("point", "rtn").values
    rho = used["residual_m"].values
    n = rho.size
    rms_comp = np.sqrt(np.mean((rho[:, None] * a) ** 2, axis=0)) if n else np.full(3, np.nan)
    offset, cov, sigma0 = np.full(3, np.nan), np.full((3, 3), np.nan), float("nan")
    normal = a.T @ a
    if n > 3 and np.linalg.cond(normal) < 1e12:
        inv = np.linalg.inv(normal)
        offset = -inv @ (a.T @ rho)
        v = rho + a @ offset
        sigma0 = float(np.sqrt(v @ v / (n - 3)))
        cov = sigma0**2 * inv
    m = {"units": "m"}
    return xr.Dataset(
        {"rms_component_m": ("rtn", rms_comp, {**m, "long_name": "RMS of the residuals "
                                               "times the line-of-sight component "
                                               "(Wang et al. 2024)"}),
         "offset_m": ("rtn", offset, {**m, "long_name": "least-squares constant orbit offset "
                                      "(orbit minus truth)"}),
         "sigma_offset_m": ("rtn", np.sqrt(np.diagonal(cov)), {**m, "long_name":
                                                               "formal sigma of offset_m"}),
         "covariance_m2": (("rtn", "rtn_b"), cov, {"units": "m2",
                                                   "long_name": "covariance of offset_m"}),
         "rms_range_m": ((), float(np.sqrt(np.mean(rho**2))) if n else float("nan"),
                         {**m, "long_name": "RMS of the residuals"}),
         "sigma0_m": ((), sigma0, {**m, "long_name": "a-posteriori sigma of unit weight"}),
         "n_np": ((), n, {"units": "1", "long_name": "number of normal points"})},
        coords={"rtn": _RTN, "rtn_b": _RTN},
    )
