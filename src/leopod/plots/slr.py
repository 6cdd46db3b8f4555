"""Figures of the SLR validation (step ``slr``).

Each function takes the residual Dataset(s) of :func:`leopod.validation.slr.slr_residuals`
and writes one PNG:

- residuals versus time, coloured by station, rejected points as grey crosses;
- mean ± STD of the residuals per station, one bar per solution (Peng et al. 2021, Table IV);
- residuals versus elevation with their STD and mean per 5° elevation bin, one colour per
  solution (Peng et al. 2021, Figs. 17–18).

The station and elevation figures compare solutions (e.g. float and fixed orbits): pass a
mapping ``{label: residuals}``; a single Dataset is one unlabelled solution. Residuals are
shown in centimetres, as in the source papers. The PNGs carry no software or time stamp, so repeated
runs give identical bytes.
"""

from __future__ import annotations

from collections.abc import Mapping

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from leopod.plots import by_solution, save_figure
from leopod.plots.pod import _heading

__all__ = ["plot_slr_elevation", "plot_slr_residuals_time", "plot_slr_stations"]

_M_TO_CM = 100.0
"""Metres to centimetres (display unit of SLR residuals)."""
_LIMIT_PERCENTILE = 99.0
"""Percentile of |residual| of the used points that sets the symmetric y-limit."""
_MIN_LIMIT_CM = 2.0
"""Smallest y-limit [cm]."""


def _used(res: xr.Dataset) -> np.ndarray:
    return res["flag"].values == 0


def _limit_cm(values_cm: np.ndarray) -> float:
    """Symmetric y-limit [cm] from the used residuals (robust to a few large ones)."""
    v = np.abs(values_cm[np.isfinite(values_cm)])
    if v.size == 0:
        return _MIN_LIMIT_CM
    return max(1.2 * float(np.percentile(v, _LIMIT_PERCENTILE)), _MIN_LIMIT_CM)


def _summary(res_cm: np.ndarray) -> str:
    if res_cm.size == 0:
        return "no residual used"
    std = res_cm.std(ddof=1) if res_cm.size > 1 else float("nan")
    return (f"{res_cm.size} NP: mean {res_cm.mean():.2f} cm, STD {std:.2f} cm, "
            f"RMS {np.sqrt(np.mean(res_cm**2)):.2f} cm")


def plot_slr_residuals_time(res: xr.Dataset, path, title: str = "") -> None:
    """SLR residuals [cm] versus time (UTC), one colour per station.

    Rejected points with a finite residual are grey crosses, clipped to the axis limits.

    Parameters
    ----------
    res : xarray.Dataset
        From :func:`leopod.validation.slr.slr_residuals`.
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title (e.g. satellite, date and solution).
    """
    time = res["time"].values.astype("datetime64[ns]")
    day = time.min().astype("datetime64[D]") if time.size else np.datetime64("2000-01-01")
    hours = (time - day) / np.timedelta64(1, "h")
    r_cm = res["residual_m"].values * _M_TO_CM
    used = _used(res)
    lim = _limit_cm(r_cm[used])
    fig, ax = plt.subplots(figsize=(10, 4.5))
    stations = sorted(set(res["station"].values[used].tolist()))
    colours = plt.get_cmap("tab20")
    for k, site in enumerate(stations):
        sel = used & (res["station"].values == site)
        ax.plot(hours[sel], r_cm[sel], "o", ms=3, color=colours(k % 20),
                label=f"{site} ({np.count_nonzero(sel)})")
    rejected = ~used & np.isfinite(r_cm)
    ax.plot(hours[rejected], np.clip(r_cm[rejected], -lim, lim), "x", ms=4, color="0.5",
            label=f"rejected ({np.count_nonzero(rejected)})")
    ax.axhline(0.0, color="k", lw=0.6)
    ax.set_ylim(-lim, lim)
    ax.set_xlabel(f"hours since {day} 00:00 (UTC)")
    ax.set_ylabel("SLR residual [cm]")
    ax.set_title(_summary(r_cm[used]), fontsize=9, loc="left")
    ax.grid(alpha=0.3)
    if stations or rejected.any():
        ax.legend(fontsize=7, ncol=2, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.suptitle(_heading(title, "SLR residuals"))
    fig.tight_layout()
    save_figure(fig, path)


def plot_slr_stations(statistics: xr.Dataset | Mapping[str, xr.Dataset], path,
                      title: str = "") -> None:
    """Mean ± STD [cm] of the used residuals per station and solution (Peng et al. 2021, Table IV).

    Bars are the means, error bars the standard deviations; the number of normal points
    of the first solution is written above each station; the last group is all stations.

    Parameters
    ----------
    statistics : xarray.Dataset or mapping of str to xarray.Dataset
        :func:`leopod.validation.slr_statistics.station_statistics` of one solution, or of
        several keyed by a label (e.g. "float", "fixed").
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title.
    """
    stats = by_solution(statistics)
    sites = sorted({s for st in stats.values() for s in st["station"].values.tolist()
                    if s != "total"}) + ["total"]
    x = np.arange(len(sites))
    width = 0.8 / len(stats)
    fig, ax = plt.subplots(figsize=(max(6.0, 0.6 * len(sites) * max(1, len(stats) / 2)), 4.5))
    for k, (label, st) in enumerate(stats.items()):
        st = st.reindex(station=sites)
        mean = st["mean_m"].values * _M_TO_CM
        std = st["std_m"].values * _M_TO_CM
        ax.bar(x + (k - (len(stats) - 1) / 2) * width, mean, width, yerr=std, capsize=2,
               label=label or None, alpha=0.85)
    first = next(iter(stats.values())).reindex(station=sites)
    for xi, n in zip(x, first["n_np"].fillna(0).values.astype(int)):
        ax.annotate(str(n), (xi, 1.0), xycoords=("data", "axes fraction"), ha="center",
                    va="bottom", fontsize=7)
    ax.axhline(0.0, color="k", lw=0.6)
    ax.set_xticks(x, sites, rotation=45, fontsize=8)
    ax.set_ylabel("mean ± STD of the residuals [cm]")
    ax.grid(axis="y", alpha=0.3)
    if len(stats) > 1:
        ax.legend(fontsize=8)
    fig.suptitle(_heading(title, "SLR residuals per station (numbers: normal points)"))
    fig.tight_layout()
    save_figure(fig, path)


def plot_slr_elevation(results: xr.Dataset | Mapping[str, xr.Dataset],
                       statistics: xr.Dataset | Mapping[str, xr.Dataset], path,
                       title: str = "") -> None:
    """Residuals [cm] versus elevation, with STD and mean per elevation bin (Peng et al. 2021,
    Figs. 17–18).

    Upper panel: used residuals of each solution; lower panel: their STD (solid) and mean
    (dashed) per elevation bin.

    Parameters
    ----------
    results : xarray.Dataset or mapping of str to xarray.Dataset
        Residuals of one solution, or of several keyed by a label.
    statistics : xarray.Dataset or mapping of str to xarray.Dataset
        Their :func:`leopod.validation.slr_statistics.elevation_statistics` (same labels).
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title.
    """
    sols = by_solution(results)
    elevation = by_solution(statistics)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True,
                                      gridspec_kw={"height_ratios": [3, 2]})
    colours = plt.get_cmap("tab10")
    all_used = []
    for k, (label, res) in enumerate(sols.items()):
        used = _used(res)
        r_cm = res["residual_m"].values[used] * _M_TO_CM
        all_used.append(r_cm)
        top.plot(res["elevation_deg"].values[used], r_cm, ".", ms=3, alpha=0.5,
                 color=colours(k % 10), label=f"{label} {_summary(r_cm)}".strip())
        el = elevation[label]
        centres = el["elevation_deg"].values
        bottom.plot(centres, el["std_m"].values * _M_TO_CM, "o-", ms=3, color=colours(k % 10),
                    label=f"{label} STD".strip())
        bottom.plot(centres, el["mean_m"].values * _M_TO_CM, "s--", ms=2, lw=0.8,
                    color=colours(k % 10), label=f"{label} mean".strip())
    lim = _limit_cm(np.concatenate(all_used))
    top.set_ylim(-lim, lim)
    top.axhline(0.0, color="k", lw=0.6)
    top.set_ylabel("SLR residual [cm]")
    top.legend(fontsize=7, loc="upper right")
    top.grid(alpha=0.3)
    bottom.axhline(0.0, color="k", lw=0.6)
    widths = {float(w) for st in elevation.values()
              for w in st["upper_deg"].values - st["lower_deg"].values}
    bottom.set_ylabel(f"per {widths.pop():g}° bin [cm]" if len(widths) == 1 else "per bin [cm]")
    bottom.set_xlabel("elevation [deg]")
    bottom.set_xlim(0.0, 90.0)
    bottom.legend(fontsize=7, ncol=2, loc="upper right")
    bottom.grid(alpha=0.3)
    fig.suptitle(_heading(title, "SLR residuals versus elevation"))
    fig.tight_layout()
    save_figure(fig, path)
