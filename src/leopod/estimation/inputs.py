"""Inputs of the float POD from the ingest and quality outputs of one or more days.

Observations of consecutive days are concatenated (passes keep separate ambiguities per day:
a pass crossing midnight gets a new ambiguity, which costs one parameter), decimated to the
POD sampling, clipped to the arc, and combined to ionosphere-free code and phase of the
``pod_code`` and ``phase`` signal pairs of one system, or of several systems each with its own
pairs (GPS L1/L2, BDS-3 B1C/B2a, Galileo E1/E5a, ...: the frequencies come from
:mod:`leopod.signals`) as columns of one arc, the satellites of the first system first.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping

import numpy as np
import xarray as xr

from leopod import signals
from leopod.estimation.float_pod import PodObservations
from leopod.estimation.obsmodel import ReceiverAntenna
from leopod.gnss.attitude import satellite_pco_if
from leopod.gnss.combinations import ionosphere_free, narrow_lane_wavelength_m
from leopod.gnss.leo_antenna import LeoAntenna, receiver_pcv_if
from leopod.io.netcdf import on_grid
from leopod.signals import SystemSignals

__all__ = ["as_system_signals", "pod_observations", "receiver_antenna", "receiver_pco_if",
           "satellite_antenna",
           "satellite_antennas"]

log = logging.getLogger(__name__)


def as_system_signals(signal_cfg, systems) -> dict[str, SystemSignals]:
    """``{system: SystemSignals}`` of ``systems`` (a letter or a sequence of letters) from one
    :class:`SystemSignals` (one system) or a mapping of them.

    Raises
    ------
    KeyError
        If a system has no signals.
    """
    systems = (systems,) if isinstance(systems, str) else tuple(systems)
    if isinstance(signal_cfg, SystemSignals):
        if len(systems) != 1:
            raise KeyError(f"one set of signals for the systems {systems}: give one per system")
        return {systems[0]: signal_cfg}
    missing = [x for x in systems if x not in signal_cfg]
    if missing:
        raise KeyError(f"no signals (phase and pod_code pairs) for the systems {missing}")
    return {x: signal_cfg[x] for x in systems}


def pod_observations(obs_days: list[xr.Dataset], quality_days: list[xr.Dataset],
                     leo_days: list[xr.Dataset], signal_cfg, system,
                     arc_start, arc_end, sampling_s: float) -> PodObservations:
    """Ionosphere-free observations of an arc.

    Parameters
    ----------
    obs_days, quality_days, leo_days : list of xarray.Dataset
        Ingest observations, quality (``pass_id``), and a-priori orbit (``clk_rx_m``) of
        consecutive days, in time order.
    signal_cfg : SystemSignals or mapping of str to SystemSignals
        Campaign signals of the system (``phase`` and ``pod_code`` pairs), or per system.
    system : str or sequence of str
        GNSS letter, or letters (the first is the reference of the inter-system biases).
    arc_start, arc_end : datetime64
        Arc limits (inclusive).
    sampling_s : float
        POD sampling [s]: epochs on this grid are used.

    Returns
    -------
    PodObservations
    """
    by_system = as_system_signals(signal_cfg, system)
    sv_of = {x: sorted({str(s) for ds in obs_days for s in ds.sv.values if str(s)[0] == x})
             for x in by_system}
    sv_all = [s for x in by_system for s in sv_of[x]]
    nl_sys = {}
    for x, sig in by_system.items():
        f1, f2 = (signals.frequency_hz(x, p) for p in sig.phase)
        nl_sys[x] = narrow_lane_wavelength_m(f1, f2)

    def combined(o: xr.Dataset) -> tuple[np.ndarray, np.ndarray]:
        """IF code and phase (time, sv_all) of each system's pairs."""
        code, phase = [], []
        for x, sig in by_system.items():
            ox = o.sel(sv=sv_of[x])
            (p1, p2), (c1, c2) = sig.phase, sig.pod_code
            f1, f2 = signals.frequency_hz(x, p1), signals.frequency_hz(x, p2)
            fc1, fc2 = signals.frequency_hz(x, c1), signals.frequency_hz(x, c2)
            code.append(ionosphere_free(ox[c1].values, ox[c2].values, fc1, fc2))
            phase.append(ionosphere_free(ox[p1].values, ox[p2].values, f1, f2))
        return np.concatenate(code, axis=1), np.concatenate(phase, axis=1)
    columns = {x: np.isin(sv_all, sv_of[x]) for x in by_system}

    def day_passes(qual: xr.Dataset) -> tuple[dict, int]:
        """Offset of each system's pass ids of a day and the day's total: the quality step
        numbers the passes of each system from 0, so they are made distinct here."""
        offsets, total = {}, 0
        for x in by_system:
            offsets[x] = total
            ids = qual.pass_id.sel(sv=[s for s in qual.sv.values if str(s)[0] == x]).values
            total += int(ids.max(initial=-1)) + 1
        return offsets, total

    blocks = []
    pass_offset = 0
    start, end = np.datetime64(arc_start, "ns"), np.datetime64(arc_end, "ns")
    for obs, qual, leo in zip(obs_days, quality_days, leo_days, strict=True):
        t = obs.time.values
        sel = (t >= start) & (t <= end) & on_grid(t, sampling_s)
        offsets, total = day_passes(qual)
        if not sel.any():
            pass_offset += total
            continue
        o = obs.isel(time=sel).reindex(sv=sv_all)
        code, phase = combined(o)
        pid = qual.pass_id.isel(time=sel).reindex(sv=sv_all, fill_value=-1).values.astype(int)
        for x, cols in columns.items():
            pid[:, cols] = np.where(pid[:, cols] >= 0, pid[:, cols] + pass_offset + offsets[x],
                                    -1)
        pass_offset += total
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
    unsolved = int((have.any(axis=1) & ~np.isfinite(clk)).sum())
    if unsolved:
        log.warning("%d epochs with observations but without a code-only position and clock "
                    "(too few satellites for it, or rejected at ingest) not used", unsolved)
    times, code, phase, pid, clk = (times[keep_epoch], code[keep_epoch], phase[keep_epoch],
                                    pid[keep_epoch], clk[keep_epoch])
    have = have[keep_epoch]
    ep, sat = np.nonzero(have)
    # renumber passes densely
    used, dense = np.unique(pid[ep, sat], return_inverse=True)
    pass_index = np.where(pid[ep, sat] >= 0, dense - (used[0] < 0), -1)
    nl = np.array([nl_sys[s[0]] for s in sv_all])
    return PodObservations(times=times, sv=np.array(sv_all), epoch=ep, sat=sat,
                           code_m=code[ep, sat], phase_m=phase[ep, sat],
                           pass_index=pass_index, clk_rx_m=clk,
                           nl_wavelength_m=float(nl[0]) if len(by_system) == 1 else nl,
                           systems=tuple(by_system))


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


def satellite_antennas(antex, sv, epoch, signal_cfg: dict[str, SystemSignals]):
    """:func:`satellite_antenna` of several systems: PCO (s, 3) [m] and one PCV function.

    Parameters
    ----------
    antex : leopod.io.antex.AntexFile
    sv : ndarray of str, shape (s,)
        Satellites; the first letter selects the system's signals in ``signal_cfg``.
    epoch : datetime64
    signal_cfg : dict of str to SystemSignals
    """
    sv = np.asarray(sv).astype(str)
    pco = np.full((sv.size, 3), np.nan)
    functions, members = [], []
    for x, sig in signal_cfg.items():
        idx = np.flatnonzero(np.char.startswith(sv, x))
        if not idx.size:
            continue
        p, f = satellite_antenna(antex, sv[idx], epoch, x, sig)
        pco[idx] = p
        functions.append(f)
        members.append(idx)
    local = np.zeros(sv.size, int)
    owner = np.full(sv.size, -1)
    for o, idx in enumerate(members):
        local[idx] = np.arange(idx.size)
        owner[idx] = o

    def pcv(sat_index: np.ndarray, nadir_deg: np.ndarray) -> np.ndarray:
        out = np.zeros(nadir_deg.shape)
        for o, f in enumerate(functions):
            sel = owner[sat_index] == o
            if sel.any():
                out[sel] = f(local[sat_index[sel]], nadir_deg[sel])
        return out

    return pco, pcv


def _antenna_name(antenna) -> str:
    """How an error names the LEO antenna: its ANTEX source, or the config key of the table."""
    if isinstance(antenna, LeoAntenna):
        return f"the LEO antenna ({antenna.source}, satellites.<sat>.antenna)"
    return "antenna_pco_body_m"


def receiver_pco_if(pco_body_m: dict | None, system: str, signal_cfg: SystemSignals) -> np.ndarray:
    """Ionosphere-free LEO antenna PCO in the body frame [m] from per-band offsets."""
    if not pco_body_m:
        return np.zeros(3)
    p1, p2 = signal_cfg.phase
    b1, b2 = signals.band(system, p1).name, signals.band(system, p2).name
    f1, f2 = signals.frequency_hz(system, p1), signals.frequency_hz(system, p2)
    missing = [b for b in (b1, b2) if b not in pco_body_m]
    if missing:
        raise ValueError(f"{_antenna_name(pco_body_m)} has no offset for {missing}")
    return ionosphere_free(np.asarray(pco_body_m[b1], float), np.asarray(pco_body_m[b2], float),
                           f1, f2)


def receiver_antenna(antenna, svs, by_system: Mapping[str, SystemSignals]
                     ) -> ReceiverAntenna | None:
    """Antenna frame and ionosphere-free PCV of a LEO ANTEX antenna for the POD model.

    Parameters
    ----------
    antenna : LeoAntenna or mapping or None
        The satellite's antenna (:func:`leopod.gnss.leo_antenna.leo_antenna`); a plain PCO
        table (or None) has neither frame nor PCV.
    svs : sequence of str, shape (s,)
        Satellites of the observation file (``PodObservations.sv``).
    by_system : mapping
        System -> its signals: the phase pair of the ionosphere-free PCV
        ``(f1² PCV1 − f2² PCV2) / (f1² − f2²)`` (:func:`leopod.gnss.leo_antenna.
        receiver_pcv_if`), the pair of the ionosphere-free PCO.

    Returns
    -------
    ReceiverAntenna or None
    """
    if not isinstance(antenna, LeoAntenna):
        return None
    per_system = {x: receiver_pcv_if(antenna, x, sig.phase) for x, sig in by_system.items()}
    if all(f is None for f in per_system.values()):
        return ReceiverAntenna(frame=antenna.frame, pcv_if_m=None)
    owner = np.array([str(sv)[0] for sv in svs])

    def pcv_if_m(sat_index: np.ndarray, el_deg: np.ndarray, az_deg: np.ndarray) -> np.ndarray:
        out = np.zeros(np.shape(el_deg))
        system = owner[sat_index]
        for x, f in per_system.items():
            sel = system == x
            if f is not None and sel.any():
                out[sel] = f(el_deg[sel], az_deg[sel])
        return out

    return ReceiverAntenna(frame=antenna.frame, pcv_if_m=pcv_if_m)
