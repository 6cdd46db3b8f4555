"""Figures of the kinematic orbit and the kinematic baseline: kinematic minus reduced-dynamic
positions (or baselines) in R/T/N."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from leopod.plots import dots, save_figure
from leopod.plots.pod import _heading, _hours_of_day

__all__ = ["plot_baseline_differences", "plot_kinematic_rtn"]

_M_TO_CM = 100.0


def plot_kinematic_rtn(ds: xr.Dataset, path, title: str = "",
                       reference: str = "reduced-dynamic float orbit") -> None:
    """Kinematic minus reference orbit in R/T/N [cm] over the hours of the arc's first day,
    and the PDOP and satellite count of the epochs (unsolved epochs marked).

    Parameters
    ----------
    ds : xarray.Dataset
        :func:`leopod.estimation.kinematic.kinematic_dataset`: ``diff_rtn_m`` (time, rtn),
        ``pdop``, ``n_satellites``, ``solved`` (time).
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title (satellite and day).
    reference : str
        What the reference orbit is, for the title.
    """
    t = ds.time.values
    hours = (t - t[0].astype("datetime64[D]")) / np.timedelta64(1, "h")
    fig, axes = plt.subplots(4, 1, figsize=(10, 8), sharex=True,
                             gridspec_kw={"height_ratios": [1, 1, 1, 0.8]})
    for ax, comp in zip(axes[:3], ("R", "T", "N"), strict=True):
        d = ds.diff_rtn_m.sel(rtn=comp).values * _M_TO_CM
        ok = np.isfinite(d)
        rms = float(np.sqrt(np.mean(d[ok] ** 2))) if ok.any() else float("nan")
        dots(ax, hours[ok], d[ok], size_pt2=2.0, label=f"{comp}: RMS {rms:.2f} cm")
        ax.set_ylabel(f"{comp} [cm]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
    ax = axes[3]
    ax.plot(hours, ds.pdop.values, lw=0.8, label="PDOP")
    ax.plot(hours, ds.n_satellites.values, lw=0.8, label="satellites")
    bad = ds.solved.values == 0
    ax.plot(hours[bad], np.zeros(bad.sum()), "rx", ms=4,
            label=f"not solved ({int(bad.sum())} of {bad.size})")
    ax.set_xlabel(f"hours of {str(t[0].astype('datetime64[D]'))} (GPS time)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper right", ncols=3)
    fig.suptitle(f"{title}: kinematic minus {reference}, R/T/N" if title else
                 f"kinematic minus {reference}, R/T/N")
    fig.tight_layout()
    save_figure(fig, path)


def plot_baseline_differences(ds: xr.Dataset, path, title: str = "") -> None:
    """Kinematic minus reduced-dynamic baseline in the leader's R/T/N [mm] per system, DD-fixed
    (Zhang et al. 2024, Fig. 10 style), with the RMS in the legend.

    Parameters
    ----------
    ds : xarray.Dataset
        Output of the kinematic_baseline rule: ``minus_dynamic_rtn_m`` (system, ambiguities,
        time, rtn).
    path : str or path-like
        PNG to write.
    title : str
        Pair and day.
    """
    hours, xlabel = _hours_of_day(ds.time.values)
    fig, axes = plt.subplots(3, 1, figsize=(10, 7), sharex=True)
    for ax, comp in zip(axes, ("R", "T", "N"), strict=True):
        for system in ds.system.values:
            d = ds.minus_dynamic_rtn_m.sel(system=system, ambiguities="fixed",
                                           rtn=comp).values * 1e3
            if "in_day" in ds:
                d = np.where(ds.in_day.values == 1, d, np.nan)
            ok = np.isfinite(d)
            rms = float(np.sqrt(np.mean(d[ok] ** 2))) if ok.any() else float("nan")
            dots(ax, hours[ok], d[ok], size_pt2=2.0, label=f"{system}: RMS {rms:.1f} mm")
        ax.set_ylabel(f"{comp} [mm]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper right", ncols=len(ds.system))
    axes[-1].set_xlabel(xlabel)
    fig.suptitle(_heading(title, "DD-fixed kinematic minus reduced-dynamic baseline"))
    fig.tight_layout()
    save_figure(fig, path)
