"""Figures of the campaign summary (rule ``campaign_summary``).

Both functions draw columns of the campaign table of :mod:`leopod.validation.summary` (daily
rows indexed by (date ``YYYY-DDD``, solution) and, per solution, the ``mean`` and ``std`` rows
it computed); they compute no statistic themselves:

- :func:`plot_pco_z`: the estimated antenna PCO-Z correction per day with its formal sigma as
  error bar, float and ambiguity-fixed solutions side by side, with the mean and the STD over the
  days in the legend (Jiang et al. 2023, Fig. 8). A campaign that does not estimate the PCO-Z
  (all values NaN) gets a figure that says so, so the report keeps one figure per satellite;
- :func:`plot_fixing_rates`: per day the wide- and narrow-lane fixing rates with both
  definitions, the graph-rank rate (fixed independent / all independent single differences,
  Jiang et al. 2023, Fig. 11) and the share of single differences fixed, with the campaign means
  in the legend. Without ambiguity resolution the figure says so;
- :func:`plot_isb`: the inter-system biases of a combined POD over time, each piece (one per
  arc, or per ``pod.isb_interval_s``) as a segment over its epochs with its formal sigma as
  a band, float and fixed solutions side by side, one panel per system. A single-system
  campaign gets a figure that says so.

The PNGs carry no software or time stamp, so repeated runs give identical bytes.
"""

from __future__ import annotations

import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.dates as mdates
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from leopod.plots import save_figure

__all__ = ["plot_fixing_rates", "plot_isb", "plot_pco_z"]

_LABELS = {"float_pod": "float", "fixed_pod": "fixed"}
_OFFSET_H = 2.0
"""Horizontal shift between the solutions of one day [h], so error bars do not overlap."""
_MAX_DAY_TICKS = 10
"""Campaigns up to this many days get one labelled tick (``YYYY-DDD``) per day."""
_RATE_MARGIN_PCT = 5.0
"""Space below the lowest fixing rate of a panel [%] (the top is 100 % plus a fifth of it)."""
_DAY = re.compile(r"\d{4}-\d{3}")
"""A day id (YYYY-DDD) in the summary table's date index."""
_NOTE = {"ha": "center", "va": "center", "fontsize": 11, "color": "grey"}


def _days(table: pd.DataFrame, solution: str) -> pd.DataFrame:
    """Daily rows of one solution, indexed by the day's noon (datetime64)."""
    rows = table.xs(solution, level="solution")
    # the daily rows (YYYY-DDD), not the rows of statistics over the days (mean, std, ...)
    rows = rows.loc[[d for d in rows.index if _DAY.fullmatch(str(d))]]
    rows.index = pd.to_datetime(rows.index, format="%Y-%j") + pd.Timedelta(hours=12)
    return rows


def _value(table: pd.DataFrame, row: str, solution: str, column: str) -> float:
    key = (row, solution)
    return float(table.loc[key, column]) if key in table.index else float("nan")


def _solutions(table: pd.DataFrame) -> list[str]:
    return list(dict.fromkeys(table.index.get_level_values("solution")))


def _date_axis(ax, days: pd.DatetimeIndex) -> None:
    """Days on the x axis (points at noon): one labelled tick per day for short campaigns."""
    locator = (mdates.HourLocator(byhour=12) if len(days) <= _MAX_DAY_TICKS
               else mdates.AutoDateLocator(minticks=3, maxticks=_MAX_DAY_TICKS))
    ax.xaxis.set_major_locator(locator)
    ax.xaxis.set_major_formatter(mdates.DateFormatter("%Y-%j") if len(days) <= _MAX_DAY_TICKS
                                 else mdates.ConciseDateFormatter(locator))
    margin = pd.Timedelta(hours=12)
    ax.set_xlim(days.min() - margin, days.max() + margin)
    ax.grid(alpha=0.3)


def _legend_above(ax, n_entries: int) -> None:
    """Legend in one row above the panel, so it never hides points."""
    ax.legend(fontsize=8, loc="lower left", bbox_to_anchor=(0.0, 1.0), ncols=n_entries,
              frameon=False)


def _note(fig, ax, text: str) -> None:
    ax.text(0.5, 0.5, text, transform=ax.transAxes, **_NOTE)
    ax.set_xticks([])
    ax.set_yticks([])
    fig.tight_layout()


def plot_pco_z(table: pd.DataFrame, path, title: str = "") -> None:
    """PCO-Z correction per day, float and fixed, with formal sigmas (Jiang et al. 2023, Fig. 8).

    Parameters
    ----------
    table : pandas.DataFrame
        :func:`leopod.validation.summary.campaign_table` (columns ``pco_z_cm``,
        ``pco_z_sigma_cm`` [cm]; rows (date, solution) with ``mean`` and ``std`` rows).
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title.
    """
    fig, ax = plt.subplots(figsize=(10, 4))
    fig.suptitle(f"{title}: estimated antenna PCO-Z (correction to the a-priori PCO)"
                 if title else "estimated antenna PCO-Z (correction to the a-priori PCO)")
    if not np.isfinite(table["pco_z_cm"].to_numpy(dtype=float)).any():
        _note(fig, ax, "PCO-Z not estimated in this campaign (pod.estimate_pco_z: false)")
        save_figure(fig, path)
        return
    sols = _solutions(table)
    offsets = (np.arange(len(sols)) - (len(sols) - 1) / 2.0) * _OFFSET_H
    for solution, offset in zip(sols, offsets, strict=True):
        days = _days(table, solution)
        mean = _value(table, "mean", solution, "pco_z_cm")
        std = _value(table, "std", solution, "pco_z_cm")
        spread = f" ± {std:.2f}" if np.isfinite(std) else ""
        ax.errorbar(days.index + pd.Timedelta(hours=offset), days["pco_z_cm"],
                    yerr=days["pco_z_sigma_cm"], marker="o", ms=4, lw=0.8, capsize=3,
                    label=f"{_LABELS.get(solution, solution)}: mean {mean:.2f}{spread} cm "
                          "(STD over days)")
    ax.axhline(0.0, color="grey", lw=0.6)
    ax.set_ylabel("PCO-Z [cm]")
    ax.set_xlabel("day (error bars: formal 1-sigma)")
    _legend_above(ax, len(sols))
    _date_axis(ax, _days(table, sols[0]).index)
    fig.tight_layout()
    save_figure(fig, path)


def plot_fixing_rates(table: pd.DataFrame, path, title: str = "") -> None:
    """WL and NL fixing rates per day, graph-rank rate and share of SDs fixed.

    Parameters
    ----------
    table : pandas.DataFrame
        :func:`leopod.validation.summary.campaign_table` (columns
        ``{wl,nl}_fixing_rate_pct`` and ``{wl,nl}_sd_fixed_pct`` [%]). The rates belong to
        the day's ambiguity resolution; they are read from the first solution whose rows
        have them.
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title.
    """
    columns = ["wl_fixing_rate_pct", "nl_fixing_rate_pct", "wl_sd_fixed_pct", "nl_sd_fixed_pct"]
    fig, axes = plt.subplots(2, 1, sharex=True, figsize=(10, 5.5))
    fig.suptitle(f"{title}: ambiguity fixing rates" if title else "ambiguity fixing rates")
    with_ar = [s for s in _solutions(table)
               if np.isfinite(_days(table, s)[columns].to_numpy(dtype=float)).any()]
    if not with_ar:
        axes[1].remove()
        _note(fig, axes[0], "no ambiguity resolution in this campaign")
        save_figure(fig, path)
        return
    solution = with_ar[0]
    days = _days(table, solution)
    for ax, lane, name in zip(axes, ("wl", "nl"), ("wide lane", "narrow lane"), strict=True):
        for column, text, marker in ((f"{lane}_fixing_rate_pct",
                                      "fixed / all independent SDs (graph rank)", "o"),
                                     (f"{lane}_sd_fixed_pct", "fixed / all SDs", "s")):
            mean = _value(table, "mean", solution, column)
            ax.plot(days.index, days[column], marker=marker, ms=4, lw=0.8,
                    label=f"{text}: mean {mean:.1f} %")
        low = np.nanmin(days[[f"{lane}_fixing_rate_pct", f"{lane}_sd_fixed_pct"]].to_numpy(float))
        ax.set_ylim(max(0.0, low - _RATE_MARGIN_PCT) if np.isfinite(low) else 0.0,
                    100 + _RATE_MARGIN_PCT / 5)
        ax.ticklabel_format(axis="y", useOffset=False)
        ax.set_ylabel(f"{name} [%]")
        _legend_above(ax, 2)
        _date_axis(ax, days.index)
    axes[-1].set_xlabel("day")
    fig.tight_layout()
    save_figure(fig, path)


def plot_isb(series: pd.DataFrame, path, title: str = "") -> None:
    """Inter-system-bias pieces over time per system, float and fixed (module docstring).

    Parameters
    ----------
    series : pandas.DataFrame
        :func:`leopod.validation.summary.isb_series` of every day, with a ``solution``
        column (``system``, ``start``, ``end`` datetime64, ``estimate_m``, ``sigma_m`` [m]).
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title.
    """
    heading = "inter-system code biases (relative to the first system of the POD)"
    systems = sorted(series["system"].unique()) if len(series) else []
    fig, axes = plt.subplots(max(len(systems), 1), 1, sharex=True, squeeze=False,
                             figsize=(10, 1.5 + 2.5 * max(len(systems), 1)))
    axes = axes[:, 0]
    fig.suptitle(f"{title}: {heading}" if title else heading)
    if not systems:
        _note(fig, axes[0], "no inter-system bias: a single-system POD")
        save_figure(fig, path)
        return
    for ax, system in zip(axes, systems, strict=True):
        mine = series[series["system"] == system]
        sols = list(dict.fromkeys(mine["solution"]))
        for k, solution in enumerate(sols):
            rows = mine[mine["solution"] == solution]
            colour = f"C{k}"
            est = rows["estimate_m"].to_numpy(float)
            spread = f" ± {np.std(est, ddof=1):.3f}" if est.size > 1 else ""
            for _, r in rows.iterrows():
                t = [r["start"], r["end"]]
                ax.plot(t, [r["estimate_m"]] * 2, color=colour, lw=1.5)
                ax.fill_between(t, r["estimate_m"] - r["sigma_m"], r["estimate_m"] + r["sigma_m"],
                                color=colour, alpha=0.25, lw=0)
            ax.plot([], [], color=colour, lw=1.5,
                    label=f"{_LABELS.get(solution, solution)}: mean {np.mean(est):.3f}{spread} m "
                          f"({est.size} piece{'s' if est.size > 1 else ''})")
        ax.set_ylabel(f"ISB {system} [m]")
        ax.ticklabel_format(axis="y", useOffset=False)
        ax.grid(alpha=0.3)
        _legend_above(ax, len(sols))
    locator = mdates.AutoDateLocator(minticks=3, maxticks=_MAX_DAY_TICKS)
    axes[-1].xaxis.set_major_locator(locator)
    axes[-1].xaxis.set_major_formatter(mdates.ConciseDateFormatter(locator))
    axes[-1].set_xlabel("time (GPS; bands: formal 1-sigma)")
    fig.tight_layout()
    save_figure(fig, path)
