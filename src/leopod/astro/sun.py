"""Low-precision Sun position in Earth-fixed axes.

The low-precision formula of the Astronomical Almanac (section C, "Low precision formulas for
the Sun": mean equinox of date, 0.01° over 1950–2050), rotated to Earth-fixed axes with GMST
(IAU 1982, pyerfa) of UT1 ≈ UTC: ample for orienting GNSS attitude and antenna offsets of at
most a few metres. (This was formerly Montenbruck & Gill's series, which refers to the J2000
equinox; rotated with the GMST of date and of UT1 ≈ GPS time it was off by 0.2° in 2007 and
0.5° in 2023: tests/gnss/test_gnss_attitude.py compares with pyerfa.) Precise Sun and Moon
positions for the force model come from :mod:`leopod.astro.ephemeris` (JPL DE421).
"""

from __future__ import annotations

import erfa
import numpy as np

from leopod.constants import AU_M, GPST_MINUS_TAI_S, JD_J2000, TT_MINUS_TAI_S
from leopod.time.calendar import J2000_TT
from leopod.time.scales import tai_minus_utc_s

__all__ = ["sun_position_ef"]

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
