"""Inputs of the float POD from the ingest and quality outputs of one or more days.

Observations of consecutive days are concatenated (passes keep separate ambiguities per day:
a pass crossing midnight gets a new ambiguity, which costs one parameter), decimated to the
POD sampling, clipped to the arc, and combined to ionosphere-free code and phase of the
``pod_code`` and ``phase`` signal pairs of one system.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from leopod import signals
from leopod.estimation.float_pod import PodObservations
from leopod.gnss.attitude import satellite_pco_if
from leopod.gnss.combinations import ionosphere_free, narrow_lane_wavelength_m
from leopod.signals import SystemSignals

__all__ = ["pod_observations", "receiver_pco_if", "satellite_antenna"]


def _on_grid(times: np.ndarray, sampling_s: float) -> np.ndarray:
    ns = times.astype("datetime64[ns]").astype("int64")
    step = round(sampling_s * 1e9)
    return ns % step == 0


def pod_observations(obs_days: list[xr.Dataset], quality_days: list[xr.Dataset],
                     leo_days: list[xr.Dataset], signal_cfg: SystemSignals, system: str,
                     arc_start, arc_end, sampling_s: float) -> PodObservations:
    """Ionosphere-free observations of an arc.

    Parameters
    ----------
    obs_days, quality_days, leo_days : list of xarray.Dataset
        Ingest observations, quality (``pass_id``), and a-priori orbit (``clk_rx_m``) of
        consecutive days, in time order.
    signal_cfg : SystemSignals
        Campaign signals of the system (``phase`` and ``pod_code`` pairs).
    system : str
        GNSS letter.
    arc_start, arc_end : datetime64
        Arc limits (inclusive).
    sampling_s : float
        POD sampling [s]: epochs on this grid are used.

    Returns
    -------
    PodObservations
    """
    p1, p2 = signal_cfg.phase
    c1, c2 = signal_cfg.pod_code
    f1, f2 = signals.frequency_hz(system, p1), signals.frequency_hz(system, p2)
    fc1, fc2 = signals.frequency_hz(system, c1), signals.frequency_hz(system, c2)
    sv_all = sorted({str(s) for ds in obs_days for s in ds.sv.values if str(s)[0] == system})
    blocks = []
    pass_offset = 0
    start, end = np.datetime64(arc_start, "ns"), np.datetime64(arc_end, "ns")
    for obs, qual, leo in zip(obs_days, quality_days, leo_days, strict=True):
        t = obs.time.values
        sel = (t >= start) & (t <= end) & _on_grid(t, sampling_s)
        if not sel.any():
            pass_offset += int(qual.pass_id.max()) + 1
            continue
        o = obs.isel(time=sel).reindex(sv=sv_all)
        q = qual.isel(time=sel).reindex(sv=sv_all, fill_value={"pass_id": -1})
        code = ionosphere_free(o[c1].values, o[c2].values, fc1, fc2)
        phase = ionosphere_free(o[p1].values, o[p2].values, f1, f2)
        pid = q.pass_id.values.astype(int)
        pid = np.where(pid >= 0, pid + pass_offset, -1)
        pass_offset += int(qual.pass_id.max()) + 1
        clk = leo.clk_rx_m.sel(time=o.time.values).values
        blocks.append((o.time.values, code, phase, pid, clk))
    if not blocks:
        raise ValueError(f"no observations between {start} and {end}")
    times = np.concatenate([b[0] for b in blocks])
    code = np.concatenate([b[1] for b in blocks])
    phase = np.concatenate([b[2] for b in blocks])
    pid = np.concatenate([b[3] for b in blocks])
    clk = np.concatenate([b[4] for b in blocks])
    phase = np.where(pid >= 0, phase, np.nan)
    have = np.isfinite(code) | np.isfinite(phase)
    keep_epoch = have.any(axis=1) & np.isfinite(clk)
    times, code, phase, pid, clk = (times[keep_epoch], code[keep_epoch], phase[keep_epoch],
                                    pid[keep_epoch], clk[keep_epoch])
    have = have[keep_epoch]
    ep, sat = np.nonzero(have)
    # renumber passes densely
    used, dense = np.unique(pid[ep, sat], return_inverse=True)
    pass_index = np.where(pid[ep, sat] >= 0, dense - (used[0] < 0), -1)
    return PodObservations(times=times, sv=np.array(sv_all), epoch=ep, sat=sat,
                           code_m=code[ep, sat], phase_m=phase[ep, sat],
                           pass_index=pass_index, clk_rx_m=clk,
                           nl_wavelength_m=narrow_lane_wavelength_m(f1, f2))


def satellite_antenna(antex, sv, epoch, system: str, signal_cfg: SystemSignals):
    """Ionosphere-free GNSS satellite PCO (s, 3) [m] and a PCV function from ANTEX.

    Satellites without an ANTEX entry get NaN PCO rows (their observations are then
    unusable: callers should drop them).

    Returns
    -------
    pco : ndarray, shape (s, 3)
    pcv : callable ``(sat_index (n,), nadir_deg (n,)) -> (n,)`` [m]
    """
    p1, p2 = signal_cfg.phase
    f1, f2 = signals.frequency_hz(system, p1), signals.frequency_hz(system, p2)
    bands = (signals.code_band(p1), signals.code_band(p2))
    pco = satellite_pco_if(antex, sv, epoch, system, bands, f1, f2)
    patterns = []
    for prn in sv:
        try:
            patterns.append(antex.satellite(str(prn), epoch))
        except KeyError:
            patterns.append(None)
    freq = [f"{system}{int(b):02d}" for b in bands]

    def pcv(sat_index: np.ndarray, nadir_deg: np.ndarray) -> np.ndarray:
        out = np.zeros(nadir_deg.shape)
        for j in np.unique(sat_index):
            pat = patterns[j]
            if pat is None:
                continue
            sel = sat_index == j
            v1 = pat.pcv_m(freq[0], nadir_deg[sel], outside="nearest")
            v2 = pat.pcv_m(freq[1], nadir_deg[sel], outside="nearest")
            out[sel] = ionosphere_free(v1, v2, f1, f2)
        return out

    return pco, pcv


def receiver_pco_if(pco_body_m: dict | None, system: str, signal_cfg: SystemSignals) -> np.ndarray:
    """Ionosphere-free LEO antenna PCO in the body frame [m] from per-band offsets."""
    if not pco_body_m:
        return np.zeros(3)
    p1, p2 = signal_cfg.phase
    b1, b2 = signals.band(system, p1).name, signals.band(system, p2).name
    f1, f2 = signals.frequency_hz(system, p1), signals.frequency_hz(system, p2)
    missing = [b for b in (b1, b2) if b not in pco_body_m]
    if missing:
        raise ValueError(f"antenna_pco_body_m has no offset for {missing}")
    return ionosphere_free(np.asarray(pco_body_m[b1], float), np.asarray(pco_body_m[b2], float),
                           f1, f2)
