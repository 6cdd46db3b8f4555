"""Figures of the antenna-frame code-bias maps (step ``code_bias``).

Each public function takes the map Dataset of :mod:`leopod.codebias` (or the MP samples the
maps were estimated from) and writes one PNG:

- polar maps of the code error per signal and attitude mode (Peng et al. 2021, Figs. 7, 8, 11;
  Jiang et al. 2023, Figs. 5, 7): zenith (antenna boresight) at the centre, horizon at the rim,
  azimuth 0° = body +X (the flight direction in the nominal attitude) at the top, increasing
  clockwise towards +Y;
- the number of observations touching each node on a logarithmic scale (Peng et al. 2021, Fig. 9);
- code multipath versus antenna elevation before and after the map correction, with the RMS and
  mean per elevation band (Jiang et al. 2023, Fig. 6);
- the difference of two maps on the same grid (e.g. two periods, Peng et al. 2021, Figs. 7 vs 8),
  with the mean and the RMS about the mean over the commonly non-empty nodes.

Map nodes are drawn as cells centred on the nodes (the map itself is bilinear between nodes,
Wang et al. (2024) eqs. (7)–(9)); nodes flagged ``empty`` (fewer than ``attrs["min_count"]``
observations) are left blank, as in the source papers. The zenith node, repeated in the 90° row of
the Dataset for every azimuth, counts once in every statistic and colour scale. The PNGs carry no
software or time stamp, so repeated runs give identical bytes.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping

import matplotlib

matplotlib.use("Agg")
import matplotlib.colors as mcolors
import matplotlib.pyplot as plt
import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.collections import PathCollection
from matplotlib.figure import Figure

from leopod.numerics.statistics import finite_rms
from leopod.plots import save_figure
from leopod.plots.pod import _heading

__all__ = [
    "plot_code_bias_counts",
    "plot_code_bias_maps",
    "plot_map_difference",
    "plot_mp_elevation",
]

logger = logging.getLogger(__name__)

_UNIT_PER_M = {"m": 1.0, "cm": 1e2, "mm": 1e3}
"""Factor from metres to each display unit of map values."""
_FIELD_NAMES = {"value_m": "code bias", "sigma_m": "formal sigma"}
"""Short display names of the map fields."""
_NONNEGATIVE_FIELDS = frozenset({"sigma_m"})
"""Map fields drawn on a sequential scale from zero instead of a symmetric diverging one."""
_COLOUR_PERCENTILE = 98.0
"""Percentile of |value| over the shown nodes that sets the colour limit (robust to outliers)."""
_SCATTER_PERCENTILE = 99.5
"""Percentile of |MP| that sets the symmetric y-limit of the MP scatter plots."""
_MAX_SCATTER_POINTS = 20_000
"""Default largest number of points per scatter series (deterministic every-k-th subsample)."""
_GRID_DIMS = ("elevation_deg", "azimuth_deg")
_RING_LABELS_DEG = (60.0, 30.0)
"""Elevation rings that carry a label [deg]."""
_PANEL_IN = (3.2, 3.0)
"""Width and height of one polar panel [inch]."""
_MIN_WIDTH_IN = 6.0
"""Smallest figure width [inch], wide enough for the three-line figure title."""
_CONVENTION = "azimuth 0° = body +X, clockwise to +Y; zenith at the centre"


def _unit_factor(units: str) -> float:
    try:
        return _UNIT_PER_M[units]
    except KeyError:
        raise ValueError(f"units must be one of {sorted(_UNIT_PER_M)}, not {units!r}") from None


def _sorted_grid(maps: xr.Dataset) -> xr.Dataset:
    """``maps`` with ascending node coordinates; at least two nodes in each grid direction."""
    for dim in _GRID_DIMS:
        if maps.sizes.get(dim, 0) < 2:
            raise ValueError(f"the map grid needs at least two {dim} nodes")
    return maps.sortby(list(_GRID_DIMS))


def _cell_edges(centres: np.ndarray, low: float, high: float) -> np.ndarray:
    """Edges of cells centred on ascending ``centres`` (n,) → (n + 1,), clipped to [low, high].

    Inner edges are the midpoints between neighbouring centres; the outer edges lie half the
    adjacent spacing beyond the first and last centre.
    """
    c = np.asarray(centres, dtype=float)
    mid = 0.5 * (c[1:] + c[:-1])
    edges = np.concatenate([[2.0 * c[0] - mid[0]], mid, [2.0 * c[-1] - mid[-1]]])
    return np.clip(edges, low, high)


def _mesh(maps: xr.Dataset) -> tuple[np.ndarray, np.ndarray]:
    """Polar cell edges of the node grid: azimuth (n_az + 1,) [rad], radius (n_el + 1,) [deg].

    The radius is the zenith distance ``90° − elevation``; elevation cells are clipped to the
    lowest node and to the zenith, so the rim of the plot is the lowest ring.
    """
    az_edges = _cell_edges(maps.azimuth_deg.values, -np.inf, np.inf)
    el = maps.elevation_deg.values
    el_edges = _cell_edges(el, float(el[0]), 90.0)
    return np.radians(az_edges), 90.0 - el_edges


def _unique_nodes(maps: xr.Dataset) -> xr.DataArray:
    """(elevation_deg, azimuth_deg) bool: False on the repeats of the zenith node."""
    at_zenith = maps.elevation_deg >= 90.0
    repeat = maps.azimuth_deg != maps.azimuth_deg[0]
    return ~(at_zenith & repeat)


def _shown(maps: xr.Dataset, name: str) -> xr.DataArray:
    """Variable ``name`` as float, NaN at empty nodes."""
    return maps[name].astype(float).where(~maps["empty"])


def _robust_limit(values: xr.DataArray, keep: xr.DataArray) -> float:
    """98th percentile of |values| over finite ``keep`` nodes; 1 when there is none or it is 0."""
    v = np.abs(values.where(keep).values)
    v = v[np.isfinite(v)]
    limit = float(np.percentile(v, _COLOUR_PERCENTILE)) if v.size else 0.0
    return limit if limit > 0 else 1.0


def _log_norm(counts: xr.DataArray) -> mcolors.LogNorm:
    """Logarithmic colour scale over the finite positive ``counts``."""
    c = counts.values[np.isfinite(counts.values) & (counts.values > 0)]
    low = float(c.min()) if c.size else 1.0
    high = float(c.max()) if c.size else 10.0
    return mcolors.LogNorm(vmin=low, vmax=high if high > low else 10.0 * low)


def _setup_polar(ax: Axes, r_max_deg: float) -> None:
    """Azimuth 0° at the top, clockwise; elevation rings labelled; radius = zenith distance."""
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    ax.set_rlim(0.0, r_max_deg)
    rings = [el for el in _RING_LABELS_DEG if 90.0 - el <= r_max_deg]
    ax.set_yticks([90.0 - el for el in rings], [f"{el:g}°" for el in rings], fontsize=7)
    ax.set_rlabel_position(112.5)
    ax.tick_params(axis="x", labelsize=7, pad=-2)
    ax.grid(alpha=0.3)


def _panel_grid(maps: xr.Dataset, heading: str, note: str) -> tuple[Figure, np.ndarray]:
    """Figure with one polar panel per (signal, mode): rows signals, columns modes.

    The figure title has three lines: ``heading``, ``note`` and the orientation convention.
    """
    n_sig, n_mode = maps.sizes["signal"], maps.sizes["mode"]
    fig, axes = plt.subplots(
        n_sig, n_mode, squeeze=False, subplot_kw={"projection": "polar"}, layout="constrained",
        figsize=(max(_PANEL_IN[0] * n_mode + 1.2, _MIN_WIDTH_IN), _PANEL_IN[1] * n_sig + 1.1))
    fig.suptitle(f"{heading}\n{note}\n({_CONVENTION})", fontsize=9)
    return fig, axes


def _blank_note(maps: xr.Dataset) -> str:
    return f"blank: nodes with fewer than {maps.attrs.get('min_count', '?')} observations"


def _draw_maps(fig: Figure, axes: np.ndarray, maps: xr.Dataset, values: xr.DataArray,
               norm: mcolors.Normalize, cmap: str, label: str) -> None:
    """pcolormesh of ``values`` (signal, mode, elevation_deg, azimuth_deg) into ``axes``.

    Every panel shares the colour scale ``norm`` and one colour bar labelled ``label``, so
    the maps of the signals compare directly; NaN nodes stay blank.
    """
    theta_rad, r_deg = _mesh(maps)
    for row, signal in enumerate(maps.signal.values):
        for col, mode in enumerate(maps.mode.values):
            ax = axes[row, col]
            cells = values.sel(signal=signal, mode=mode).transpose(*_GRID_DIMS).values
            mesh = ax.pcolormesh(theta_rad, r_deg, np.ma.masked_invalid(cells), cmap=cmap,
                                 norm=norm, shading="flat", rasterized=True)
            _setup_polar(ax, float(r_deg[0]))
            ax.set_title(f"{signal}, mode {mode}", fontsize=9)
    fig.colorbar(mesh, ax=axes.ravel().tolist(), shrink=0.6, label=label)


def _maps_figure(maps: xr.Dataset, *, title: str, field: str, units: str) -> Figure:
    """Figure of :func:`plot_code_bias_maps` (kept open for the caller)."""
    maps = _sorted_grid(maps)
    values = _shown(maps, field) * _unit_factor(units)
    keep = _unique_nodes(maps)
    limit = _robust_limit(values, keep)          # one scale: the codes compare at a glance
    if field in _NONNEGATIVE_FIELDS:
        norm = mcolors.Normalize(0.0, limit)
        cmap = "viridis"
    else:
        norm = mcolors.Normalize(-limit, limit)
        cmap = "RdBu_r"
    name = _FIELD_NAMES.get(field, field)
    what = "antenna-frame code-bias maps" + ("" if field == "value_m" else f" ({name})")
    fig, axes = _panel_grid(maps, _heading(title, what),
                            _blank_note(maps))
    _draw_maps(fig, axes, maps, values, norm, cmap, f"{name} [{units}]")
    return fig


def plot_code_bias_maps(maps: xr.Dataset, path, *, title: str = "", field: str = "value_m",
                        units: str = "cm") -> None:
    """Polar maps of a code-bias map field, one panel per signal (row) and attitude mode (column).

    Azimuth is the polar angle with 0° (body +X) at the top increasing clockwise
    towards +Y; elevation is radial with the zenith (antenna boresight) at the centre, as in
    Peng et al. (2021) Figs. 7–11 and Jiang et al. (2023) Fig. 5. Each node fills the cell centred
    on it; empty nodes are blank. All panels share one colour scale (the codes compare at a
    glance): symmetric about zero at the 98th percentile of |value| over all of them
    (sequential from zero for ``sigma_m``).

    Parameters
    ----------
    maps : xarray.Dataset
        Map Dataset of :mod:`leopod.codebias`: ``field`` and ``empty`` (signal, mode,
        elevation_deg, azimuth_deg), field in [m]; attr ``min_count``.
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title (e.g. satellite and period).
    field : str
        Variable to draw: ``"value_m"`` (map value) or ``"sigma_m"`` (formal sigma).
    units : {"cm", "m", "mm"}
        Display unit of the colour scale.
    """
    save_figure(_maps_figure(maps, title=title, field=field, units=units), path)


def _counts_figure(maps: xr.Dataset, *, title: str) -> Figure:
    """Figure of :func:`plot_code_bias_counts` (kept open for the caller)."""
    maps = _sorted_grid(maps)
    counts = _shown(maps, "count")
    keep = _unique_nodes(maps)
    fig, axes = _panel_grid(maps, _heading(title, "observations per map node"),
                            _blank_note(maps))
    _draw_maps(fig, axes, maps, counts, _log_norm(counts.where(keep)), "viridis",
               "observations per node")
    return fig


def plot_code_bias_counts(maps: xr.Dataset, path, *, title: str = "") -> None:
    """Polar maps of the number of observations touching each node (Peng et al. 2021, Fig. 9).

    Same layout and orientation as :func:`plot_code_bias_maps`; one logarithmic colour scale
    over the non-empty nodes of all panels; nodes with fewer than ``attrs["min_count"]`` observations
    (``empty``) are blank.

    Parameters
    ----------
    maps : xarray.Dataset
        Map Dataset of :mod:`leopod.codebias`: ``count`` and ``empty`` (signal, mode,
        elevation_deg, azimuth_deg); attr ``min_count``.
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title.
    """
    save_figure(_counts_figure(maps, title=title), path)


def _subsample_step(n: int, max_points: int) -> int:
    """Smallest ``k`` with ``ceil(n / k) <= max_points``: plotting every k-th point."""
    return max(1, -(-n // max_points))


def _overall_rms(maps: xr.Dataset | None, signal: str, before_m: np.ndarray,
                 after_m: np.ndarray) -> tuple[float, float]:
    """RMS of MP before and after correction [m]: from ``maps`` if it holds them, else samples."""
    if maps is not None and "mp_rms_all_before_m" in maps and signal in maps.signal.values:
        return (float(maps.mp_rms_all_before_m.sel(signal=signal)),
                float(maps.mp_rms_all_after_m.sel(signal=signal)))
    return finite_rms(before_m), finite_rms(after_m)


def _band_width(maps: xr.Dataset) -> float:
    """Width of the elevation bands [deg]: attr ``band_width_deg`` of ``el_band_deg`` or of the
    Dataset, else the spacing of the band lower edges."""
    width = maps.el_band_deg.attrs.get("band_width_deg", maps.attrs.get("band_width_deg"))
    if width is None:
        edges = maps.el_band_deg.values
        width = edges[1] - edges[0] if edges.size > 1 else 90.0 - edges[0]
    return float(width)


def _draw_bands(ax: Axes, maps: xr.Dataset, signal: str) -> None:
    """RMS (solid) and mean (dashed) of MP per elevation band, before and after correction."""
    width = _band_width(maps)
    centres = maps.el_band_deg.values + 0.5 * width
    for when, colour in (("before", "navy"), ("after", "darkred")):
        rms = maps[f"mp_rms_{when}_m"].sel(signal=signal).values
        mean = maps[f"mp_mean_{when}_m"].sel(signal=signal).values
        ax.plot(centres, rms, "o-", color=colour, ms=3, lw=1.2,
                label=f"RMS per {width:g}° band, {when}")
        ax.plot(centres, mean, "s--", color=colour, ms=2, lw=0.8,
                label=f"mean per {width:g}° band, {when}")


def _figure_legend(fig: Figure, axes: np.ndarray) -> None:
    """One legend below the panels with every label of ``axes`` once; scatter keys enlarged."""
    entries = {}
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            entries.setdefault(label, handle)
    legend = fig.legend(list(entries.values()), list(entries), loc="outside lower center",
                        ncols=3, fontsize=8)
    for handle in legend.legend_handles:
        if isinstance(handle, PathCollection):
            handle.set_sizes([12.0])
            handle.set_alpha(1.0)


def _mp_figure(samples: Mapping[str, tuple], maps: xr.Dataset | None, *, title: str,
               max_points: int) -> Figure:
    """Figure of :func:`plot_mp_elevation` (kept open for the caller)."""
    if not samples:
        raise ValueError("no MP samples to plot")
    fig, axes = plt.subplots(len(samples), 1, figsize=(8, 2.9 * len(samples) + 0.6),
                             sharex=True, squeeze=False, layout="constrained")
    for ax, (signal, arrays) in zip(axes[:, 0], samples.items(), strict=True):
        el, before, after = (np.asarray(a, dtype=float).ravel() for a in arrays)
        if not el.shape == before.shape == after.shape:
            raise ValueError(f"{signal}: el_deg, mp_before_m and mp_after_m differ in size "
                             f"({el.size}, {before.size}, {after.size})")
        k = _subsample_step(el.size, max_points)
        logger.debug("%s: plotting every %d-th of %d MP samples", signal, k, el.size)
        shown = []
        for values, colour, when in ((before, "tab:blue", "before"), (after, "tab:red", "after")):
            ok = np.isfinite(el[::k]) & np.isfinite(values[::k])
            ax.scatter(el[::k][ok], values[::k][ok], s=1, alpha=0.3, color=colour,
                       rasterized=True, label=f"{when} correction")
            shown.append(np.abs(values[::k][ok]))
        if maps is not None and "mp_rms_before_m" in maps and signal in maps.signal.values:
            _draw_bands(ax, maps, signal)
        rms_before, rms_after = _overall_rms(maps, signal, before, after)
        gain = 100.0 * (1.0 - rms_after / rms_before) if rms_before > 0 else float("nan")
        ax.set_title(f"{signal}: RMS {rms_before:.3f} m before, {rms_after:.3f} m after "
                     f"correction ({gain:.0f} % less)", fontsize=9, loc="left")
        magnitudes = np.concatenate(shown)
        lim = (1.1 * float(np.percentile(magnitudes, _SCATTER_PERCENTILE))
               if magnitudes.size else 0.0)
        ax.set_ylim(-lim if lim > 0 else -1.0, lim if lim > 0 else 1.0)
        ax.set_ylabel(f"MP {signal} [m]")
        ax.grid(alpha=0.3)
    _figure_legend(fig, axes[:, 0])
    axes[-1, 0].set_xlim(0.0, 90.0)
    axes[-1, 0].set_xticks(np.arange(0.0, 91.0, 15.0))
    axes[-1, 0].set_xlabel("elevation in the antenna frame [deg]")
    fig.suptitle(_heading(title, "code multipath vs elevation before and after map correction"),
                 fontsize=10)
    return fig


def plot_mp_elevation(samples: Mapping[str, tuple], maps: xr.Dataset | None, path, *,
                      title: str = "", max_points: int = _MAX_SCATTER_POINTS) -> None:
    """Code multipath versus antenna elevation before and after the map correction.

    One panel per signal, as Jiang et al. (2023) Fig. 6: scatter of MP before (blue) and after (red)
    the correction, and, when ``maps`` holds the signal, the RMS (solid) and mean (dashed) per
    elevation band. Long series are thinned to every k-th point, ``k = ceil(n / max_points)``
    (deterministic), for the scatter only; the RMS in the panel title comes from ``maps``
    (``mp_rms_all_*_m``) or, for a signal it lacks, from all finite samples.

    Parameters
    ----------
    samples : mapping of str to (el_deg, mp_before_m, mp_after_m)
        Per signal (RINEX 3 code), three 1-D arrays of equal length (n,): antenna elevation
        [deg] and MP before and after the map correction [m]; NaN entries are skipped.
    maps : xarray.Dataset or None
        Map Dataset with the statistics ``mp_rms_before_m``, ``mp_rms_after_m``,
        ``mp_mean_before_m``, ``mp_mean_after_m`` (signal, el_band_deg) [m] (coordinate
        ``el_band_deg`` = band lower edges [deg]; band width from attr ``band_width_deg`` of
        the coordinate or of the Dataset, else the edge spacing) and
        ``mp_rms_all_before_m``, ``mp_rms_all_after_m`` (signal) [m]; None for no band lines.
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title.
    max_points : int
        Largest number of scatter points per series and signal.
    """
    save_figure(_mp_figure(samples, maps, title=title, max_points=max_points), path)


def _difference_stats(diff: xr.DataArray, keep: xr.DataArray) -> tuple[float, float, int]:
    """Mean, RMS about the mean and count of the finite ``diff`` at ``keep`` nodes.

    ``rms = sqrt(sum((d_i − mean)**2) / n)``; NaN mean and RMS when ``n = 0``.
    """
    d = diff.where(keep).values
    d = d[np.isfinite(d)]
    if not d.size:
        return float("nan"), float("nan"), 0
    mean = float(d.mean())
    return mean, finite_rms(d - mean), int(d.size)


def _common_maps(map_a: xr.Dataset, map_b: xr.Dataset) -> tuple[xr.Dataset, xr.Dataset]:
    """The two maps on their common signals and modes; their node grids must be identical."""
    a, b = _sorted_grid(map_a), _sorted_grid(map_b)
    for dim in _GRID_DIMS:
        if not np.array_equal(a[dim].values, b[dim].values):
            raise ValueError(f"the two maps have different {dim} nodes")
    a, b = xr.align(a, b, join="inner", exclude=list(_GRID_DIMS))
    if not (a.sizes["signal"] and a.sizes["mode"]):
        raise ValueError("the two maps share no signal and mode")
    return a, b


def _difference(map_a: xr.Dataset, map_b: xr.Dataset) -> xr.DataArray:
    """``map_b − map_a`` map value [m]; NaN unless the node is non-empty in both."""
    return _shown(map_b, "value_m") - _shown(map_a, "value_m")


def _difference_figure(map_a: xr.Dataset, map_b: xr.Dataset, *, title: str,
                       units: str) -> Figure:
    """Figure of :func:`plot_map_difference` (kept open for the caller)."""
    a, b = _common_maps(map_a, map_b)
    diff = _difference(a, b) * _unit_factor(units)
    keep = _unique_nodes(a)
    limit = _robust_limit(diff, keep)
    fig, axes = _panel_grid(a, _heading(title, "difference of two code-bias maps (second − "
                                        "first)"), "drawn: nodes non-empty in both maps")
    _draw_maps(fig, axes, a, diff, mcolors.Normalize(-limit, limit), "RdBu_r",
               f"difference [{units}]")
    for row, signal in enumerate(a.signal.values):
        for col, mode in enumerate(a.mode.values):
            mean, rms, n = _difference_stats(diff.sel(signal=signal, mode=mode), keep)
            axes[row, col].set_title(f"{signal}, mode {mode}: mean {mean:+.2f}, "
                                     f"RMS {rms:.2f} {units}\n({n} common nodes)", fontsize=8)
    return fig


def plot_map_difference(map_a: xr.Dataset, map_b: xr.Dataset, path, *, title: str = "",
                        units: str = "cm") -> None:
    """Polar maps of ``map_b − map_a`` per common signal and mode, with mean and RMS per panel.

    Only nodes that are non-empty in both maps are drawn and enter the statistics; the panel
    title gives the mean difference and the RMS about it (``sqrt(mean((d − mean(d))**2))``,
    which ignores the constant offset a map datum choice can leave), counting the zenith node
    once, as :func:`leopod.codebias.products.map_difference` does (same sign, ``b − a``).
    Layout, orientation and colour scaling as in :func:`plot_code_bias_maps`.

    Parameters
    ----------
    map_a, map_b : xarray.Dataset
        Map Datasets of :mod:`leopod.codebias` on the same node grid (e.g. an earlier and a
        later period): ``value_m`` and
        ``empty`` (signal, mode, elevation_deg, azimuth_deg), ``value_m`` [m]. Signals and
        modes are matched by label; only the common ones are drawn.
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title (e.g. the two periods).
    units : {"cm", "m", "mm"}
        Display unit of the differences.

    Raises
    ------
    ValueError
        If the node grids differ or the maps share no signal and mode.
    """
    save_figure(_difference_figure(map_a, map_b, title=title, units=units), path)
