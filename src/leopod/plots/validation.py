"""Figures of the orbit validation steps (``overlap``, ``reference_orbit``).

Each function writes one PNG from the Datasets of :mod:`leopod.validation.overlap` and
:mod:`leopod.validation.compare`; a Mapping ``{"float": ds, "fixed": ds}`` draws several
solutions side by side (Jiang et al. 2023 compares ambiguity-float and -fixed orbits in every
figure):

- :func:`plot_overlaps`: per arc pair the RMS of the overlap differences in R, T, N and 3D as
  grouped bars, with the campaign mean ± STD of the per-pair RMS in the legend (Jiang et al. 2023
  Fig. 13, which shows the 3D panel);
- :func:`plot_reference_differences`: time series of the differences to an external orbit in
  R, T, N with mean and RMS in the legend and GPS day boundaries marked (Jiang et al. 2023,
  Fig. 17);
- :func:`plot_daily_statistics`: daily RMS and mean per component as bars, with the totals in
  the legend (Jiang et al. 2023, Fig. 18; Wang et al. 2024, Fig. 9).

Values are shown in millimetres. The PNGs carry no software or time stamp, so repeated runs
give identical bytes.
"""

from __future__ import annotations

from collections.abc import Mapping

import matplotlib

matplotlib.use("Agg")
import matplotlib.dates as mdates
import matplotlib.pyplot as plt
import numpy as np
import xarray as xr
from matplotlib.ticker import FuncFormatter

from leopod.plots import by_solution, save_figure
from leopod.plots.pod import _heading, _hours_of_day

__all__ = ["plot_daily_statistics", "plot_formation_summary", "plot_overlaps",
           "plot_range_check", "plot_reference_differences", "plot_strategy"]

_M_TO_MM = 1e3
"""Metres to millimetres (display unit of all validation figures)."""
_COMPONENTS = ("R", "T", "N", "3D")
_NAMES = {"R": "radial", "T": "along-track", "N": "cross-track", "3D": "3D"}
_BAR_GROUP_WIDTH = 0.8
"""Width of a group of bars (one bar per solution) in units of the category spacing."""
_PANEL_HEIGHT_IN = 1.9
"""Height of one component panel [inch]."""


def _label(name: str, text: str) -> str:
    return f"{name}: {text}" if name else text


def _bar_offsets(n: int) -> np.ndarray:
    """Centre offsets of ``n`` bars within a group of width :data:`_BAR_GROUP_WIDTH`."""
    width = _BAR_GROUP_WIDTH / n
    return (np.arange(n) - (n - 1) / 2.0) * width


def _legend_above(ax, n_entries: int) -> None:
    """Legend in one row above the panel, so it never hides bars or curves."""
    ax.legend(fontsize=8, loc="lower left", bbox_to_anchor=(0.0, 1.0), ncols=n_entries,
              frameon=False, borderaxespad=0.2)


def _category_axis(ax, labels: list[str]) -> None:
    ax.set_xticks(np.arange(len(labels)))
    ax.set_xticklabels(labels, rotation=45 if len(labels) > 6 else 0, ha="right"
                       if len(labels) > 6 else "center", fontsize=8)


def plot_overlaps(summaries: xr.Dataset | Mapping[str, xr.Dataset], path,
                  title: str = "") -> None:
    """RMS of the orbit overlaps per arc pair in R, T, N and 3D (Jiang et al. 2023, Fig. 13).

    Parameters
    ----------
    summaries : xarray.Dataset or Mapping[str, xarray.Dataset]
        :func:`leopod.validation.overlap.overlap_summary` result(s): ``rms_m`` (pair,
        component), ``campaign_rms_mean_m``, ``campaign_rms_std_m`` (component) [m]. Several
        solutions (e.g. float, fixed) are drawn on the union of their pair labels.
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title.
    """
    sols = by_solution(summaries)
    pairs = sorted({str(p) for ds in sols.values() for p in ds.pair.values})
    offsets = _bar_offsets(len(sols))
    width = _BAR_GROUP_WIDTH / len(sols)
    fig, axes = plt.subplots(len(_COMPONENTS), 1, sharex=True,
                             figsize=(max(6.0, 0.5 * len(pairs) + 3.0),
                                      _PANEL_HEIGHT_IN * len(_COMPONENTS) + 1.0))
    for ax, comp in zip(axes, _COMPONENTS, strict=True):
        for off, (name, ds) in zip(offsets, sols.items(), strict=True):
            rms = ds.rms_m.sel(component=comp).reindex(pair=pairs).values * _M_TO_MM
            mean = float(ds.campaign_rms_mean_m.sel(component=comp)) * _M_TO_MM
            std = float(ds.campaign_rms_std_m.sel(component=comp)) * _M_TO_MM
            ax.bar(np.arange(len(pairs)) + off, np.nan_to_num(rms), width,
                   label=_label(name, f"{mean:.1f} ± {std:.1f} mm"))
        ax.set_ylabel(f"{_NAMES[comp]}\n{comp} RMS [mm]")
        _legend_above(ax, len(sols))
        ax.grid(alpha=0.3, axis="y")
    _category_axis(axes[-1], pairs)
    axes[-1].set_xlabel("arc pair (GPS date of the overlap centre)")
    fig.suptitle(_heading(title, "orbit overlaps of consecutive arcs: RMS per pair "
                          "(legend: campaign mean ± STD)"), fontsize=10)
    fig.tight_layout()
    save_figure(fig, path)


def _day_starts(times: np.ndarray) -> np.ndarray:
    """GPS midnights strictly inside ``(times[0], times[-1])``."""
    if times.size == 0:
        return times
    first = times.min().astype("datetime64[D]") + np.timedelta64(1, "D")
    last = times.max().astype("datetime64[D]")
    return np.arange(first, last + np.timedelta64(1, "D"), np.timedelta64(1, "D")) \
        .astype("datetime64[ns]")


def plot_reference_differences(diffs: xr.Dataset | Mapping[str, xr.Dataset], path,
                               title: str = "") -> None:
    """Orbit minus reference orbit in R, T, N versus time (Jiang et al. 2023, Fig. 17).

    Parameters
    ----------
    diffs : xarray.Dataset or Mapping[str, xarray.Dataset]
        :func:`leopod.validation.compare.compare_orbits` result(s) (``diff_rtn_m`` (time, rtn)
        [m]), possibly several days concatenated along ``time``.
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title.
    """
    sols = by_solution(diffs)
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(10, 7))
    all_times = np.concatenate([ds.time.values for ds in sols.values()])
    for ax, comp in zip(axes, _COMPONENTS[:3], strict=True):
        for name, ds in sols.items():
            d = ds.diff_rtn_m.sel(rtn=comp).values * _M_TO_MM
            ok = np.isfinite(d)
            text = (f"mean {np.mean(d[ok]):.1f}, RMS {np.sqrt(np.mean(d[ok] ** 2)):.1f} mm"
                    if ok.any() else "no data")
            ax.plot(ds.time.values, d, lw=0.6, label=_label(name, text))
        for day in _day_starts(all_times):
            ax.axvline(day, color="grey", lw=0.6, ls=":")
        ax.set_ylabel(f"{_NAMES[comp]}\n{comp} [mm]")
        _legend_above(ax, len(sols))
        ax.grid(alpha=0.3)
    axes[-1].xaxis.set_major_formatter(mdates.DateFormatter("%m-%d %H:%M"))
    axes[-1].set_xlabel("GPS time")
    fig.suptitle(_heading(title, "orbit minus reference orbit (inertial R/T/N)"), fontsize=10)
    fig.autofmt_xdate()
    fig.tight_layout()
    save_figure(fig, path)


def plot_daily_statistics(stats: xr.Dataset | Mapping[str, xr.Dataset], path,
                          title: str = "") -> None:
    """Daily RMS (left) and mean (right) of the reference-orbit differences per component.

    Parameters
    ----------
    stats : xarray.Dataset or Mapping[str, xarray.Dataset]
        :func:`leopod.validation.orbit_statistics.orbit_statistics` result(s): ``rms_m``, ``mean_m``
        (period, component) [m] with day periods and a ``"total"`` row (shown in the legend).
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title.
    """
    sols = by_solution(stats)
    days = sorted({str(p) for ds in sols.values() for p in ds.period.values if p != "total"})
    offsets = _bar_offsets(len(sols))
    width = _BAR_GROUP_WIDTH / len(sols)
    fig, axes = plt.subplots(len(_COMPONENTS), 2, sharex=True,
                             figsize=(max(9.0, 0.8 * len(days) + 4.0),
                                      _PANEL_HEIGHT_IN * len(_COMPONENTS) + 1.0))
    for row, comp in enumerate(_COMPONENTS):
        for col, what in enumerate(("rms", "mean")):
            ax = axes[row, col]
            for off, (name, ds) in zip(offsets, sols.items(), strict=True):
                var = ds[f"{what}_m"].sel(component=comp)
                daily = var.reindex(period=days).values * _M_TO_MM
                total = (float(var.sel(period="total")) * _M_TO_MM
                         if "total" in ds.period.values else np.nan)
                ax.bar(np.arange(len(days)) + off, np.nan_to_num(daily), width,
                       label=_label(name, f"total {total:.1f} mm"))
            ax.axhline(0.0, color="black", lw=0.5)
            ax.set_ylabel(f"{comp} {'RMS' if what == 'rms' else 'mean'} [mm]")
            _legend_above(ax, len(sols))
            ax.grid(alpha=0.3, axis="y")
    for ax in axes[-1]:
        _category_axis(ax, days)
        ax.set_xlabel("GPS day")
    fig.suptitle(_heading(title, "daily statistics of orbit minus reference orbit "
                          "(3D: of the distance)"), fontsize=10)
    fig.tight_layout()
    save_figure(fig, path)


def plot_range_check(ds: xr.Dataset, path, title: str = "") -> None:
    """Baseline length minus inter-satellite range [mm] over the day, one panel per solution
    (mean and STD in the legend).

    Parameters
    ----------
    ds : xarray.Dataset
        Output of the range_check rule: ``residual_m`` (solution, time), ``mean_m``,
        ``std_m`` (solution).
    path : str or path-like
        PNG to write.
    title : str
        Pair and day.
    """
    hours, xlabel = _hours_of_day(ds.time.values)
    n = ds.sizes["solution"]
    fig, axes = plt.subplots(n, 1, figsize=(10, 1.6 * n + 1.2), sharex=True, squeeze=False)
    for ax, label in zip(axes[:, 0], ds.solution.values, strict=True):
        r = ds.residual_m.sel(solution=label).values * 1e3
        ok = np.isfinite(r)
        ax.plot(hours[ok], r[ok], lw=0.6,
                label=f"{label}: mean {1e3 * float(ds.mean_m.sel(solution=label)):+.2f}, "
                      f"STD {1e3 * float(ds.std_m.sel(solution=label)):.2f} mm")
        ax.set_ylabel("mm")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
    axes[-1, 0].set_xlabel(xlabel)
    fig.suptitle(_heading(title, "baseline length minus inter-satellite range"))
    fig.tight_layout()
    save_figure(fig, path)


def plot_formation_summary(table, path, title: str = "") -> None:
    """Baselines of a formation pair per day (3D RMS [mm] against the truth, or against the
    reduced-dynamic baseline for the kinematic ones when there is no truth; the mutual
    differences of the pair's G, C and G+C solutions where the table has them; a log axis when
    they span more than a factor 10) and the DD NL fixing rate.

    Parameters
    ----------
    table : pandas.DataFrame
        :func:`leopod.validation.formation.formation_table` (days, then ``mean``/``std``).
    path : str or path-like
        PNG to write.
    title : str
        Pair.
    """
    days = table.drop(index=["mean", "std"], errors="ignore")
    x = np.arange(len(days))
    fig, (ax, ax_rate) = plt.subplots(2, 1, figsize=(9, 6), sharex=True,
                                      gridspec_kw={"height_ratios": [2.5, 1]})
    truth = any(c.endswith("_minus_truth_3d") for c in days.columns)
    series = [(c, c.replace("_vs_truth_3d", "").replace("_", " ")) for c in days.columns
              if c in ("dynamic_float_vs_truth_3d", "dynamic_fixed_vs_truth_3d")]
    ref = "truth" if truth else "dynamic"
    series += [(c, c.replace(f"_minus_{ref}_3d", "").replace("_", " ")) for c in days.columns
               if c.startswith("kinematic_") and c.endswith(f"_fixed_minus_{ref}_3d")]
    for column, label in series:
        ax.plot(x, days[column].to_numpy(dtype=float), "o-", label=label)
    for column in days.columns:
        if column.startswith("mutual_") and column.endswith("_3d"):
            a, b = column[len("mutual_"):-len("_3d")].split("_minus_")
            ax.plot(x, days[column].to_numpy(dtype=float), "^--", label=f"{a} − {b} (dynamic)")
    # sub-mm dynamic and cm kinematic baselines in one panel
    _log_axis_if_wide(ax, days[[c for c in days.columns if c.endswith("_3d")]])
    ax.set_ylabel(f"3D RMS [mm]: vs {ref}" + (", ▲ between solutions"
                                               if any(c.startswith("mutual_") for c in days)
                                               else ""))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, ncols=2)
    ax_rate.plot(x, days["dd_nl_rate"].to_numpy(dtype=float), "s-", color="C3",
                 label="DD NL fixing rate")
    ax_rate.set_ylabel("%")
    ax_rate.grid(alpha=0.3)
    ax_rate.legend(fontsize=8)
    _category_axis(ax_rate, [str(d) for d in days.index])
    fig.suptitle(_heading(title, "formation baselines per day"))
    fig.tight_layout()
    save_figure(fig, path)


def _log_axis_if_wide(ax, values) -> None:
    """A log y axis with plain tick labels (minor ones at 2, 3, 5 x 10^k) when the positive
    ``values`` span more than a factor 10, else a linear axis from 0."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v) & (v > 0)]
    if v.size and v.max() > 10.0 * v.min():
        ax.set_yscale("log")
        ax.yaxis.set_major_formatter(FuncFormatter(lambda x, _: f"{x:g}"))
        ax.yaxis.set_minor_formatter(FuncFormatter(
            lambda x, _: f"{x:g}" if f"{x:.0e}"[0] in "235" else ""))
    else:
        ax.set_ylim(bottom=0.0)


def plot_strategy(table, path, title: str, figure: str = "reference_3d_rms_cm",
                  ylabel: str | None = None) -> None:
    """One figure of :func:`leopod.workflow.strategy.strategy_table` against the pulse sigma,
    a line per pulse interval (and empirical sigma).

    Parameters
    ----------
    table : pandas.DataFrame
        The strategy table (index ``(sigma_m_s, empirical_sigma_m_s2, figure)``, columns the
        intervals [min]).
    path : str or path-like
        PNG to write.
    title : str
    figure : str
        The row plotted (a campaign-summary figure).
    ylabel : str, optional
        Its description and unit (default: the row name).
    """
    sel = table.xs(figure, level="figure")
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for emp, part in sel.groupby(level="empirical_sigma_m_s2", dropna=False):
        part = part.droplevel("empirical_sigma_m_s2").sort_index()
        suffix = "" if not np.isfinite(emp) else f", empirical {emp:.0e} m/s²"
        for minutes in part.columns:
            ax.plot(part.index, part[minutes], "o-", label=f"{minutes:g} min{suffix}")
    ax.set_xscale("log")
    _log_axis_if_wide(ax, sel)
    ax.set_xlabel("pulse a-priori sigma [m/s]")
    ax.set_ylabel(ylabel or figure)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, title="pulse interval")
    ax.set_title(title)
    fig.tight_layout()
    save_figure(fig, path)
