"""Correction of the BDS-2 satellite-induced code bias in a day of observations.

``corrected = observed + Δ(type, band, e*)`` for every B1I/B2I/B3I code of the BDS-2 IGSO and
MEO satellites (Wanninger & Beer 2015; :mod:`leopod.gnss.scb`), with ``e*`` the ground
elevation equivalent to the nadir angle at the BDS satellite of the line to the LEO, which the
quality step stores as ``nadir_sv_deg``. Every other code (GPS, BDS-3, BDS-2 GEO) and every
phase is returned unchanged. The quality step corrects the codes before its multipath
combination and the POD and ambiguity steps before their code and HMW observations, so that
every code the campaign uses is corrected once and the code-bias maps do not absorb the SCB.
"""

from __future__ import annotations

import logging

import numpy as np
import xarray as xr

from leopod.gnss.scb import BDS2_ORBIT_TYPE, bds2_scb_m, scb_band

__all__ = ["NADIR_VARIABLE", "correct_bds2_scb", "scb_codes"]

log = logging.getLogger(__name__)

#: Quality variable with the nadir angle at the GNSS satellite of the line to the LEO [deg].
NADIR_VARIABLE = "nadir_sv_deg"


def scb_codes(obs: xr.Dataset) -> list[str]:
    """Code variables of ``obs`` (``C<band><attr>``, float) on the B1I/B2I/B3I bands."""
    return [str(v) for v in obs.data_vars
            if len(str(v)) == 3 and str(v)[0] == "C" and obs[v].dtype.kind == "f"
            and scb_band(str(v)) is not None]


def correct_bds2_scb(obs: xr.Dataset, geometry: xr.Dataset) -> tuple[xr.Dataset, dict]:
    """Add the Wanninger & Beer (2015) correction to the BDS-2 IGSO/MEO codes of ``obs``.

    Parameters
    ----------
    obs : xarray.Dataset
        Observations on (time, sv), codes in metres (ingest schema).
    geometry : xarray.Dataset
        ``nadir_sv_deg`` on (time, sv) (the quality output of the same day), reindexed to
        ``obs``; needed only when ``obs`` has BDS-2 IGSO/MEO codes on the SCB bands.

    Returns
    -------
    corrected : xarray.Dataset
        Copy of ``obs`` with corrected codes (attribute ``bds2_scb`` on each corrected code).
    summary : dict
        Per corrected code: ``corrected`` (observations), ``no_geometry`` (BDS-2 IGSO/MEO codes
        without a nadir angle, e.g. epochs without a-priori orbit: set to NaN, since they would
        keep the SCB) and ``rms_m`` (RMS of the applied correction).

    Raises
    ------
    KeyError
        If BDS-2 IGSO/MEO codes are present and ``geometry`` has no ``nadir_sv_deg``.
    """
    svs = [str(s) for s in obs.sv.values]
    affected = np.array([s in BDS2_ORBIT_TYPE for s in svs])
    codes = scb_codes(obs)
    if not affected.any() or not codes:
        return obs, {}
    if NADIR_VARIABLE not in geometry:
        raise KeyError(f"{geometry.attrs.get('title', 'geometry dataset')}: no "
                       f"{NADIR_VARIABLE} for the BDS-2 SCB correction (rerun the quality step "
                       "of this leopod version)")
    nadir = geometry[NADIR_VARIABLE].reindex(time=obs.time, sv=obs.sv).transpose(
        "time", "sv").values
    out = obs.copy()
    summary = {}
    for code in codes:
        values = obs[code].transpose("time", "sv").values
        have = np.isfinite(values) & affected[None, :]
        if not have.any():
            continue
        lacking = have & ~np.isfinite(nadir)
        corr = bds2_scb_m(svs, code, np.where(have & ~lacking, nadir, 0.0))
        # a code without geometry cannot be corrected: dropped, as it would carry the SCB
        new = np.where(have, np.where(lacking, np.nan, values + corr), values)
        out[code] = obs[code].transpose("time", "sv").copy(data=new)
        out[code].attrs["bds2_scb"] = "Wanninger & Beer (2015) correction added (BDS-2 IGSO/MEO)"
        ok = have & ~lacking
        summary[code] = {"corrected": int(ok.sum()), "no_geometry": int(lacking.sum()),
                         "rms_m": float(np.sqrt(np.mean(corr[ok] ** 2))) if ok.any() else 0.0}
        if lacking.any():
            log.warning("BDS-2 SCB on %s: %d codes without %s dropped", code,
                        int(lacking.sum()), NADIR_VARIABLE)
        log.info("BDS-2 SCB on %s: %d codes corrected, RMS of the correction %.3f m", code,
                 summary[code]["corrected"], summary[code]["rms_m"])
    return out, summary
