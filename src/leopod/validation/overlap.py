"""Orbit overlaps: consistency of consecutive arcs over their common span.

Jiang et al. (2023), "Internal consistency validation" (Fig. 13): each daily arc is extended by 3 h
at both ends, so consecutive 30-h arcs share 6 h (21:00–03:00); the 3D RMS of the differences over
that span, per pair of arcs and averaged over the campaign (mean ± STD), measures the internal
precision of the POD (float and fixed solutions alike: the input is any orbit Dataset).

Conventions
    - Differences are ``orbit_a − orbit_b`` (earlier minus later arc) at the epochs of
      ``orbit_a`` inside the common span; ``orbit_b`` is Lagrange-interpolated there when its
      epochs differ (exact at common nodes, :func:`leopod.validation.compare.interpolate_orbit`).
    - RTN axes are those of the **mean** of the two inertial states. Jiang et al. (2023) does not
      say which axes it uses; the mean makes the overlap symmetric (swapping the arcs only flips the
      sign) and favours neither arc. The choice is immaterial numerically: the axes of the two
      arcs differ by ``|Δr|/|r|`` ≈ 1e-8 rad for cm differences, i.e. < 1e-9 m in the result.
    - Inertial states (GCRF) are used when both orbits carry ``pos_gcrf_m``/``vel_gcrf_m_s``;
      otherwise the ITRF variables are differenced and the axes built from the inertial state
      (:func:`leopod.frames.rtn.rtn_axes`).
    - ``trim_s`` removes that much from both ends of the common span (the arc ends are the
      least determined part of each arc).

Schema of :func:`overlap` (one pair; netCDF with :func:`leopod.io.netcdf.write_netcdf`)
    ``diff_rtn_m`` (time, rtn), ``diff_3d_m`` (time) [m]; ``mean_m``, ``std_m``, ``rms_m``
    (component: R, T, N, 3D) [m]; ``n_epochs`` (scalar); attrs ``arc_a_start``, ``arc_a_end``,
    ``arc_b_start``, ``arc_b_end``, ``span_start``, ``span_end`` (ISO strings), ``trim_s``,
    ``frame``, ``difference``, ``rtn_axes``.
Schema of :func:`overlap_summary` (campaign; CSV through
:func:`leopod.validation.orbit_statistics.statistics_table`)
    dims ``pair`` (str label) and ``component``: ``mean_m``, ``std_m``, ``rms_m`` [m],
    ``n_epochs`` (pair), ``span_start`` (pair); ``campaign_rms_mean_m``, ``campaign_rms_std_m``
    (component): mean and population STD over the pairs of the per-pair RMS [m].
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import xarray as xr

from leopod.frames.rtn import rtn_axes
from leopod.validation.compare import interpolate_orbit
from leopod.validation.orbit_statistics import COMPONENTS, component_statistics

__all__ = ["overlap", "overlap_summary"]

_GCRF = ("pos_gcrf_m", "vel_gcrf_m_s")
_ITRF = ("pos_itrf_m", "vel_itrf_m_s")


def _frame(orbit_a: xr.Dataset, orbit_b: xr.Dataset) -> tuple[str, str, str]:
    if all(name in ds for ds in (orbit_a, orbit_b) for name in _GCRF):
        return ("gcrf", *_GCRF)
    return ("itrf", *_ITRF)


def _iso(t) -> str:
    return str(np.datetime64(t, "ns"))


def _stats_vars(diff_rtn: np.ndarray) -> dict:
    mean, std, rms, n = component_statistics(diff_rtn)
    label = "(3D: of the distance) over the overlap"
    return {"mean_m": (("component",), mean, {"units": "m", "long_name": f"mean {label}"}),
            "std_m": (("component",), std, {"units": "m", "long_name": f"standard deviation "
                                            f"{label}"}),
            "rms_m": (("component",), rms, {"units": "m", "long_name": f"root mean square "
                                            f"{label}"}),
            "n_epochs": ((), np.int64(n), {"units": "1", "long_name": "epochs compared"})}


def overlap(orbit_a: xr.Dataset, orbit_b: xr.Dataset, *, trim_s: float = 0.0, order: int = 10,
            eop=None) -> xr.Dataset:
    """Differences of two arcs over their common span, in RTN, with their statistics.

    Parameters
    ----------
    orbit_a, orbit_b : xarray.Dataset
        Earlier and later arc in the POD orbit schema (``time`` GPS; ``pos_gcrf_m``,
        ``vel_gcrf_m_s`` or ``pos_itrf_m``, ``vel_itrf_m_s`` (time, xyz) [m, m/s]).
    trim_s : float
        Removed from both ends of the common span [s] (>= 0).
    order : int
        Lagrange degree used when ``orbit_b`` must be interpolated to ``orbit_a``'s epochs.
    eop : EarthOrientation, optional
        EOP source, only used for ITRF-only orbits.

    Returns
    -------
    xarray.Dataset
        Schema in the module docstring.

    Raises
    ------
    ValueError
        If the (trimmed) common span is empty.
    """
    if trim_s < 0:
        raise ValueError(f"trim_s must be >= 0, got {trim_s}")
    frame, pos, vel = _frame(orbit_a, orbit_b)
    ta, tb = orbit_a.time.values, orbit_b.time.values
    trim = np.timedelta64(round(trim_s * 1e9), "ns")
    start = max(ta[0], tb[0]) + trim
    end = min(ta[-1], tb[-1]) - trim
    times = ta[(ta >= start) & (ta <= end)]
    if times.size == 0:
        raise ValueError(f"the arcs have no common span (a: {_iso(ta[0])}–{_iso(ta[-1])}, "
                         f"b: {_iso(tb[0])}–{_iso(tb[-1])}, trim {trim_s} s)")
    a = orbit_a.sel(time=times)
    b = interpolate_orbit(orbit_b, times, pos=pos, vel=vel, order=order)
    diff = a[pos].values - b[pos].values
    mean_pos = 0.5 * (a[pos].values + b[pos].values)
    mean_vel = 0.5 * (a[vel].values + b[vel].values)
    ok = np.isfinite(diff).all(axis=1) & np.isfinite(mean_vel).all(axis=1)
    diff_rtn = np.full_like(diff, np.nan)
    if ok.any():
        axes = rtn_axes(times[ok], mean_pos[ok], mean_vel[ok], frame=frame, eop=eop)
        diff_rtn[ok] = np.einsum("nij,nj->ni", axes, diff[ok])
    data = {"diff_rtn_m": (("time", "rtn"), diff_rtn,
                           {"units": "m", "long_name": "orbit a minus orbit b in radial, "
                            "along-track, cross-track"}),
            "diff_3d_m": ("time", np.linalg.norm(diff_rtn, axis=1),
                          {"units": "m", "long_name": "3D distance of the two arcs"}),
            **_stats_vars(diff_rtn)}
    return xr.Dataset(data, coords={"time": times, "rtn": ["R", "T", "N"],
                                    "component": list(COMPONENTS)},
                      attrs={"difference": "orbit_a - orbit_b", "frame": frame,
                             "rtn_axes": "inertial RTN of the mean state of both arcs",
                             "trim_s": float(trim_s),
                             "arc_a_start": _iso(ta[0]), "arc_a_end": _iso(ta[-1]),
                             "arc_b_start": _iso(tb[0]), "arc_b_end": _iso(tb[-1]),
                             "span_start": _iso(times[0]), "span_end": _iso(times[-1])})


def _default_label(ov: xr.Dataset) -> str:
    """GPS date of the middle of the overlap (the day arc b is centred on, e.g. 2023-01-02)."""
    t0 = np.datetime64(ov.attrs["span_start"], "ns")
    t1 = np.datetime64(ov.attrs["span_end"], "ns")
    return str((t0 + (t1 - t0) // 2).astype("datetime64[D]"))


def overlap_summary(overlaps: Sequence[xr.Dataset], labels: Sequence[str] | None = None
                    ) -> xr.Dataset:
    """Per-pair statistics and the campaign mean ± STD of the per-pair RMS (Jiang et al. 2023,
    Fig. 13).

    Parameters
    ----------
    overlaps : sequence of xarray.Dataset
        Results of :func:`overlap` (or files written from them), in campaign order.
    labels : sequence of str, optional
        One label per pair; default the GPS date of the middle of each overlap.

    Returns
    -------
    xarray.Dataset
        Schema in the module docstring. Pairs without any compared epoch have NaN statistics
        and are left out of the campaign values.
    """
    if len(overlaps) == 0:
        raise ValueError("no overlaps to summarise")
    if labels is None:
        labels = [_default_label(ov) for ov in overlaps]
    if len(labels) != len(overlaps):
        raise ValueError(f"{len(labels)} labels for {len(overlaps)} overlaps")
    stack = {name: np.stack([ov[name].sel(component=list(COMPONENTS)).values
                             for ov in overlaps]) for name in ("mean_m", "std_m", "rms_m")}
    rms = stack["rms_m"]
    good = np.isfinite(rms).all(axis=1)
    if good.any():
        camp_mean, camp_std = rms[good].mean(axis=0), rms[good].std(axis=0)
    else:
        camp_mean = camp_std = np.full(len(COMPONENTS), np.nan)
    data = {name: (("pair", "component"), values, dict(overlaps[0][name].attrs))
            for name, values in stack.items()}
    data["n_epochs"] = ("pair", np.array([int(ov.n_epochs) for ov in overlaps], dtype=np.int64),
                        {"units": "1", "long_name": "epochs compared"})
    data["span_start"] = ("pair", np.array([np.datetime64(ov.attrs["span_start"], "ns")
                                            for ov in overlaps]),
                          {"long_name": "first compared epoch (GPS time)"})
    data["campaign_rms_mean_m"] = ("component", camp_mean, {
        "units": "m", "long_name": "mean over the pairs of the per-pair RMS"})
    data["campaign_rms_std_m"] = ("component", camp_std, {
        "units": "m", "long_name": "standard deviation over the pairs of the per-pair RMS"})
    return xr.Dataset(data, coords={"pair": [str(s) for s in labels],
                                    "component": list(COMPONENTS)},
                      attrs={"n_pairs_used": int(good.sum())})
