"""Ingest: raw files -> canonical observation, GNSS-product and a-priori LEO orbit Datasets.

* :func:`canonical_observations` keeps the configured GNSS and signals of a RINEX file, maps
  RINEX 2 names to RINEX 3 codes (:mod:`leopod.signals`), converts phase to metres and the
  epochs to GPS time (BDT and GST files, :func:`leopod.time.scales.to_gps_time`), and drops
  BDS GEO satellites when the campaign says so, so every later step sees one schema
  whatever the input version and time system.
* :func:`gnss_at_epochs` evaluates the precise GNSS orbits (Lagrange) at the observation
  epochs and keeps the clock product's values at its own epochs only.
* :func:`apriori_from_spp` makes the a-priori LEO orbit from a code-only kinematic solution
  (:mod:`leopod.gnss.spp`) reduced to the centre of mass and smoothed;
  :func:`apriori_from_sp3` reads it from an orbit file instead.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping

import numpy as np
import xarray as xr

from leopod import signals
from leopod.astro.sun import sun_position_ef
from leopod.constants import C_LIGHT_M_S
from leopod.frames.attitude import body_to_ef
from leopod.frames.leo_attitude import LeoAttitude, leo_body_axes_ef
from leopod.gnss.attitude import satellite_pco_if
from leopod.gnss.combinations import ionosphere_free
from leopod.gnss.products import GnssProducts
from leopod.gnss.spp import solve_spp
from leopod.numerics.interpolate import interpolate_table
from leopod.numerics.smoothing import savitzky_golay
from leopod.signals import SystemSignals
from leopod.time.calendar import seconds_since
from leopod.time.scales import to_gps_time

__all__ = ["canonical_observations", "gnss_at_epochs", "apriori_from_spp", "apriori_from_sp3",
           "smooth_positions"]

log = logging.getLogger(__name__)


def _source_name(raw: xr.Dataset, system: str, code: str) -> str | None:
    """Name of the raw variable that holds RINEX 3 ``code`` for ``system`` (None if absent)."""
    if float(raw.attrs.get("rinex_version", 3.0)) >= 3.0:
        return code if code in raw else None
    for name in raw.data_vars:
        if len(name) == 2 and signals.RINEX2_TO_RINEX3.get(system, {}).get(name) == code:
            return name
    return None


def canonical_observations(raw: xr.Dataset, signal_cfg: Mapping[str, SystemSignals]
                           ) -> xr.Dataset:
    """Canonical observation Dataset for the configured systems and signals.

    Parameters
    ----------
    raw : xarray.Dataset
        Output of :func:`leopod.io.rinex_obs.read_rinex_obs` (phase in cycles).
    signal_cfg : mapping of str to SystemSignals
        ``{system: {"phase": [...], "code": [...], "pod_code": [...]}}`` (campaign config).

    Returns
    -------
    xarray.Dataset
        Dims ``(time, sv)``; ``time`` in GPS time (datetime64[ns]); one float64 variable per
        RINEX 3 code in metres (phase converted with the band's wavelength, recorded in the
        ``wavelength_m`` attribute), int8 ``<code>_lli`` and ``<code>_ssi`` where the file
        has them. Satellites of other systems, and GEO satellites of systems with
        ``exclude_geo``, are dropped; epochs without any configured observation are dropped.
        Attributes: those of ``raw``, with ``time_system = "GPS"``, ``time_system_file``
        (the file's own, e.g. ``"BDT"``) and ``excluded_geo`` (space-joined ids dropped).

    Raises
    ------
    ValueError
        If a configured signal is in no satellite of the file (names the file and signal),
        or the file's time system is not convertible to GPS time (GLONASS, QZSS, IRNSS:
        names the file, the line and the field 'TIME OF FIRST OBS').
    """
    fname = raw.attrs.get("filename", "observation file")
    times = _gps_epochs(raw, fname)
    sv_all = np.array([str(s) for s in raw.sv.values])
    geo = np.array([signals.is_geo(s) and s[0] in signal_cfg and signal_cfg[s[0]].exclude_geo
                    for s in sv_all], dtype=bool)
    if geo.any():
        log.info("%s: BDS GEO satellites excluded by configuration: %s", fname,
                 " ".join(sv_all[geo]))
    keep_sv = np.array([s[0] in signal_cfg for s in sv_all], dtype=bool) & ~geo
    sv = sv_all[keep_sv]
    n = raw.sizes["time"]
    out: dict[str, xr.Variable] = {}
    for system, cfg in signal_cfg.items():
        cols = np.array([s[0] == system for s in sv])
        if not cols.any():
            log.warning("%s: no %s satellites in the file", fname, signals.SYSTEMS[system])
            continue
        for code in cfg.observations:
            src = _source_name(raw, system, code)
            if src is None:
                raise ValueError(f"{fname}: field '{code}': configured signal {code} of "
                                 f"{signals.SYSTEMS[system]} is not in the file "
                                 f"(observation types: {' '.join(map(str, raw.data_vars))})")
            values = raw[src].values[:, keep_sv][:, cols]
            attrs = {"units": "m", "system": system, "rinex_name": src,
                     "frequency_hz": signals.frequency_hz(system, code)}
            if code[0] == "L":
                lam = signals.wavelength_m(system, code)
                values = values * lam
                attrs.update(long_name=f"carrier phase {code} [m]", wavelength_m=lam)
            else:
                attrs.update(long_name=f"pseudorange {code}")
            _put(out, code, values, cols, n, len(sv), np.nan, np.float64, attrs)
            for ind in ("lli", "ssi"):
                if f"{src}_{ind}" in raw:
                    ind_vals = raw[f"{src}_{ind}"].values[:, keep_sv][:, cols]
                    _put(out, f"{code}_{ind}", ind_vals, cols, n, len(sv), -1, np.int8,
                         {"units": "1", "long_name": f"RINEX {'loss-of-lock' if ind == 'lli' else 'signal-strength'} indicator of {code}"})
    ds = xr.Dataset(out, coords={"time": times, "sv": sv})
    has_data = np.zeros(n, dtype=bool)
    for name, var in ds.data_vars.items():
        if var.dtype.kind == "f":
            has_data |= np.isfinite(var.values).any(axis=1)
    ds = ds.isel(time=np.nonzero(has_data)[0])
    ds.attrs = {k: v for k, v in raw.attrs.items() if isinstance(v, (str, int, float))}
    ds.attrs.update(systems=" ".join(signal_cfg), time_system="GPS",
                    time_system_file=str(raw.attrs.get("time_system", "GPS")),
                    excluded_geo=" ".join(sv_all[geo]))
    return ds


def _gps_epochs(raw: xr.Dataset, fname: str) -> np.ndarray:
    """The epochs of a read RINEX file in GPS time (exact integer-nanosecond offsets).

    Raises
    ------
    ValueError
        Naming the file, the line of TIME OF FIRST OBS (or "default" when the system's
        default applied) and the field, for a time system that has no conversion.
    """
    system = str(raw.attrs.get("time_system", "GPS"))
    try:
        times = to_gps_time(raw.time.values, system)
    except ValueError as err:
        line = int(raw.attrs.get("time_system_line", 0))
        where = f"{fname}:{line}" if line else f"{fname} (default of the file's system)"
        raise ValueError(f"{where}: field 'TIME OF FIRST OBS time system': {err}; only GPS, "
                         "GAL and BDT observation files can be ingested") from None
    if system != "GPS":
        log.info("%s: epochs converted from %s to GPS time", fname, system)
    return times


def _put(out, name, values, cols, n, s, fill, dtype, attrs):
    """Write ``values`` into the columns ``cols`` of variable ``name`` (created if needed)."""
    if name not in out:
        out[name] = xr.Variable(("time", "sv"), np.full((n, s), fill, dtype=dtype), attrs)
    out[name].values[:, cols] = values


def gnss_at_epochs(products: GnssProducts, times: np.ndarray) -> xr.Dataset:
    """GNSS orbits at observation epochs and clocks at the product's own epochs.

    Parameters
    ----------
    products : GnssProducts
    times : ndarray of datetime64[ns], shape (n,)

    Returns
    -------
    xarray.Dataset
        ``pos_m``, ``vel_m_s`` (time, sv, xyz) Earth-fixed centre of mass; ``clk_s`` (time, sv)
        exact product values at coinciding epochs, NaN elsewhere; ``extrapolated`` (time, sv)
        1 where the orbit was extrapolated beyond the product table.
    """
    t = seconds_since(times, products.ref)
    n, s = len(t), len(products.sv)
    isv = np.tile(np.arange(s), n)
    tt = np.repeat(t, s)
    pos, vel, extra = products.position(isv, tt)
    ds = xr.Dataset(
        {
            "pos_m": (("time", "sv", "xyz"), pos.reshape(n, s, 3),
                      {"units": "m", "long_name": "GNSS satellite centre-of-mass position (Earth-fixed)"}),
            "vel_m_s": (("time", "sv", "xyz"), vel.reshape(n, s, 3),
                        {"units": "m s-1", "long_name": "GNSS satellite velocity (Earth-fixed)"}),
            "clk_s": (("time", "sv"), products.clock_at_samples(t),
                      {"units": "s", "long_name": "GNSS satellite clock offset (product epochs only)"}),
            "extrapolated": (("time", "sv"), extra.reshape(n, s).astype(np.int8),
                             {"units": "1", "long_name": "1 where the orbit is extrapolated beyond the product"}),
        },
        coords={"time": times, "sv": products.sv, "xyz": ["x", "y", "z"]},
    )
    return ds


def smooth_positions(t_s: np.ndarray, pos_m: np.ndarray, *, window_s: float = 200.0,
                     polyorder: int = 5, max_fill_s: float = 300.0):
    """Smooth a kinematic position series and differentiate it (Savitzky–Golay).

    Parameters
    ----------
    t_s : ndarray, shape (n,)
        Epochs [s]; assumed on a regular grid with gaps (missing epochs may be NaN rows).
    pos_m : ndarray, shape (n, 3)
        Positions [m], NaN where unsolved.
    window_s : float
        Length of the local polynomial window [s]; at least 11 samples are used.
    polyorder : int
        Degree of the local polynomial.
    max_fill_s : float
        NaN gaps up to this length are bridged by cubic interpolation before smoothing [s].

    Returns
    -------
    pos, vel : ndarray, shape (n, 3)
        Smoothed position [m] and velocity [m/s]; NaN in gaps longer than ``max_fill_s`` and
        in segments shorter than the window.
    """
    from scipy.interpolate import CubicSpline

    dt = float(np.median(np.diff(t_s)))
    ok = np.isfinite(pos_m).all(axis=1)
    filled = pos_m.copy()
    if ok.sum() >= 4:
        spline = CubicSpline(t_s[ok], pos_m[ok], axis=0, extrapolate=False)
        tv = t_s[ok]
        j = np.searchsorted(tv, t_s)
        prev_t = tv[np.clip(j - 1, 0, len(tv) - 1)]
        next_t = tv[np.clip(j, 0, len(tv) - 1)]
        bridge = ~ok & (next_t - prev_t <= max_fill_s) & (t_s > tv[0]) & (t_s < tv[-1])
        filled[bridge] = spline(t_s[bridge])
    good = np.isfinite(filled).all(axis=1)
    pos = np.full(pos_m.shape, np.nan)
    vel = np.full(pos_m.shape, np.nan)
    win = max(int(round(window_s / dt)), 11) | 1
    # contiguous segments on the grid
    breaks = np.nonzero(~good[1:] | ~good[:-1] | ~np.isclose(np.diff(t_s), dt))[0] + 1
    for seg in np.split(np.arange(len(t_s)), breaks):
        seg = seg[good[seg]]
        if seg.size < max(win, polyorder + 2):
            continue
        pos[seg] = savitzky_golay(filled[seg], win, polyorder)
        vel[seg] = savitzky_golay(filled[seg], win, polyorder, deriv=1, delta=dt)
    return pos, vel


def apriori_from_spp(obs: xr.Dataset, products: GnssProducts,
                     signal_cfg: Mapping[str, SystemSignals],
                     pco_body_m: dict | None = None, antex=None,
                     attitude: LeoAttitude | None = None) -> xr.Dataset:
    """A-priori LEO orbit from code-only single point positioning.

    The ionosphere-free combination of the ``pod_code`` pair of each system is positioned
    epoch by epoch; the antenna position is reduced to the centre of mass with the
    ionosphere-free phase-centre offset rotated by the satellite's attitude law, smoothed, and
    moved from the true reception time to the nominal epoch with the receiver clock.

    Parameters
    ----------
    obs : xarray.Dataset
        Canonical observations.
    products : GnssProducts
    signal_cfg : mapping of str to SystemSignals
        Campaign signals (only GPS is used for now: one receiver clock, one system).
    pco_body_m : dict, optional
        Antenna phase-centre offsets in the body frame per band name (``{"L1": [x, y, z]}``).
    antex : leopod.io.antex.AntexFile, optional
        GNSS satellite antenna offsets; without it the transmitters' centres of mass are used
        (metre-level errors for satellites with large offsets).
    attitude : LeoAttitude, optional
        Attitude law of the LEO (:mod:`leopod.frames.leo_attitude`); None: nominal.

    Returns
    -------
    xarray.Dataset
        ``pos_m``, ``vel_m_s`` (time, xyz) Earth-fixed centre of mass; ``clk_rx_m``, ``n_sv``,
        ``rms_m``, ``pdop`` (time); attrs ``apriori_source = "spp"``.
    """
    system = "G" if "G" in signal_cfg else next(iter(signal_cfg))
    c1, c2 = signal_cfg[system].pod_code
    f1, f2 = signals.frequency_hz(system, c1), signals.frequency_hz(system, c2)
    cols = np.array([str(s).startswith(system) for s in obs.sv.values])
    code_if = ionosphere_free(obs[c1].values[:, cols], obs[c2].values[:, cols], f1, f2)
    t = seconds_since(obs.time.values, products.ref)
    sv = obs.sv.values[cols]
    sat_pco = sun = None
    if antex is not None:
        sat_pco = satellite_pco_if(antex, sv, obs.time.values[len(t) // 2], system,
                                   (signals.code_band(c1), signals.code_band(c2)), f1, f2)
        missing = [str(s) for s, p in zip(sv, sat_pco) if not np.isfinite(p).all()]
        if missing:
            log.warning("no ANTEX entry for %s: not used in the code-only orbit", " ".join(missing))
            code_if[:, ~np.isfinite(sat_pco).all(axis=1)] = np.nan
        sat_pco = np.nan_to_num(sat_pco)
        sun = sun_position_ef(obs.time.values)
    spp = solve_spp(t, sv, code_if, products, sat_pco_body_m=sat_pco, sun_ef_m=sun)
    dt_rx_s = spp.clk_rx_m / C_LIGHT_M_S
    # first pass: velocity for the attitude; then reduce to the centre of mass
    pos_s, vel_s = smooth_positions(t, spp.pos_m)
    pco_if = np.zeros(3)
    if pco_body_m:
        b1, b2 = signals.band(system, c1).name, signals.band(system, c2).name
        if b1 in pco_body_m and b2 in pco_body_m:
            pco_if = ionosphere_free(np.array(pco_body_m[b1]), np.array(pco_body_m[b2]), f1, f2)
        else:
            log.warning("no antenna offset for %s/%s: a-priori orbit is the antenna position", b1, b2)
    rot = leo_body_axes_ef(attitude, obs.time.values, pos_s, vel_s)
    com = spp.pos_m - body_to_ef(rot, pco_if)
    # the solution refers to the true reception time t - dt_rx; move it to the nominal epoch
    com = com + vel_s * dt_rx_s[:, None]
    # robust smoothing: drop kinematic epochs far from a first smooth fit, then fit again
    first, _ = smooth_positions(t, com)
    dist = np.linalg.norm(com - first, axis=1)
    limit = max(5.0 * float(np.nanmedian(dist)), 1.0) if np.isfinite(dist).any() else np.inf
    outlying = dist > limit
    log.info("code-only orbit: %d epochs farther than %.1f m from the smooth fit rejected",
             int(outlying.sum()), limit)
    pos, vel = smooth_positions(t, np.where(outlying[:, None], np.nan, com))
    ds = xr.Dataset(
        {
            "pos_m": (("time", "xyz"), pos, {"units": "m", "long_name": "a-priori LEO centre-of-mass position (Earth-fixed)"}),
            "vel_m_s": (("time", "xyz"), vel, {"units": "m s-1", "long_name": "a-priori LEO velocity (Earth-fixed)"}),
            "pos_kinematic_m": (("time", "xyz"), com, {"units": "m", "long_name": "unsmoothed code-only kinematic centre-of-mass position"}),
            "clk_rx_m": (("time",), spp.clk_rx_m, {"units": "m", "long_name": "receiver clock offset times c (code-only)"}),
            "n_sv": (("time",), spp.n_used.astype(np.int16), {"units": "1", "long_name": "satellites used in the code-only solution"}),
            "rms_m": (("time",), spp.rms_m, {"units": "m", "long_name": "RMS of code-only post-fit residuals"}),
            "pdop": (("time",), spp.pdop, {"units": "1", "long_name": "position dilution of precision"}),
        },
        coords={"time": obs.time.values, "xyz": ["x", "y", "z"]},
    )
    ds.attrs.update({"apriori_source": "spp", "spp_system": system, "spp_codes": f"{c1} {c2}",
                     "gnss_antenna_offsets": "ANTEX" if antex is not None else "none",
                     "antenna_pco_if_body_m": " ".join(f"{v:.4f}" for v in pco_if)})
    return ds


def apriori_from_sp3(orbit: xr.Dataset, sat_id: str | None, times: np.ndarray) -> xr.Dataset:
    """A-priori LEO orbit interpolated from an SP3 Dataset at the observation epochs.

    Raises
    ------
    ValueError
        If ``sat_id`` is not in the file or the file holds several satellites and no id is given.
    """
    ids = [str(s) for s in orbit.sv.values]
    if sat_id is None:
        if len(ids) != 1:
            raise ValueError(f"{orbit.attrs.get('filename')}: field 'sv': several satellites "
                             f"({' '.join(ids)}); set sp3_id in the config")
        sat_id = ids[0]
    if sat_id not in ids:
        raise ValueError(f"{orbit.attrs.get('filename')}: field 'sv': {sat_id} not in the file")
    ref = times[0]
    tn = seconds_since(orbit.time.values, ref)
    pos_tab = orbit.pos_m.sel(sv=sat_id).values
    good = np.isfinite(pos_tab).all(axis=1)
    t = seconds_since(times, ref)
    pos, vel = interpolate_table(tn[good], pos_tab[good], t, order=8,
                                 max_gap_s=4 * float(np.median(np.diff(tn))))
    ds = xr.Dataset(
        {
            "pos_m": (("time", "xyz"), pos, {"units": "m", "long_name": "a-priori LEO centre-of-mass position (Earth-fixed)"}),
            "vel_m_s": (("time", "xyz"), vel, {"units": "m s-1", "long_name": "a-priori LEO velocity (Earth-fixed)"}),
        },
        coords={"time": times, "xyz": ["x", "y", "z"]},
    )
    ds.attrs.update({"apriori_source": "sp3", "sp3_id": sat_id})
    return ds
