"""Nominal attitude of GNSS satellites and their antenna phase-centre offsets.

Yaw-steering attitude (IGS convention, Montenbruck et al. 2015, Adv. Space Res. 56:1015):
+Z points to the geocentre, +Y = Z × e_sun (along the solar-panel axis), +X = Y × Z completes
the frame so that +X points to the Sun-lit hemisphere. The antenna phase centre is
``r_com + x e_X + y e_Y + z e_Z`` with the ANTEX offset (x, y, z).

The Sun position is the low-precision formula of the Astronomical Almanac (section C, "Low
precision formulas for the Sun": mean equinox of date, 0.01° 1950–2050), rotated to Earth-fixed
axes with GMST (IAU 1982, pyerfa) of UT1 ≈ UTC — ample for orienting antenna offsets of at most
a few metres. (This was formerly Montenbruck & Gill's series, which refers to the J2000
equinox; rotated with the GMST of date and of UT1 ≈ GPS time it was off by 0.2° in 2007 and
0.5° in 2023: tests/orbit/test_gnss_attitude.py compares with pyerfa.)
"""

from __future__ import annotations

import erfa
import numpy as np

from leopod.constants import AU_M, GPST_MINUS_TAI_S, JD_J2000, TT_MINUS_TAI_S
from leopod.gnss.combinations import ionosphere_free
from leopod.time import J2000_TT
from leopod.timescales import tai_minus_utc_s

__all__ = ["sun_position_ef", "gnss_body_axes", "satellite_pco_if"]

_GPS_TT_OFFSET_S = TT_MINUS_TAI_S - GPST_MINUS_TAI_S   # TT - GPST = 51.184 s (exact)


def sun_position_ef(times) -> np.ndarray:
    """Low-precision Earth-fixed Sun position [m], shape (n, 3), at GPS-time epochs.

    Parameters
    ----------
    times : array_like of datetime64
        Epochs (GPS time). UT1 is approximated by UTC (|UT1 − UTC| < 0.9 s: < 0.004°).
    """
    t = np.atleast_1d(np.asarray(times, dtype="datetime64[ns]"))
    days_tt = ((t - J2000_TT).astype("int64") * 1e-9 + _GPS_TT_OFFSET_S) / 86400.0
    mean_lon = np.radians(280.460 + 0.9856474 * days_tt)
    g = np.radians(357.528 + 0.9856003 * days_tt)
    lon = mean_lon + np.radians(1.915 * np.sin(g) + 0.020 * np.sin(2 * g))
    r = (1.00014 - 0.01671 * np.cos(g) - 0.00014 * np.cos(2 * g)) * AU_M
    eps = np.radians(23.439 - 4.0e-7 * days_tt)
    x = r * np.cos(lon)
    y = r * np.sin(lon) * np.cos(eps)
    z = r * np.sin(lon) * np.sin(eps)
    days_utc = days_tt - (TT_MINUS_TAI_S + tai_minus_utc_s(t)) / 86400.0
    gmst = erfa.gmst82(JD_J2000, days_utc)
    c, s = np.cos(gmst), np.sin(gmst)
    return np.stack([c * x + s * y, -s * x + c * y, z], axis=-1)


def gnss_body_axes(pos_m: np.ndarray, sun_m: np.ndarray) -> np.ndarray:
    """Yaw-steering body axes (rows X, Y, Z), shape (..., 3, 3), in the frame of the inputs.

    Parameters
    ----------
    pos_m : ndarray, shape (..., 3)
        Satellite positions [m].
    sun_m : ndarray, shape (..., 3)
        Sun positions in the same frame [m] (broadcast against ``pos_m``).
    """
    ez = -pos_m / np.linalg.norm(pos_m, axis=-1, keepdims=True)
    to_sun = sun_m - pos_m
    ey = np.cross(ez, to_sun)
    ey /= np.linalg.norm(ey, axis=-1, keepdims=True)
    ex = np.cross(ey, ez)
    return np.stack([ex, ey, ez], axis=-2)


def satellite_pco_if(antex, sv, epoch, system: str, bands: tuple[str, str],
                     f1_hz: float, f2_hz: float) -> np.ndarray:
    """Ionosphere-free phase-centre offsets of satellites in their body frame [m].

    Parameters
    ----------
    antex : leopod.io.antex.AntexFile
    sv : sequence of str, shape (s,)
        Satellite ids (``"G05"``).
    epoch : datetime64
        Epoch that selects the antenna entry valid for each PRN.
    system : str
        GNSS letter.
    bands : (str, str)
        RINEX band digits of the two frequencies (``("1", "2")``).
    f1_hz, f2_hz : float

    Returns
    -------
    ndarray, shape (s, 3)
        Body-frame offsets (x, y, z) [m]; NaN rows for satellites without an entry.
    """
    out = np.full((len(sv), 3), np.nan)
    for j, prn in enumerate(sv):
        try:
            pattern = antex.satellite(str(prn), epoch)
            p1 = pattern.pco_m(f"{system}{int(bands[0]):02d}")
            p2 = pattern.pco_m(f"{system}{int(bands[1]):02d}")
        except KeyError:
            continue
        out[j] = ionosphere_free(p1, p2, f1_hz, f2_hz)
    return out
