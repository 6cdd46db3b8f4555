"""Code-bias map products: the map dataset, multipath statistics, stacking and differences.

Map dataset (one file per satellite and period, ``results/<campaign>/code_bias/<sat>/<period>.nc``):

- coordinates ``signal`` (RINEX 3 codes), ``mode`` (attitude mode), ``elevation_deg`` (rings
  and the zenith, whose row repeats the single zenith node for every azimuth), ``azimuth_deg``
  (0° = +X, the flight direction, towards +Y);
- ``value_m``, ``sigma_m``, ``count``, ``empty`` on (signal, mode, elevation_deg, azimuth_deg):
  node value and formal sigma [m] (NaN where empty), observations touching the node, and
  ``count < min_count``;
- multipath statistics on (signal, el_band_deg): RMS and mean before and after the correction
  per elevation band, over the observations whose interpolation cell has no empty node (the
  ones the map corrects), each pass's mean removed; overall RMS per signal and the fraction of
  observations the map covers.

Datum: each map has a zero count-weighted mean over its estimated nodes (:mod:`leopod.codebias.estimate`); a
constant is not observable, so comparisons remove the mean difference over the common nodes.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from leopod.codebias.estimate import MapFit, MapSettings, band_index
from leopod.codebias.grid import AntennaGrid
from leopod.codebias.samples import MpSamples

__all__ = ["MpStatistics", "grid_of", "map_dataset", "map_difference", "mp_statistics",
           "node_vector", "stack_maps", "statistics_csv"]


class MpStatistics:
    """Multipath of one signal before and after its map correction (flat arrays).

    Attributes
    ----------
    el_deg, before_m, after_m : ndarray, shape (n,)
        Antenna elevation [deg] and pass-centred multipath [m] of the covered observations.
    n_total : int
        Observations of the signal (covered or not).
    """

    def __init__(self, el_deg, before_m, after_m, n_total):
        self.el_deg, self.before_m, self.after_m = el_deg, before_m, after_m
        self.n_total = n_total

    def bands(self, band_width_deg: float) -> dict[str, np.ndarray]:
        """RMS and mean per elevation band [m] (NaN for empty bands)."""
        n_bands = int(np.ceil(90.0 / band_width_deg))
        b = band_index(self.el_deg, band_width_deg)
        out = {}
        for name, x in (("before", self.before_m), ("after", self.after_m)):
            cnt = np.bincount(b, minlength=n_bands).astype(float)
            s1 = np.bincount(b, weights=x, minlength=n_bands)
            s2 = np.bincount(b, weights=x**2, minlength=n_bands)
            with np.errstate(invalid="ignore", divide="ignore"):
                out[f"mean_{name}"] = np.where(cnt > 0, s1 / cnt, np.nan)
                out[f"rms_{name}"] = np.where(cnt > 0, np.sqrt(s2 / cnt), np.nan)
        return out


def grid_of(maps: xr.Dataset) -> AntennaGrid:
    """The grid of a map dataset."""
    return AntennaGrid(float(maps.attrs["az_step_deg"]), float(maps.attrs["el_step_deg"]))


def _centred(x: np.ndarray, key: np.ndarray) -> np.ndarray:
    _, p = np.unique(key, return_inverse=True)
    mean = np.bincount(p, weights=x) / np.bincount(p)
    return x - mean[p]


def mp_statistics(samples: MpSamples, node_values: np.ndarray, grid: AntennaGrid
                  ) -> MpStatistics:
    """Multipath before and after subtracting the map, over the observations it covers.

    Parameters
    ----------
    samples : MpSamples
        Observations of one signal and attitude mode.
    node_values : ndarray, shape (n_nodes,)
        Map with empty nodes NaN [m].
    grid : AntennaGrid
    """
    corr = grid.interpolate(node_values, samples.az_deg, samples.el_deg)
    ok = np.isfinite(corr) & np.isfinite(samples.mp_m)
    key = samples.pass_key[ok]
    return MpStatistics(samples.el_deg[ok], _centred(samples.mp_m[ok], key),
                        _centred(samples.mp_m[ok] - corr[ok], key), int(samples.mp_m.size))


def _merge_statistics(parts: list[MpStatistics]) -> MpStatistics:
    return MpStatistics(*(np.concatenate([getattr(p, f) for p in parts])
                          for f in ("el_deg", "before_m", "after_m")),
                        sum(p.n_total for p in parts))


def map_dataset(fits: dict[tuple[str, int], MapFit], stats: dict[tuple[str, int], MpStatistics],
                settings: MapSettings, *, period: str, satellite: str
                ) -> tuple[xr.Dataset, dict[str, MpStatistics]]:
    """Assemble the map dataset (module docstring) from the fits per (signal, mode).

    Returns
    -------
    maps : xarray.Dataset
    stats_by_signal : dict
        Statistics of each signal over all modes (for figures).
    """
    grid = settings.grid
    signals = sorted({s for s, _ in fits})
    modes = sorted({m for _, m in fits})
    shape = (len(signals), len(modes), grid.n_rings + 1, grid.n_az)
    value, sigma = np.full(shape, np.nan), np.full(shape, np.nan)
    count = np.zeros(shape, dtype=np.int64)
    for (s, m), fit in fits.items():
        i, j = signals.index(s), modes.index(m)
        empty = fit.empty(settings.min_count)
        value[i, j] = grid.to_grid(np.where(empty, np.nan, fit.value_m))
        sigma[i, j] = grid.to_grid(np.where(empty, np.nan, fit.sigma_m))
        count[i, j] = grid.to_grid(fit.count)
    dims = ("signal", "mode", "elevation_deg", "azimuth_deg")
    band_width = settings.band_width_deg
    bands = np.arange(int(np.ceil(90.0 / band_width))) * band_width
    per_signal = {s: _merge_statistics([st for (s2, _), st in stats.items() if s2 == s])
                  for s in signals}
    band_vars = {k: np.array([per_signal[s].bands(band_width)[k] for s in signals])
                 for k in ("rms_before", "rms_after", "mean_before", "mean_after")}

    def total_rms(attr):
        return np.array([np.sqrt(np.mean(getattr(per_signal[s], attr)**2))
                         if getattr(per_signal[s], attr).size else np.nan for s in signals])

    covered = np.array([per_signal[s].el_deg.size / max(per_signal[s].n_total, 1)
                        for s in signals])
    ds = xr.Dataset(
        {
            "value_m": (dims, value, {"units": "m", "long_name": "code bias map value "
                                      "(zero count-weighted mean)"}),
            "sigma_m": (dims, sigma, {"units": "m", "long_name": "formal standard deviation"}),
            "count": (dims, count, {"units": "1",
                                    "long_name": "observations with weight on the node"}),
            "empty": (dims, ~np.isfinite(value),
                      {"units": "1", "long_name": f"fewer than {settings.min_count} "
                                                  "observations or not estimated"}),
            "mp_rms_before_m": (("signal", "el_band_deg"), band_vars["rms_before"],
                                {"units": "m", "long_name": "RMS of MP before correction"}),
            "mp_rms_after_m": (("signal", "el_band_deg"), band_vars["rms_after"],
                               {"units": "m", "long_name": "RMS of MP after correction"}),
            "mp_mean_before_m": (("signal", "el_band_deg"), band_vars["mean_before"],
                                 {"units": "m", "long_name": "mean MP before correction"}),
            "mp_mean_after_m": (("signal", "el_band_deg"), band_vars["mean_after"],
                                {"units": "m", "long_name": "mean MP after correction"}),
            "mp_rms_all_before_m": (("signal",), total_rms("before_m"),
                                    {"units": "m", "long_name": "RMS of MP before correction"}),
            "mp_rms_all_after_m": (("signal",), total_rms("after_m"),
                                   {"units": "m", "long_name": "RMS of MP after correction"}),
            "covered_fraction": (("signal",), covered,
                                 {"units": "1", "long_name": "fraction of the MP observations "
                                  "whose cell has no empty node"}),
            "sigma0": (("signal", "mode"),
                       np.array([[fits[(s, m)].sigma0 if (s, m) in fits else np.nan
                                  for m in modes] for s in signals]),
                       {"units": "1", "long_name": "a-posteriori sigma of unit weight"}),
        },
        coords={"signal": signals, "mode": np.array(modes, dtype=np.int64),
                "elevation_deg": ("elevation_deg", grid.elevation_deg,
                                  {"units": "deg", "long_name": "antenna elevation"}),
                "azimuth_deg": ("azimuth_deg", grid.azimuth_deg,
                                {"units": "deg", "long_name": "antenna azimuth from +X"}),
                "el_band_deg": ("el_band_deg", bands,
                                {"units": "deg", "long_name": "lower edge of elevation band"})},
        attrs={"period": period, "satellite": satellite, "az_step_deg": settings.az_step_deg,
               "el_step_deg": settings.el_step_deg, "min_count": settings.min_count,
               "band_width_deg": band_width, "datum": "zero count-weighted mean over the estimated nodes",
               "sign": "corrected code = observed code - value"},
    )
    return ds, per_signal


_NODE_DIMS = ("elevation_deg", "azimuth_deg")


def _node_mean(values: xr.DataArray) -> xr.DataArray:
    """Mean over the finite nodes, the repeated zenith row (the last) counted once."""
    once = xr.ones_like(values.isel({d: 0 for d in values.dims if d not in _NODE_DIMS},
                                    drop=True))
    once[{"elevation_deg": -1, "azimuth_deg": slice(1, None)}] = np.nan
    return (values * once).mean(dim=_NODE_DIMS, skipna=True)


def _aligned(maps: list[xr.Dataset]) -> list[xr.DataArray]:
    """Map values shifted by their mean difference to the first over common nodes."""
    ref = maps[0].value_m
    out = [ref]
    for ds in maps[1:]:
        v = ds.value_m.reindex_like(ref)
        out.append(v - _node_mean(v - ref).fillna(0.0))
    return out


def stack_maps(maps: list[xr.Dataset]) -> xr.Dataset:
    """Stack maps of several periods: inverse-variance mean per node of the aligned maps.

    Parameters
    ----------
    maps : list of xarray.Dataset
        Map datasets on the same grid, signals and modes (those of the first are kept).

    Returns
    -------
    xarray.Dataset
        Map dataset with ``value_m``, ``sigma_m``, ``count`` (sum), ``empty`` (no input map
        has the node), attributes of the first map and ``period`` listing the periods.
    """
    values = _aligned(maps)
    weights = [1.0 / ds.sigma_m.reindex_like(maps[0].sigma_m) ** 2 for ds in maps]
    wsum = sum(w.fillna(0.0) for w in weights)
    vsum = sum((w * v).fillna(0.0) for w, v in zip(weights, values, strict=True))
    have = wsum > 0
    out = maps[0][["value_m", "sigma_m", "count", "empty"]].copy()
    out["value_m"] = (vsum / wsum).where(have)
    out["sigma_m"] = (1.0 / np.sqrt(wsum)).where(have)
    out["count"] = sum(ds["count"].reindex_like(maps[0]["count"], fill_value=0) for ds in maps)
    out["empty"] = ~have
    out.attrs["period"] = " ".join(str(ds.attrs.get("period", "?")) for ds in maps)
    return out


def map_difference(map_a: xr.Dataset, map_b: xr.Dataset) -> tuple[xr.DataArray, xr.DataArray]:
    """Difference ``b − a`` over common non-empty nodes with its mean removed, and its RMS.

    The zenith row repeats one node; it is counted once in the mean and RMS.

    Returns
    -------
    diff : xarray.DataArray (signal, mode, elevation_deg, azimuth_deg) [m]
    rms : xarray.DataArray (signal, mode) [m]
    """
    d = map_b.value_m - map_a.value_m
    d = d - _node_mean(d)
    rms = np.sqrt(_node_mean(d**2))
    d.attrs.update(units="m", long_name="map difference minus its mean")
    rms.attrs.update(units="m", long_name="RMS of the map difference over common nodes")
    return d, rms


def node_vector(maps: xr.Dataset, signal: str, mode: int) -> np.ndarray:
    """Node values (n_nodes,) of one signal and mode [m] (empty nodes NaN)."""
    grid = grid_of(maps)
    return grid.from_grid(maps.value_m.sel(signal=signal, mode=mode).values)



def statistics_csv(maps: xr.Dataset) -> str:
    """Multipath RMS/mean per signal and elevation band before and after, as CSV text [m]."""
    width = float(maps.attrs["band_width_deg"])
    header = ("signal,el_min_deg,el_max_deg,rms_before_m,rms_after_m,reduction_percent,"
              "mean_before_m,mean_after_m")
    lines = [header]

    def row(sig, lo, hi, rb, ra, mb, ma):
        red = 100.0 * (1.0 - ra / rb) if rb > 0 else float("nan")
        return f"{sig},{lo:g},{hi:g},{rb:.4f},{ra:.4f},{red:.1f},{mb:.4f},{ma:.4f}"

    for sig in maps.signal.values:
        s = maps.sel(signal=sig)
        for lo in s.el_band_deg.values:
            b = s.sel(el_band_deg=lo)
            lines.append(row(sig, lo, min(lo + width, 90.0), float(b.mp_rms_before_m),
                             float(b.mp_rms_after_m), float(b.mp_mean_before_m),
                             float(b.mp_mean_after_m)))
        lines.append(row(sig, 0.0, 90.0, float(s.mp_rms_all_before_m),
                         float(s.mp_rms_all_after_m), float("nan"), float("nan")))
    return "\n".join(lines) + "\n"
