"""Nominal attitude of GNSS satellites and their antenna phase-centre offsets.

Yaw-steering attitude (IGS convention, Montenbruck et al. 2015, Adv. Space Res. 56:1015):
+Z points to the geocentre, +Y = Z × e_sun (along the solar-panel axis), +X = Y × Z completes
the frame so that +X points to the Sun-lit hemisphere. The antenna phase centre is
``r_com + x e_X + y e_Y + z e_Z`` with the ANTEX offset (x, y, z).

The Sun position is the low-precision series of Montenbruck & Gill (Satellite Orbits, 2000,
sec. 3.3.2; ~0.1–1 % in distance, ~0.01° in direction), rotated to Earth-fixed axes with
GMST (IAU 1982, pyerfa) — ample for orienting antenna offsets of at most a few metres.
"""

from __future__ import annotations

import erfa
import numpy as np

from leopod.constants import GPST_MINUS_TAI_S, JD_J2000, TT_MINUS_TAI_S
from leopod.gnss.combinations import ionosphere_free
from leopod.time import J2000_TT

__all__ = ["sun_position_ef", "gnss_body_axes", "satellite_pco_if"]

_GPS_TT_OFFSET_S = TT_MINUS_TAI_S - GPST_MINUS_TAI_S   # TT - GPST = 51.184 s (exact)


def sun_position_ef(times) -> np.ndarray:
    """Low-precision Earth-fixed Sun position [m], shape (n, 3), at GPS-time epochs.

    Parameters
    ----------
    times : array_like of datetime64
        Epochs (GPS time). UT1 is approximated by GPS time for GMST (error < 0.01° in the
        direction over the leap seconds of the GPS era), which the use here tolerates.
    """
    t = np.atleast_1d(np.asarray(times, dtype="datetime64[ns]"))
    days_tt = ((t - J2000_TT).astype("int64") * 1e-9 + _GPS_TT_OFFSET_S) / 86400.0
    cent = days_tt / 36525.0
    m = np.radians(357.5256 + 35999.049 * cent)
    lon = np.radians(282.9400) + m + np.radians((6892.0 * np.sin(m) + 72.0 * np.sin(2 * m)) / 3600.0)
    r = (149.619 - 2.499 * np.cos(m) - 0.021 * np.cos(2 * m)) * 1e9
    eps = np.radians(23.43929111)
    x = r * np.cos(lon)
    y = r * np.sin(lon) * np.cos(eps)
    z = r * np.sin(lon) * np.sin(eps)
    gmst = erfa.gmst82(JD_J2000, days_tt - _GPS_TT_OFFSET_S / 86400.0)
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
