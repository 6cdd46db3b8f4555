"""Data-quality indicators of onboard GNSS observations (Wang et al. 2024, Table 2;
Peng et al. 2021, sec. II-B).

Input is the canonical observation Dataset written by the ingest step (codes and phases in
metres, RINEX 3 codes as variable names) plus the antenna-frame angles of every observation.
Output is one Dataset per satellite and day with per-observation series (pass, MP, code
noise, IOD), per-GNSS-satellite statistics and the daily indicators:

* satellites tracked per epoch and its histogram (Wang et al. 2024, Fig. 3);
* data completeness: epochs with any observation / epochs expected over the day at the file's
  interval; utilisation: satellite-epochs with all configured codes and both phases / all
  observed satellite-epochs (Wang et al. 2024, sec. 3.1.2, read at the level of satellite-epochs);
* code multipath MP_i (Peng et al. 2021, eq. 1) minus its pass mean, RMS per satellite and per day,
  formed without the per-frequency antenna range terms when they are given
  (:mod:`leopod.gnss.antenna_terms`: the code-bias maps then hold no antenna term);
* observations per cycle slip ("o/slps", Wang et al. 2024, Table 2): satellite-epochs with phase
  divided by the slips detected inside continuous tracking (starts of tracking and gaps are
  not slips);
* ionospheric delay rate IOD on L1 [m/min] (Wang et al. 2024, eq. 15) and the fraction above a
  limit;
* code noise after Peng et al. (2021) sec. II-B: code minus carrier on the same frequency,
  differenced between adjacent epochs of a pass, and the STD of that series in a sliding window
  (2 min); the histogram peak, minimum and 90th percentile of the window STDs are what
  Peng et al. (2021) quotes (C1 0.46–0.50 m, P1 0.09–0.10 m, P2 0.02–0.03 m for HY-2B). The STD is
  of the epoch differences themselves (not divided by √2), as in the paper.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import xarray as xr

from leopod import signals
from leopod.gnss.antenna_terms import remove_antenna_terms
from leopod.gnss.combinations import ionosphere_l1_m, multipath
from leopod.gnss.passes import FLAG_GAP, FLAG_NEW, PassResult, detect_passes
from leopod.numerics.statistics import finite_rms
from leopod.settings import Settings

__all__ = ["QualitySettings", "assess_quality", "merge_systems", "sliding_std"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class QualitySettings(Settings):
    """Tunables of the quality step (see the config schema for meanings and units)."""

    SCHEMA_DEF = "quality"

    elevation_mask_deg: float
    max_gap_s: float
    min_pass_s: float
    slip_mw_threshold_cyc: float
    slip_gf_threshold_m: float
    noise_window_s: float
    iod_threshold_m_min: float


def sliding_std(t_s: np.ndarray, x: np.ndarray, window_s: float, min_count: int) -> np.ndarray:
    """Standard deviation of ``x`` in a centred sliding time window.

    Parameters
    ----------
    t_s : ndarray, shape (n,)
        Epochs [s], increasing.
    x : ndarray, shape (n,)
        Series (NaN = no value).
    window_s : float
        Window length [s] (centred: ``|t - t_k| <= window_s / 2``).
    min_count : int
        Minimum number of values in the window, else NaN.

    Returns
    -------
    ndarray, shape (n,)
        Sample standard deviation (ddof=1) at each epoch with a value.
    """
    ok = np.isfinite(x)
    tv, xv = t_s[ok], x[ok]
    out = np.full(len(x), np.nan)
    if tv.size < max(min_count, 2):
        return out
    lo = np.searchsorted(tv, tv - window_s / 2, side="left")
    hi = np.searchsorted(tv, tv + window_s / 2, side="right")
    c1 = np.concatenate([[0.0], np.cumsum(xv)])
    c2 = np.concatenate([[0.0], np.cumsum(xv * xv)])
    cnt = hi - lo
    s1 = c1[hi] - c1[lo]
    s2 = c2[hi] - c2[lo]
    with np.errstate(invalid="ignore", divide="ignore"):
        var = (s2 - s1 * s1 / cnt) / (cnt - 1)
    std = np.sqrt(np.clip(var, 0.0, None))
    std[cnt < min_count] = np.nan
    out[np.nonzero(ok)[0]] = std
    return out


def _pass_mean_removed(values: np.ndarray, pass_id: np.ndarray, keep: np.ndarray) -> np.ndarray:
    """Subtract the mean of each pass (over ``keep`` epochs) from ``values``."""
    out = np.full(values.shape, np.nan)
    sel = keep & np.isfinite(values) & (pass_id >= 0)
    ids = pass_id[sel]
    if ids.size == 0:
        return out
    sums = np.bincount(ids, weights=values[sel])
    counts = np.bincount(ids)
    means = np.divide(sums, counts, out=np.full(sums.shape, np.nan), where=counts > 0)
    out[sel] = values[sel] - means[ids]
    return out


def _pass_durations(t_s: np.ndarray, pass_id: np.ndarray) -> np.ndarray:
    """Duration [s] of the pass each observation belongs to (NaN where no pass)."""
    out = np.full(pass_id.shape, np.nan)
    sel = pass_id >= 0
    if not sel.any():
        return out
    tt = np.broadcast_to(t_s[:, None], pass_id.shape)[sel]
    ids = pass_id[sel]
    n = ids.max() + 1
    t_min = np.full(n, np.inf)
    t_max = np.full(n, -np.inf)
    np.minimum.at(t_min, ids, tt)
    np.maximum.at(t_max, ids, tt)
    out[sel] = (t_max - t_min)[ids]
    return out


def assess_quality(obs: xr.Dataset, el_deg: np.ndarray, az_deg: np.ndarray, system: str,
                   phase: list[str], codes: list[str], pod_code: list[str],
                   settings: QualitySettings, *, antenna: xr.Dataset | None = None
                   ) -> xr.Dataset:
    """Compute the quality indicators of one satellite-day for one GNSS.

    Parameters
    ----------
    obs : xarray.Dataset
        Canonical observations (dims time, sv) with code and phase variables in metres named
        by RINEX 3 codes and ``<phase>_lli`` indicators.
    el_deg, az_deg : ndarray, shape (n, s)
        Antenna-frame elevation and azimuth of each observation [deg].
    system : str
        GNSS letter; only satellites of this system are assessed.
    phase : list of str
        The two phase codes (frequency 1, frequency 2), e.g. ``["L1C", "L2W"]``.
    codes : list of str
        Codes to assess (MP, noise), e.g. ``["C1C", "C1W", "C2W"]``.
    pod_code : list of str
        The two codes for the MW combination, e.g. ``["C1W", "C2W"]``.
    settings : QualitySettings
    antenna : xarray.Dataset, optional
        Antenna range terms per band (``antenna_range_<digit>_m`` on (time, sv),
        :func:`leopod.gnss.antenna_terms.antenna_terms`), removed from the codes and phases
        of the multipath combinations, so that MP (and the code-bias maps estimated from it)
        is free of the frequency-dependent PCO/PCV; None: raw observations. The terms and
        their ``antenna_*`` attributes are kept in the output (for the ambiguity step and the
        code-bias maps). Code noise (code minus phase of one band) does not see them; the
        slip detection uses raw observations (the terms vary slowly).

    Returns
    -------
    xarray.Dataset
        Per-observation series (time, sv), per-satellite statistics ``sv_*`` (sv), the
        histogram ``<system>_epochs_per_n_sats`` (n_sats) and daily indicators as scalars
        named ``<system>_<indicator>`` (see module docstring); every variable has ``units``
        and ``long_name``.
    """
    sel = np.array([str(s).startswith(system) for s in obs.sv.values])
    obs = obs.isel(sv=np.nonzero(sel)[0])
    el_deg, az_deg = el_deg[:, sel], az_deg[:, sel]
    t_s = (obs.time.values - obs.time.values[0]).astype("timedelta64[ns]").astype("int64") * 1e-9
    interval = float(obs.attrs.get("interval_s", np.median(np.diff(t_s))))
    f1 = signals.frequency_hz(system, phase[0])
    f2 = signals.frequency_hz(system, phase[1])
    l1, l2 = obs[phase[0]].values, obs[phase[1]].values
    p1, p2 = obs[pod_code[0]].values, obs[pod_code[1]].values
    lli1 = obs[f"{phase[0]}_lli"].values if f"{phase[0]}_lli" in obs else np.zeros(l1.shape)
    lli2 = obs[f"{phase[1]}_lli"].values if f"{phase[1]}_lli" in obs else np.zeros(l2.shape)
    passes: PassResult = detect_passes(
        t_s, l1, l2, p1, p2, lli1, lli2, f1, f2, max_gap_s=settings.max_gap_s,
        mw_k=settings.slip_mw_threshold_cyc, gf_threshold_m=settings.slip_gf_threshold_m)
    pid = passes.pass_id
    above = np.nan_to_num(el_deg, nan=-90.0) >= settings.elevation_mask_deg
    long_pass = _pass_durations(t_s, pid) >= settings.min_pass_s

    data = {}
    stats = {}
    coords = {"time": obs.time.values, "sv": obs.sv.values}
    data["el_deg"] = (("time", "sv"), el_deg, {"units": "degree",
                      "long_name": "elevation in the antenna frame"})
    data["az_deg"] = (("time", "sv"), az_deg, {"units": "degree",
                      "long_name": "azimuth in the antenna frame from +X (flight direction) towards +Y"})
    data["pass_id"] = (("time", "sv"), pid, {"units": "1", "long_name": "pass number (-1: none)"})
    data["pass_flag"] = (("time", "sv"), passes.flags, {
        "units": "1", "long_name": "why a pass starts: bit mask 1 new, 2 gap, 4 LLI, 8 MW, "
        "16 GF, 32 MW or GF outlier"})
    data["mw_cyc"] = (("time", "sv"), passes.mw_cyc, {
        "units": "1", "long_name": f"Melbourne-Wuebbena {phase[0]}/{phase[1]}/{pod_code[0]}/"
        f"{pod_code[1]} in wide-lane cycles"})

    # satellites tracked per epoch and completeness / utilisation
    any_obs = np.zeros(l1.shape, dtype=bool)
    complete = np.ones(l1.shape, dtype=bool)
    for name in list(codes) + list(phase):
        if name in obs:
            v = np.isfinite(obs[name].values)
            any_obs |= v
            complete &= v
        else:
            complete &= False
    n_sv = any_obs.sum(axis=1)
    hist_max = max(int(n_sv.max(initial=0)), 12)
    hist = np.bincount(n_sv, minlength=hist_max + 1)
    day_span = 86400.0 if t_s[-1] - t_s[0] > 43200 else (t_s[-1] - t_s[0] + interval)
    expected = int(round(day_span / interval))
    completeness = (n_sv > 0).sum() / expected
    utilisation = complete.sum() / max(any_obs.sum(), 1)
    data[_TRACKED] = (("time",), n_sv.astype(np.int16),
                            {"units": "1", "long_name": "GNSS satellites tracked per epoch"})
    hist_da = xr.DataArray(hist, dims="n_sats", coords={"n_sats": np.arange(hist.size)},
                           attrs={"units": "1", "long_name": "number of epochs with n_sats satellites tracked"})
    stats["mean_sv_per_epoch"] = (float(n_sv[n_sv > 0].mean()) if (n_sv > 0).any() else np.nan,
                                  "1", "mean number of satellites tracked per epoch with data")
    stats["completeness"] = (float(completeness), "1", "epochs with data / expected epochs")
    stats["utilisation"] = (float(utilisation), "1",
                            "satellite-epochs with all configured observations / observed satellite-epochs")
    n_phase_obs = int((pid >= 0).sum())
    stats["n_passes"] = (passes.n_passes, "1", "number of continuous phase passes")
    stats["n_slips"] = (passes.n_slips, "1", "cycle slips inside continuous tracking")
    stats["obs_per_slip"] = (n_phase_obs / passes.n_slips if passes.n_slips else np.inf, "1",
                             "phase observations per cycle slip (o/slps)")
    stats["n_phase_obs"] = (n_phase_obs, "1", "satellite-epochs with dual-frequency phase and code")
    for bit, name in ((4, "lli"), (8, "mw"), (16, "gf")):
        brk = ((passes.flags & bit) != 0) & ((passes.flags & (FLAG_NEW | FLAG_GAP)) == 0)
        stats[f"n_slips_{name}"] = (int(brk.sum()), "1", f"slips flagged by the {name.upper()} test")
    stats["n_outliers"] = (int(((passes.flags & 32) != 0).sum()), "1", "single-epoch MW or GF outliers")

    # code multipath MP_i per code, minus the pass mean (antenna terms removed if given)
    sv_stats = {}
    obs_mp = obs
    if antenna is not None:
        obs_mp = remove_antenna_terms(obs, antenna, [c for c in codes if c in obs] + list(phase))
        for name in antenna.data_vars:
            term = antenna[name].reindex(time=obs.time, sv=obs.sv)
            data[name] = (("time", "sv"), term.values, dict(antenna[name].attrs))
    for code in codes:
        if code not in obs:
            log.warning("code %s not in the observations: no MP/noise for it", code)
            continue
        band = signals.code_band(code)
        ph_i, ph_j = (phase[0], phase[1]) if signals.code_band(phase[0]) == band else (phase[1], phase[0])
        if signals.code_band(ph_i) != band:
            log.warning("no phase on the band of %s: no MP for it", code)
            continue
        fi, fj = signals.frequency_hz(system, ph_i), signals.frequency_hz(system, ph_j)
        mp_raw = multipath(obs_mp[code].values, obs_mp[ph_i].values, obs_mp[ph_j].values,
                           fi, fj)
        keep = above & long_pass
        mp = _pass_mean_removed(mp_raw, pid, keep)
        data[f"mp_{code}_m"] = (("time", "sv"), mp, {
            "units": "m", "long_name": f"code multipath MP of {code} (with {ph_i}, {ph_j}) minus pass mean",
            "antenna_terms_removed": int(antenna is not None)})
        sv_stats[f"mp_rms_{code}_m"] = (finite_rms(mp, axis=0), "m",
                                        f"RMS of MP {code} per satellite")
        stats[f"mp_rms_{code}_m"] = (finite_rms(mp), "m", f"RMS of MP {code} over the day")

        # code noise: epoch-differenced code-minus-carrier within a pass, sliding STD
        cmc = obs[code].values - obs[ph_i].values
        dcmc = np.full(cmc.shape, np.nan)
        same = (pid[1:] == pid[:-1]) & (pid[1:] >= 0)
        adjacent = np.isclose(np.diff(t_s), interval)[:, None]
        d = cmc[1:] - cmc[:-1]
        dcmc[1:] = np.where(same & adjacent & above[1:], d, np.nan)
        win = np.full(cmc.shape, np.nan)
        min_count = max(3, int(0.5 * settings.noise_window_s / interval))
        for j in range(cmc.shape[1]):
            win[:, j] = sliding_std(t_s, dcmc[:, j], settings.noise_window_s, min_count)
        data[f"noise_{code}_m"] = (("time", "sv"), dcmc, {
            "units": "m", "long_name": f"epoch-differenced {code} minus {ph_i}"})
        data[f"noise_std_{code}_m"] = (("time", "sv"), win, {
            "units": "m", "long_name": f"STD of epoch-differenced {code}-{ph_i} in a "
            f"{settings.noise_window_s:g} s sliding window"})
        w = win[np.isfinite(win)]
        if w.size:
            counts, edges = np.histogram(w, bins=np.geomspace(max(w.min(), 1e-4), w.max() * 1.0001, 60))
            k = counts.argmax()
            peak = float(np.sqrt(edges[k] * edges[k + 1]))
            stats[f"noise_{code}_peak_m"] = (peak, "m", f"{code} noise: histogram peak of window STDs")
            stats[f"noise_{code}_min_m"] = (float(w.min()), "m", f"{code} noise: minimum window STD")
            stats[f"noise_{code}_median_m"] = (float(np.median(w)), "m", f"{code} noise: median window STD")
            stats[f"noise_{code}_p90_m"] = (float(np.percentile(w, 90)), "m",
                                            f"{code} noise: 90th percentile of window STDs")

    # ionospheric delay on frequency 1 and its rate (IOD) within passes
    ion = ionosphere_l1_m(l1, l2, f1, f2)
    iod = np.full(ion.shape, np.nan)
    same = (pid[1:] == pid[:-1]) & (pid[1:] >= 0)
    dt = np.diff(t_s)[:, None]
    iod[1:] = np.where(same, (ion[1:] - ion[:-1]) / dt * 60.0, np.nan)
    data["iod_m_min"] = (("time", "sv"), iod, {
        "units": "m min-1", "long_name": f"rate of the ionospheric delay on {phase[0]} (IOD)"})
    stats["iod_rms_m_min"] = (finite_rms(iod), "m min-1", "RMS of IOD over the day")
    n_iod = np.isfinite(iod).sum()
    stats["iod_above_threshold"] = (float((np.abs(iod) > settings.iod_threshold_m_min).sum() / max(n_iod, 1)),
                                    "1", f"fraction of IOD values above {settings.iod_threshold_m_min} m/min")
    sv_stats["n_obs"] = ((pid >= 0).sum(axis=0), "1", "phase observations per satellite")
    sv_stats["n_passes"] = (np.array([np.unique(pid[:, j][pid[:, j] >= 0]).size
                                      for j in range(pid.shape[1])]), "1", "passes per satellite")

    ds = xr.Dataset({k: xr.Variable(v[0], v[1], v[2]) for k, v in data.items()}, coords=coords)
    ds[f"{system}_epochs_per_n_sats"] = hist_da
    for k, (val, unit, name) in sv_stats.items():
        ds[f"sv_{k}"] = xr.Variable(("sv",), np.asarray(val), {"units": unit, "long_name": name})
    for k, (val, unit, name) in stats.items():
        ds[f"{system}_{k}"] = xr.Variable((), val, {"units": unit, "long_name": f"{system}: {name}"})
    ds.attrs.update(antenna.attrs if antenna is not None
                    else {"antenna_terms": "not removed (multipath of raw observations)"})
    ds.attrs.update({"system": system, "phase_pair": " ".join(phase), "codes": " ".join(codes),
                     "pod_code": " ".join(pod_code), "interval_s": interval,
                     "elevation_mask_deg": settings.elevation_mask_deg})
    log.info("quality %s: %.2f satellites/epoch, completeness %.2f %%, utilisation %.2f %%, "
             "%d passes, %d slips", system, stats["mean_sv_per_epoch"][0],
             100 * completeness, 100 * utilisation, passes.n_passes, passes.n_slips)
    return ds


#: Satellites tracked per epoch (time,): a per-system series that merging sums.
_TRACKED = "n_sv_tracked"


def merge_systems(parts: list[xr.Dataset]) -> xr.Dataset:
    """Combine the per-system results of :func:`assess_quality` into one Dataset.

    Series and per-satellite variables are concatenated along ``sv`` (satellite ids are
    unique across systems); the per-system scalars and histograms keep their prefixes; the
    satellites tracked per epoch are summed over the systems. Attributes: ``systems``, the
    ``codes`` of all systems, ``<system>_phase_pair`` and ``<system>_pod_code``, and the
    shared ones (sampling, mask, antenna terms) of the first.
    """
    if len(parts) == 1:
        return parts[0]
    per_sv = [p[[k for k in p.data_vars if "sv" in p[k].dims]] for p in parts]
    other = [p[[k for k in p.data_vars if "sv" not in p[k].dims and k != _TRACKED]]
             for p in parts]
    tracked = [p[_TRACKED] for p in parts if _TRACKED in p]
    if tracked:   # satellites of all systems tracked per epoch
        total = sum(t.astype(np.int32) for t in xr.align(*tracked, join="outer", fill_value=0))
        other.append(total.astype(np.int16).assign_attrs(tracked[0].attrs).to_dataset(
            name=_TRACKED))
    merged = xr.merge([xr.concat(per_sv, dim="sv", join="outer")] + other, join="outer")
    shared = {k: v for k, v in parts[0].attrs.items()
              if k not in ("system", "phase_pair", "codes", "pod_code")}
    merged.attrs = {**shared, "systems": " ".join(p.attrs["system"] for p in parts),
                    "codes": " ".join(p.attrs["codes"] for p in parts),
                    **{f"{p.attrs['system']}_{k}": p.attrs[k] for p in parts
                       for k in ("phase_pair", "pod_code")}}
    return merged
