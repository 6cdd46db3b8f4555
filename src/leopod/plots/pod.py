"""Figures of the float POD step.

Each function takes a Dataset written by the float POD and writes one PNG:

- post-fit code and phase residuals versus time and versus antenna elevation, with RMS per
  elevation bin (the usual residual diagnostics of reduced-dynamic POD, e.g. Peng et al. 2021);
- a sky map of the mean phase residual in the antenna frame (azimuth 0° = +X = flight
  direction, the convention of Peng et al. 2021, Figs. 7–9 and of :mod:`leopod.plots.quality`), a
  first look at antenna phase-centre variations before an empirical PCV map is estimated;
- the difference of the a-priori (code-only) orbit to the estimated orbit in radial, along-track
  and cross-track, with the formal sigmas of the estimate.

RMS values are computed from the finite values only (unused and rejected observations are NaN
in the residual Dataset). The PNGs carry no software or time stamp, so repeated runs give
identical bytes.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import matplotlib.ticker as mticker
import matplotlib.transforms as mtransforms
import numpy as np
import xarray as xr

from leopod.numerics.statistics import finite_rms
from leopod.plots import dots, save_figure

__all__ = [
    "ARC_FIGURES",
    "plot_apriori_difference",
    "plot_arc",
    "plot_residual_skymap",
    "plot_residuals_elevation",
    "plot_residuals_time",
    "ring_azimuth_cells",
    "rms_by_bin",
    "robust_limit",
]

_M_TO_MM = 1e3
"""Metres to millimetres (display unit of phase residuals and formal sigmas)."""
_BIN_DEG = 5.0
"""Width of the elevation bins and of the sky-map cells [deg]."""
_PANELS = (("phase", _M_TO_MM, "mm"), ("code", 1.0, "m"))
"""(kind, factor from m to the display unit, display unit) of the two residual panels."""
_RTN = ("R", "T", "N")
_RTN_NAMES = {"R": "radial", "T": "along-track", "N": "cross-track"}




def _heading(title: str, what: str) -> str:
    return f"{title}: {what}" if title else what


def _hours_of_day(time: np.ndarray) -> tuple[np.ndarray, str]:
    """Hours since 00:00 of the day that holds the middle epoch of ``time`` (datetime64).

    A 30-h arc from 21:00 of the previous day to 03:00 of the next thus runs from −3 h to 27 h
    and the nominal day spans 0–24 h. Returns the hours, shape (n,), and an axis label.
    """
    t = np.asarray(time, dtype="datetime64[ns]")
    if t.size == 0:
        return np.zeros(0), "hours of day"
    middle = t[0] + (t[-1] - t[0]) // 2
    midnight = middle.astype("datetime64[D]")
    hours = (t - midnight) / np.timedelta64(1, "h")
    return hours, f"hours since {midnight} 00:00 (GPS time)"


def rms_by_bin(values, coordinate, edges) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Root mean square of ``values`` in bins of ``coordinate``.

    ``rms_k = sqrt(sum(v_i**2) / n_k)`` over the pairs with ``edges[k] <= coordinate_i <
    edges[k+1]`` (the last bin also holds ``coordinate_i == edges[-1]``, as ``numpy.histogram``);
    pairs where either value is not finite are ignored.

    Parameters
    ----------
    values, coordinate : array_like, same shape (any)
        Values (e.g. residuals [m]) and the coordinate they are binned by (e.g. elevation [deg]).
    edges : array_like, shape (k+1,)
        Monotonically increasing bin edges, in the unit of ``coordinate``.

    Returns
    -------
    centres : ndarray, shape (k,)
        Bin centres, unit of ``coordinate``.
    rms : ndarray, shape (k,)
        RMS per bin, unit of ``values``; NaN for empty bins.
    counts : ndarray of int, shape (k,)
        Number of finite pairs per bin.
    """
    v = np.asarray(values, dtype=float).ravel()
    x = np.asarray(coordinate, dtype=float).ravel()
    if v.shape != x.shape:
        raise ValueError(f"values and coordinate differ in size: {v.size} vs {x.size}")
    edges = np.asarray(edges, dtype=float)
    ok = np.isfinite(v) & np.isfinite(x)
    counts, _ = np.histogram(x[ok], bins=edges)
    sum_sq, _ = np.histogram(x[ok], bins=edges, weights=v[ok] ** 2)
    rms = np.full(counts.shape, np.nan)
    np.sqrt(np.divide(sum_sq, counts, out=rms, where=counts > 0), out=rms, where=counts > 0)
    return 0.5 * (edges[:-1] + edges[1:]), rms, counts


_AXIS_PERCENTILE = 99.9
"""Percentile of |residual| that sets a residual axis: a few outliers do not stretch it."""
_AXIS_MARGIN = 1.2
"""Factor on that percentile (room above the bulk of the points)."""


def robust_limit(values, fallback: float) -> float:
    """Symmetric axis limit of ``values``: :data:`_AXIS_MARGIN` times the
    :data:`_AXIS_PERCENTILE` th percentile of the finite |values|, at most their largest
    |value| with a 5 % margin; ``fallback`` when there is no non-zero finite value.

    A handful of outliers (0.1 % of the points) no longer sets the scale: 7-mm phase
    residuals get a ±20-mm axis, not ±300 mm because of one rejected 300-mm residual.
    """
    v = np.abs(np.asarray(values, dtype=float))
    v = v[np.isfinite(v)]
    if not v.size or v.max() <= 0:
        return fallback
    return min(_AXIS_MARGIN * float(np.percentile(v, _AXIS_PERCENTILE)), 1.05 * float(v.max()))


def _clip_note(values: np.ndarray, lim: float, unit: str) -> str:
    """``", n beyond ±lim unit (at the edge)"`` for the finite values outside the axis."""
    n = int(np.count_nonzero(np.abs(values[np.isfinite(values)]) > lim))
    return f", {n} beyond ±{lim:.3g} {unit} (drawn at the edge)" if n else ""


def _n_rejected(res: xr.Dataset, kind: str) -> int:
    return int(np.count_nonzero(res[f"{kind}_rejected"].values == 1))


def plot_residuals_time(res: xr.Dataset, path, title: str = "", solution: str = "float") -> None:
    """Post-fit phase [mm] and code [m] residuals versus time, coloured by satellite.

    Each panel states the RMS of the finite residuals, their number and the number of
    observations rejected as outliers; red ticks on the lower axis mark epochs that hold a
    rejected observation.

    Parameters
    ----------
    res : xarray.Dataset
        Residual Dataset of the float POD: ``code_residual_m``, ``phase_residual_m``,
        ``code_rejected``, ``phase_rejected`` (time, sv).
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title (e.g. satellite and date).
    """
    hours, xlabel = _hours_of_day(res.time.values)
    n_sv = res.sizes["sv"]
    colours = plt.get_cmap("tab20")(np.arange(n_sv) / max(n_sv - 1, 1))
    fig, axes = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
    for ax, (kind, scale, unit) in zip(axes, _PANELS):
        r = res[f"{kind}_residual_m"].values * scale
        ok = np.isfinite(r)
        lim = robust_limit(r, 1.0)
        shown = np.clip(r, -lim, lim)
        for j in np.flatnonzero(ok.any(axis=0)):
            dots(ax, hours[ok[:, j]], shown[ok[:, j], j], size_pt2=2.0, color=colours[j])
        rejected = (res[f"{kind}_rejected"].values == 1).any(axis=1)
        ax.plot(hours[rejected], np.zeros(np.count_nonzero(rejected)), "|", color="red", ms=6,
                transform=mtransforms.blended_transform_factory(ax.transData, ax.transAxes))
        ax.set_ylim(-1.02 * lim, 1.02 * lim)
        ax.set_ylabel(f"{kind} residual [{unit}]")
        ax.set_title(f"{kind}: RMS {finite_rms(r):.3g} {unit}, {np.count_nonzero(ok)} used, "
                     f"{_n_rejected(res, kind)} rejected (red ticks){_clip_note(r, lim, unit)}",
                     fontsize=9, loc="left")
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel(xlabel)
    fig.suptitle(_heading(title, f"{solution} POD post-fit residuals"))
    fig.tight_layout()
    save_figure(fig, path)


def plot_residuals_elevation(res: xr.Dataset, path, title: str = "",
                             solution: str = "float") -> None:
    """Post-fit phase [mm] and code [m] residuals versus antenna elevation, with RMS per bin.

    The red line is the RMS in 5° elevation bins (:func:`rms_by_bin`), drawn at the bin centres.

    Parameters
    ----------
    res : xarray.Dataset
        Residual Dataset of the float POD: ``code_residual_m``, ``phase_residual_m``, ``el_deg``
        (time, sv) [deg], elevation above the antenna (body X–Y) plane.
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title.
    """
    el = res.el_deg.values
    low = min(float(np.nanmin(el)) if np.isfinite(el).any() else 0.0, 0.0)
    edges = np.arange(np.floor(low / _BIN_DEG) * _BIN_DEG, 90.0 + _BIN_DEG / 2, _BIN_DEG)
    fig, axes = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for ax, (kind, scale, unit) in zip(axes, _PANELS):
        r = res[f"{kind}_residual_m"].values * scale
        ok = np.isfinite(r) & np.isfinite(el)
        lim = robust_limit(r[ok], 1.0)
        dots(ax, el[ok], np.clip(r[ok], -lim, lim), alpha=0.25, color="tab:blue",
             label="residuals")
        centres, rms, _ = rms_by_bin(r, el, edges)
        ax.plot(centres, rms, "o-", color="tab:red", ms=3, label=f"RMS per {_BIN_DEG:g}° bin")
        ax.set_ylim(-1.02 * lim, 1.02 * lim)
        ax.set_ylabel(f"{kind} residual [{unit}]")
        ax.set_title(f"{kind}: RMS {finite_rms(r):.3g} {unit}{_clip_note(r[ok], lim, unit)}",
                     fontsize=9, loc="left")
        legend = ax.legend(fontsize=8, loc="upper right")
        legend.legend_handles[0].set_markersize(4.0)      # the residual dots, visible
        legend.legend_handles[0].set_alpha(1.0)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("elevation in the antenna frame [deg]")
    axes[-1].set_xlim(edges[0], 90)
    fig.suptitle(_heading(title, f"{solution} POD residuals vs elevation"))
    fig.tight_layout()
    save_figure(fig, path)


def _cell_means(values: np.ndarray, az_deg: np.ndarray, el_deg: np.ndarray,
                az_edges: np.ndarray, el_edges: np.ndarray) -> np.ndarray:
    """Mean of ``values`` per (azimuth, elevation) cell, shape (n_az, n_el); NaN when empty."""
    ok = np.isfinite(values) & np.isfinite(az_deg) & np.isfinite(el_deg)
    az = np.mod(az_deg[ok], 360.0)
    counts, _, _ = np.histogram2d(az, el_deg[ok], bins=(az_edges, el_edges))
    sums, _, _ = np.histogram2d(az, el_deg[ok], bins=(az_edges, el_edges), weights=values[ok])
    means = np.full(counts.shape, np.nan)
    np.divide(sums, counts, out=means, where=counts > 0)
    return means


def ring_azimuth_cells(el_low_deg: float, el_high_deg: float) -> int:
    """Number of azimuth cells of the elevation ring [``el_low_deg``, ``el_high_deg``] of the
    residual sky map: ``360° / 5°`` times the cosine of the ring's mid elevation, at least 3.

    Cells of about equal area: near the zenith 5° × 5° cells shrink to slivers holding a
    handful of residuals each, which drew a noisy starburst; the ring 85–90° has 3 cells.
    """
    mid = np.radians(0.5 * (el_low_deg + el_high_deg))
    return max(3, int(round(360.0 / _BIN_DEG * np.cos(mid))))


def plot_residual_skymap(res: xr.Dataset, path, title: str = "") -> None:
    """Antenna-frame polar map of the mean phase residual [mm] in cells of about equal area.

    Azimuth is the polar angle with 0° at the top (body +X) increasing clockwise
    toward +Y; elevation is radial with 90° (antenna boresight) at the centre. Rings are 5°
    of elevation; each ring has :func:`ring_azimuth_cells` azimuth cells (5° at the horizon,
    wider towards the zenith). Observations below the antenna plane (negative elevation) are
    left out. The colour scale is symmetric about zero (98th percentile of |cell mean|).

    Parameters
    ----------
    res : xarray.Dataset
        Residual Dataset of the float POD: ``phase_residual_m``, ``el_deg``, ``az_deg``
        (time, sv) [deg].
    path : str or path-like
        Figure to write.
    title : str
        Prefix of the figure title.
    """
    el_edges = np.arange(0.0, 90.0 + _BIN_DEG / 2, _BIN_DEG)
    values = res.phase_residual_m.values * _M_TO_MM
    rings = []
    for low, high in zip(el_edges[:-1], el_edges[1:], strict=True):
        az_edges = np.linspace(0.0, 360.0, ring_azimuth_cells(low, high) + 1)
        rings.append((az_edges, np.array([low, high]),
                      _cell_means(values, res.az_deg.values, res.el_deg.values, az_edges,
                                  np.array([low, high]))))
    finite = np.abs(np.concatenate([m.ravel() for *_, m in rings]))
    finite = finite[np.isfinite(finite)]
    vmax = float(np.percentile(finite, 98)) if finite.size and finite.max() > 0 else 1.0
    fig = plt.figure(figsize=(6.5, 6))
    ax = fig.add_subplot(projection="polar")
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    for az_edges, edges, means in rings:
        mesh = ax.pcolormesh(np.radians(az_edges), 90.0 - edges, np.ma.masked_invalid(means.T),
                             cmap="RdBu_r", vmin=-vmax, vmax=vmax, shading="flat",
                             rasterized=True)
    fig.colorbar(mesh, ax=ax, shrink=0.7, pad=0.1, label="mean phase residual [mm]")
    ax.set_rlim(0, 90)
    ax.set_yticks([30, 60])
    ax.set_yticklabels(["60°", "30°"])
    ax.set_rlabel_position(112.5)
    ax.grid(alpha=0.3)
    # one short line each: the polar axes leave no room for a long title line
    ax.set_title((f"{title}\n" if title else "")
                 + f"mean phase residual, {_BIN_DEG:g}° rings of equal-area cells"
                 + "\n(antenna frame, azimuth 0° = body +X)", fontsize=10)
    save_figure(fig, path)


def plot_apriori_difference(orbit: xr.Dataset, path, title: str = "", solution: str = "float",
                            reference: str = "a-priori (code-only) orbit") -> None:
    """A-priori minus estimated orbit in R/T/N [m] and formal sigmas of the estimate [mm].

    Upper panel: ``apriori_diff_rtn_m`` per component with its RMS (finite values) in the
    legend; lower panel: ``sigma_rtn_m`` per component on a logarithmic axis.

    Parameters
    ----------
    orbit : xarray.Dataset
        Orbit Dataset of the float POD: ``apriori_diff_rtn_m`` and ``sigma_rtn_m`` (time, rtn)
        [m], with ``rtn`` labels "R", "T", "N".
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title.
    solution : str
        The estimated solution ("float", "ambiguity-fixed"), for the title.
    reference : str
        What the a-priori orbit is (the code-only orbit of the float POD, the float orbit of
        the fixed POD), for the title.
    """
    hours, xlabel = _hours_of_day(orbit.time.values)
    fig, (ax, ax_sig) = plt.subplots(2, 1, figsize=(10, 6.5), sharex=True)
    any_sigma = False
    for comp in _RTN:
        diff = orbit.apriori_diff_rtn_m.sel(rtn=comp).values
        ax.plot(hours, diff, lw=0.8,
                label=f"{comp} ({_RTN_NAMES[comp]}): RMS {finite_rms(diff):.3f} m")
        sigma = orbit.sigma_rtn_m.sel(rtn=comp).values * _M_TO_MM
        ok = np.isfinite(sigma) & (sigma > 0)
        any_sigma |= bool(ok.any())
        ax_sig.plot(hours[ok], sigma[ok], lw=0.8, label=comp)
    ax.set_ylabel("a priori − estimated [m]")
    ax.grid(alpha=0.3)
    if any_sigma:
        ax_sig.set_yscale("log")
        ax_sig.yaxis.set_major_formatter(mticker.LogFormatter())
        ax_sig.yaxis.set_minor_formatter(mticker.LogFormatter(labelOnlyBase=False,
                                                              minor_thresholds=(2, 0.5)))
    ax_sig.set_ylabel("formal sigma [mm]")
    for a in (ax, ax_sig):
        a.legend(fontsize=8, loc="lower left", bbox_to_anchor=(0.0, 1.0), ncols=3,
                 frameon=False)
    ax_sig.grid(alpha=0.3, which="both")
    ax_sig.set_xlabel(xlabel)
    fig.suptitle(_heading(title, f"{reference} minus {solution} POD orbit, R/T/N"))
    fig.tight_layout()
    save_figure(fig, path)


#: The figures :func:`plot_arc` draws (its path arguments).
ARC_FIGURES = ("res_time", "res_elevation", "res_skymap", "apriori")


def plot_arc(orbit: xr.Dataset, residuals: xr.Dataset, *, res_time, res_elevation, res_skymap,
             apriori, title: str, solution: str, reference: str) -> None:
    """The four figures of a POD solution: residuals vs time and elevation, phase residual
    map, and the orbit minus its a-priori orbit in RTN (paths of the PNG files).

    ``solution`` names the estimate ("float", "ambiguity-fixed") and ``reference`` its a-priori
    orbit in the titles (:func:`plot_apriori_difference`)."""
    plot_residuals_time(residuals, res_time, title=title, solution=solution)
    plot_residuals_elevation(residuals, res_elevation, title=title, solution=solution)
    plot_residual_skymap(residuals, res_skymap, title=f"{solution} {title}")
    plot_apriori_difference(orbit, apriori, title=title, solution=solution, reference=reference)
