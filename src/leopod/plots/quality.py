"""Figures and the summary table of the quality step.

Each function takes the per-system Dataset of :func:`leopod.gnss.quality.assess_quality` and
writes one PNG: MP versus antenna elevation (Wang et al. 2024, Fig. 4; Peng et al. 2021, Fig. 5), an
antenna-frame sky plot (Peng et al. 2021, Figs. 7–9 convention: azimuth 0° = +X = flight
direction), code-noise histograms with cumulative curves (Peng et al. 2021, Fig. 4) and
visibility/IOD (Wang et al. 2024, Figs. 3, 5).
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from leopod.plots import dots, save_figure
from leopod.plots.tables import Column, Footnotes, html_page, row_table

__all__ = ["plot_mp_elevation", "plot_skyplot", "plot_code_noise", "plot_visibility",
           "summary_html"]



def _codes(q: xr.Dataset) -> list[str]:
    return [k[3:-2] for k in q.data_vars if k.startswith("mp_") and k.endswith("_m")]




def plot_mp_elevation(q: xr.Dataset, path, title: str) -> None:
    """Scatter of MP (pass mean removed) versus antenna-frame elevation, one panel per code."""
    codes = _codes(q)
    fig, axes = plt.subplots(len(codes), 1, figsize=(8, 2.6 * max(len(codes), 1)), sharex=True,
                             squeeze=False)
    el = q.el_deg.values
    for ax, code in zip(axes[:, 0], codes):
        mp = q[f"mp_{code}_m"].values
        ok = np.isfinite(mp) & np.isfinite(el)
        dots(ax, el[ok], mp[ok], alpha=0.25, color="tab:blue")
        rms = float(q[f"{q.attrs['system']}_mp_rms_{code}_m"])
        ax.set_ylabel(f"MP {code} [m]")
        ax.set_title(f"{code}: RMS {rms:.3f} m", fontsize=9, loc="left")
        lim = max(4 * rms, 0.2) if np.isfinite(rms) else 1.0
        ax.set_ylim(-lim, lim)
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("elevation in the antenna frame [deg]")
    axes[-1, 0].set_xlim(0, 90)
    fig.suptitle(f"{title}: code multipath vs elevation")
    fig.tight_layout()
    save_figure(fig, path)


def plot_skyplot(q: xr.Dataset, path, title: str) -> None:
    """Polar plot of all observations in the antenna frame, coloured by |MP| of the first code."""
    codes = _codes(q)
    fig = plt.figure(figsize=(6.5, 6))
    ax = fig.add_subplot(projection="polar")
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    el, az = q.el_deg.values, q.az_deg.values
    ok = np.isfinite(el) & (q.pass_id.values >= 0)
    if codes:
        mp = np.abs(q[f"mp_{codes[0]}_m"].values)
        ok &= np.isfinite(mp)
        sc = ax.scatter(np.radians(az[ok]), 90 - el[ok], c=mp[ok], s=1, cmap="viridis",
                        vmax=np.nanpercentile(mp[ok], 98) if ok.any() else 1, rasterized=True)
        fig.colorbar(sc, ax=ax, shrink=0.7, pad=0.1, label=f"|MP {codes[0]}| [m]")
    else:
        ax.scatter(np.radians(az[ok]), 90 - el[ok], s=1, rasterized=True)
    ax.set_rlim(0, 90)
    # elevation rings labelled inside, off the azimuth labels of the rim (0° at the rim and
    # 90° at the centre need none)
    ax.set_yticks([30, 60], ["60°", "30°"])
    ax.set_rlabel_position(112.5)
    ax.grid(alpha=0.3)
    ax.set_title(f"{title}: antenna-frame sky plot\n(azimuth 0° = body +X)",
                 fontsize=10)
    save_figure(fig, path)


def plot_code_noise(q: xr.Dataset, path, title: str) -> None:
    """Histograms of the 2-min sliding STDs of epoch-differenced code-minus-carrier."""
    codes = [k[10:-2] for k in q.data_vars if k.startswith("noise_std_")]
    fig, (ax, ax_cum) = plt.subplots(1, 2, figsize=(10, 4))
    for code in codes:
        w = q[f"noise_std_{code}_m"].values
        w = w[np.isfinite(w)]
        if not w.size:
            continue
        bins = np.geomspace(max(w.min(), 1e-3), w.max(), 60)
        peak = float(q[f"{q.attrs['system']}_noise_{code}_peak_m"])
        ax.hist(w, bins=bins, histtype="step", label=f"{code} (peak {peak:.3f} m)")
        ws = np.sort(w)
        ax_cum.plot(ws, 100 * np.arange(1, ws.size + 1) / ws.size, label=code)
    for a in (ax, ax_cum):
        a.set_xscale("log")
        a.set_xlabel("STD of epoch-differenced code − carrier [m]")
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    ax.set_ylabel("number of windows")
    ax_cum.set_ylabel("cumulative [%]")
    fig.suptitle(f"{title}: code noise, sliding-window STD")
    fig.tight_layout()
    save_figure(fig, path)


def plot_visibility(q: xr.Dataset, path, title: str) -> None:
    """Histogram of satellites per epoch and IOD versus time."""
    system = q.attrs["system"]
    hist = q[f"{system}_epochs_per_n_sats"]
    fig, (ax, ax_iod) = plt.subplots(1, 2, figsize=(11, 4))
    total = hist.values.sum()
    ax.bar(hist.n_sats.values, 100 * hist.values / max(total, 1))
    ax.set_xlabel("satellites tracked per epoch")
    ax.set_ylabel("epochs [%]")
    ax.set_title(f"mean {float(q[f'{system}_mean_sv_per_epoch']):.2f} per epoch", fontsize=9)
    ax.grid(alpha=0.3)
    hours = (q.time.values - q.time.values[0]) / np.timedelta64(1, "h")
    iod = q.iod_m_min.values
    for j in range(iod.shape[1]):
        ok = np.isfinite(iod[:, j])
        if ok.any():
            ax_iod.plot(hours[ok], iod[ok, j], ".", ms=1)
    ax_iod.set_xlabel("hours since first epoch")
    ax_iod.set_ylabel("IOD [m/min]")
    ax_iod.grid(alpha=0.3)
    fig.suptitle(f"{title}: visibility and ionospheric delay rate")
    fig.tight_layout()
    save_figure(fig, path)


#: Indicators that are shares of 1, shown in per cent.
_PERCENT = ("completeness", "utilisation", "iod_above_threshold")


def _indicator(system: str, name: str, var: xr.DataArray) -> tuple[Column, float]:
    """The table column of a daily indicator ``<system>_<name>`` and the factor of its value:
    shares in per cent, counts as integers, metres in centimetres (a code noise of 0.8 mm
    is not "0.001 m")."""
    label = str(var.attrs.get("long_name", name)).removeprefix(f"{system}: ")
    unit = str(var.attrs.get("units", "1"))
    if name in _PERCENT:
        return Column(name, label, "%", "percent", label), 100.0
    if var.dtype.kind in "iu":
        return Column(name, label, "1", "count", label), 1.0
    if unit == "m":
        return Column(name, label, "cm", "number", label), 100.0
    return Column(name, label, unit.replace("min-1", "/min").replace(" /", "/"), "number",
                  label), 1.0


def summary_html(parts: list[xr.Dataset], title: str) -> str:
    """An HTML page of the daily indicators: one row per indicator, one column per system
    (:mod:`leopod.plots.tables`: units in the labels, shares in per cent, counts as integers,
    a dash with a footnote where a system has no value)."""
    systems = [q.attrs["system"] for q in parts]
    rows: dict[str, tuple[Column, list]] = {}
    for j, q in enumerate(parts):
        for var_name, var in q.data_vars.items():
            name = var_name.removeprefix(f"{systems[j]}_")
            if var.ndim or name == var_name:
                continue
            column, factor = _indicator(systems[j], name, var)
            rows.setdefault(name, (column, [np.nan] * len(parts)))[1][j] = float(var) * factor
    notes = Footnotes()
    table = row_table(["indicator", *systems], list(rows.values()), notes,
                      "no such value for this system")
    return html_page(f"Data quality: {title}", table + notes.html())
