"""Receiver tracking of the simulated observations: channels, gaps, passes, slips, ambiguities.

A sticky channel allocation per system: a satellite is tracked from its acquisition above the
antenna-frame elevation mask until it sets or a random gap breaks the lock; free channels go
to the highest untracked satellites. Each acquisition starts a pass with new random integer
ambiguities (LLI set); cycle slips add random integer jumps (not all zero) and start a new
pass, with the LLI set with probability ``lli_detected``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from leopod.simulate.observations import ObservationSettings

__all__ = ["Passes", "passes", "track"]


def track(el_deg: np.ndarray, systems: np.ndarray, settings: ObservationSettings,
          dt_s: float, rng: np.random.Generator) -> np.ndarray:
    """Tracked (n, s) mask: sticky channel allocation per system with random gaps.

    Parameters
    ----------
    el_deg : ndarray, shape (n, s)
        Antenna-frame elevations [deg].
    systems : ndarray of str, shape (s,)
        System letter of each satellite (channels are counted per system).
    settings : ObservationSettings
        ``channels``, ``elevation_mask_deg``, ``gap_rate_per_h``, ``gap_max_epochs``.
    dt_s : float
        Epoch spacing [s].
    rng : numpy.random.Generator

    Returns
    -------
    ndarray of bool, shape (n, s)
    """
    n, s = el_deg.shape
    visible = el_deg > settings.elevation_mask_deg
    p_gap = settings.gap_rate_per_h * dt_s / 3600.0
    gap_start = rng.random((n, s)) < p_gap
    gap_len = rng.integers(1, settings.gap_max_epochs + 1, (n, s))
    blocked = np.zeros((n, s), dtype=bool)
    for i, j in zip(*np.nonzero(gap_start & visible)):
        blocked[i:i + gap_len[i, j], j] = True
    available = visible & ~blocked
    tracked = np.zeros((n, s), dtype=bool)
    groups = [np.flatnonzero(systems == sys) for sys in np.unique(systems)]
    prev = np.zeros(s, dtype=bool)
    for i in range(n):
        now = prev & available[i]
        for cols in groups:
            free = settings.channels - int(now[cols].sum())
            cand = cols[available[i, cols] & ~now[cols]]
            if free > 0 and cand.size:
                best = cand[np.argsort(-el_deg[i, cand], kind="stable")[:free]]
                now[best] = True
        tracked[i] = now
        prev = now
    return tracked


@dataclass
class Passes:
    """Pass numbers, ambiguities per phase signal and LLI flags of the tracked pairs."""

    pass_id: np.ndarray          # (n, s) int, -1 where not tracked
    ambiguity_cyc: dict          # phase code -> (n, s) float, NaN where not tracked
    lli: np.ndarray              # (n, s) int8: 1 at acquisitions and flagged slips, else 0/-1
    n_slips: int


def passes(tracked: np.ndarray, systems: np.ndarray, phase_codes: dict,
           settings: ObservationSettings, dt_s: float, rng: np.random.Generator) -> Passes:
    """New pass at every acquisition (new ambiguities) and slip (integer jumps).

    Parameters
    ----------
    tracked : ndarray of bool, shape (n, s)
    systems : ndarray of str, shape (s,)
    phase_codes : dict
        System -> its phase codes (ambiguities are drawn per code).
    settings : ObservationSettings
        ``slip_rate_per_h``, ``slip_max_cyc``, ``lli_detected``, ``ambiguity_max_cyc``.
    dt_s : float
        Epoch spacing [s].
    rng : numpy.random.Generator

    Returns
    -------
    Passes
    """
    n, s = tracked.shape
    starts = tracked & ~np.vstack([np.zeros((1, s), bool), tracked[:-1]])
    slips = tracked & ~starts & (rng.random((n, s)) < settings.slip_rate_per_h * dt_s / 3600.0)
    flagged = slips & (rng.random((n, s)) < settings.lli_detected)
    pass_id = (np.cumsum((starts | slips).T.ravel()) - 1).reshape(s, n).T   # sv-major
    pass_id = np.where(tracked, pass_id, -1)
    amb_max, slip_max = settings.ambiguity_max_cyc, settings.slip_max_cyc
    values = {}
    for system in sorted(phase_codes):
        codes = phase_codes[system]
        acquired = {c: rng.integers(-amb_max, amb_max + 1, (n, s)) for c in codes}
        jump = {c: rng.integers(-slip_max, slip_max + 1, (n, s)) for c in codes}
        # a slip of zero cycles on every frequency would be no slip: +1 on the first phase
        no_jump = np.all([jump[c] == 0 for c in codes], axis=0)
        jump[codes[0]] = np.where(no_jump, 1, jump[codes[0]])
        mine = (systems == system)[None, :]
        for c in codes:
            own = _accumulate(np.where(starts, acquired[c], 0).astype(float),
                              np.where(slips, jump[c], 0).astype(float), starts,
                              tracked & mine)
            # a code name of several systems (GPS and Galileo L1C) keeps each one's columns
            values[c] = np.where(mine, own, values[c]) if c in values else own
    lli = np.where(tracked, (starts | flagged).astype(np.int8), -1).astype(np.int8)
    return Passes(pass_id=pass_id, ambiguity_cyc=values, lli=lli, n_slips=int(slips.sum()))


def _accumulate(level: np.ndarray, step: np.ndarray, starts: np.ndarray,
                tracked: np.ndarray) -> np.ndarray:
    """Running value per track: reset to ``level`` at starts, plus ``step`` at slips."""
    n, s = level.shape
    out = np.full((n, s), np.nan)
    for j in range(s):
        rows = np.flatnonzero(tracked[:, j])
        if rows.size == 0:
            continue
        seg = np.cumsum(starts[rows, j]) - 1
        base = level[rows, j][starts[rows, j]][seg]
        jumps = np.cumsum(step[rows, j])
        jumps -= jumps[starts[rows, j]][seg]
        out[rows, j] = base + jumps
    return out
