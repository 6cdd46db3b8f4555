"""Correction of code observations with antenna-frame code-bias maps.

``corrected = observed − map(az, el)`` for every code the campaign asks to correct, with the
antenna-frame direction of each observation from the quality step and the attitude mode of
its epoch. Observations whose interpolation cell touches an empty node (too few data,
Peng et al. 2021, Fig. 7 "blank areas") have no correction: ``empty_cells="drop"`` removes those
codes (NaN), ``"keep"`` leaves them uncorrected. Dropping is the default because the datum of a map
is arbitrary: an uncorrected code differs from the corrected ones of the same epoch by the map's
mean, which neither the receiver clock nor the wide-lane single difference would absorb.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import xarray as xr

from leopod.codebias.products import grid_of
from leopod.codebias.samples import attitude_mode
from leopod.settings import Settings

__all__ = ["EMPTY_CELL_POLICIES", "CodeCorrection", "correct_codes", "map_correction"]

log = logging.getLogger(__name__)

#: What to do with a code whose direction has no map value.
EMPTY_CELL_POLICIES = ("drop", "keep")


@dataclass(frozen=True)
class CodeCorrection(Settings):
    """Which code corrections a step applies (config ``code_bias``).

    Attributes
    ----------
    apply : tuple of str
        RINEX 3 codes corrected with their map (empty: none).
    empty_cells : str
        Policy for codes whose cell touches an empty node (:data:`EMPTY_CELL_POLICIES`).
    bds2_scb : bool
        Add the BDS-2 satellite-induced code-bias correction to the BDS-2 IGSO/MEO codes
        (:func:`leopod.codebias.scb.correct_bds2_scb`), with or without maps.
    """

    SCHEMA_DEF = "code_bias"

    apply: tuple[str, ...]
    empty_cells: str
    bds2_scb: bool


def map_correction(maps: xr.Dataset, signal: str, az_deg, el_deg, mode) -> np.ndarray:
    """Map values at directions [m] (NaN where the cell has an empty node).

    Parameters
    ----------
    maps : xarray.Dataset
        Map dataset (:mod:`leopod.codebias.products`).
    signal : str
        RINEX 3 code.
    az_deg, el_deg : array_like, shape (n,)
        Antenna-frame directions [deg].
    mode : array_like of int, shape (n,)
        Attitude mode per direction; modes without a map get NaN.
    """
    grid = grid_of(maps)
    az, el = np.asarray(az_deg, dtype=float), np.asarray(el_deg, dtype=float)
    mode = np.broadcast_to(np.asarray(mode), az.shape)
    out = np.full(az.shape, np.nan)
    for m in np.unique(mode):
        if m not in maps.mode.values:
            continue
        sel = mode == m
        nodes = grid.from_grid(maps.value_m.sel(signal=signal, mode=m).values)
        out[sel] = grid.interpolate(nodes, az[sel], el[sel])
    return out


def correct_codes(obs: xr.Dataset, quality: xr.Dataset, maps: xr.Dataset, codes, *,
                  empty_cells: str, yaw_flips=None) -> tuple[xr.Dataset, dict]:
    """Subtract the maps from the codes of one day of observations.

    Parameters
    ----------
    obs : xarray.Dataset
        Ingest observations (codes in metres on (time, sv)).
    quality : xarray.Dataset
        Quality output of the same day (``el_deg``, ``az_deg`` on (time, sv)).
    maps : xarray.Dataset
        Map dataset holding every code of ``codes``.
    codes : sequence of str
        Codes to correct (absent from ``obs``: skipped with a warning).
    empty_cells : {"drop", "keep"}
        Policy for directions without a map value (module docstring).
    yaw_flips : sequence of datetime-like, optional
        Yaw-flip epochs giving the attitude mode.

    Returns
    -------
    corrected : xarray.Dataset
        Copy of ``obs`` with corrected codes (attribute ``code_bias_map`` on each).
    summary : dict
        Per code: ``corrected`` and ``no_map`` observation counts.

    Raises
    ------
    ValueError
        If the policy is unknown or a code has no map.
    """
    if empty_cells not in EMPTY_CELL_POLICIES:
        raise ValueError(f"empty_cells must be one of {EMPTY_CELL_POLICIES}, not {empty_cells!r}")
    missing = [c for c in codes if c not in maps.signal.values]
    if missing:
        raise ValueError(f"code-bias map of period {maps.attrs.get('period')} has no "
                         f"{' '.join(missing)} (signals: {' '.join(maps.signal.values)})")
    out = obs.copy()
    q = quality[["el_deg", "az_deg"]].reindex(time=obs.time, sv=obs.sv)
    mode = np.broadcast_to(attitude_mode(obs.time.values, yaw_flips)[:, None],
                           q.el_deg.shape)
    summary = {}
    for code in codes:
        if code not in obs:
            log.warning("code %s not in the observations: not corrected", code)
            continue
        values = obs[code].values
        have = np.isfinite(values)
        corr = np.full(values.shape, np.nan)
        corr[have] = map_correction(maps, code, q.az_deg.values[have], q.el_deg.values[have],
                                    mode[have])
        no_map = have & ~np.isfinite(corr)
        new = values - np.nan_to_num(corr)
        if empty_cells == "drop":
            new[no_map] = np.nan
        out[code] = obs[code].copy(data=new)
        out[code].attrs["code_bias_map"] = (f"period {maps.attrs.get('period')}, "
                                            f"empty cells: {empty_cells}")
        summary[code] = {"corrected": int((have & ~no_map).sum()), "no_map": int(no_map.sum())}
        log.info("code-bias map on %s: %d corrected, %d without map value (%s)", code,
                 summary[code]["corrected"], summary[code]["no_map"], empty_cells)
        if no_map.sum() > 0.5 * have.sum():
            log.warning("the map of %s covers only %.0f %% of its codes: a longer period or a "
                        "smaller code_bias.min_count (now %s) gives more", code,
                        100 * (1 - no_map.sum() / max(have.sum(), 1)),
                        maps.attrs.get("min_count"))
    return out, summary
