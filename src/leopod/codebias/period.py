"""Maps of one satellite and period from its daily quality outputs (rule ``code_bias``)."""

from __future__ import annotations

import logging

import numpy as np
import xarray as xr

from leopod.codebias.estimate import MapFit, MapSettings, estimate_map
from leopod.codebias.products import MpStatistics, map_dataset, mp_statistics
from leopod.codebias.samples import mp_samples

__all__ = ["estimate_period"]

log = logging.getLogger(__name__)


def _antenna_attrs(quality_days: list[xr.Dataset]) -> dict:
    """The ``antenna_*`` attributes shared by the quality outputs of a period."""
    found = [{k: v for k, v in ds.attrs.items() if k.startswith("antenna_")}
             for ds in quality_days]
    if not found or not found[0]:
        return {"antenna_terms": "not removed (multipath of raw observations)"}
    if any(f != found[0] for f in found[1:]):
        log.warning("the quality outputs of the period removed different antenna terms; the "
                    "maps record those of the first day")
    return found[0]


def estimate_period(quality_days: list[xr.Dataset], codes, settings: MapSettings, *,
                    period: str, satellite: str, yaw_flips=None,
                    min_elevation_deg: float = 0.0
                    ) -> tuple[xr.Dataset, dict[str, MpStatistics]]:
    """Estimate the maps of ``codes`` (per attitude mode if ``yaw_flips`` is given).

    Parameters
    ----------
    quality_days : list of xarray.Dataset
        Quality outputs of the days of the period.
    codes : sequence of str
        Codes to map; None = every code the quality step assessed (attribute ``codes``).
    settings : MapSettings
    period, satellite : str
        Identification written into the product.
    yaw_flips : sequence of datetime-like, optional
        Yaw-flip epochs: one map per attitude mode.
    min_elevation_deg : float
        Lowest antenna elevation used [deg].

    Returns
    -------
    maps : xarray.Dataset
        Map dataset (:mod:`leopod.codebias.products`), with the ``antenna_*`` attributes of the
        quality outputs: which antenna terms (LEO PCO per band, GNSS PCO/PCV per frequency,
        :mod:`leopod.gnss.antenna_terms`) the multipath was freed of, so that the maps hold
        no antenna term (``antenna_terms = "not removed"`` for older quality outputs).
    stats : dict
        Multipath before/after per signal (for figures).
    """
    if codes is None:
        codes = sorted({c for ds in quality_days for c in ds.attrs.get("codes", "").split()})
    fits: dict[tuple[str, int], MapFit] = {}
    stats: dict[tuple[str, int], MpStatistics] = {}
    for code in codes:
        samples = mp_samples(quality_days, code, yaw_flips=yaw_flips,
                             min_elevation_deg=min_elevation_deg)
        for mode in np.unique(samples.mode):
            sub = samples.select(samples.mode == mode)
            log.info("%s %s mode %d: %d multipath observations", period, code, mode,
                     sub.mp_m.size)
            fit = estimate_map(sub.az_deg, sub.el_deg, sub.mp_m, sub.pass_key, settings)
            fits[(code, int(mode))] = fit
            stats[(code, int(mode))] = mp_statistics(
                sub, np.where(fit.empty(settings.min_count), np.nan, fit.value_m),
                settings.grid)
    if not fits:
        raise ValueError(f"no multipath observations of {' '.join(codes)} in period {period}")
    maps, per_signal = map_dataset(fits, stats, settings, period=period, satellite=satellite)
    maps.attrs.update(_antenna_attrs(quality_days))
    for code in maps.signal.values:
        s = maps.sel(signal=code)
        filled = sum(int((~fit.empty(settings.min_count)).sum())
                     for (c, _), fit in fits.items() if c == code)
        log.info("%s %s: MP RMS %.3f -> %.3f m over %.1f %% of the observations; "
                 "%d of %d nodes non-empty", period, code, float(s.mp_rms_all_before_m),
                 float(s.mp_rms_all_after_m), 100 * float(s.covered_fraction), filled,
                 settings.grid.n_nodes * s.sizes["mode"])
    return maps, per_signal
