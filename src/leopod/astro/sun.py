"""Low-precision Sun position in Earth-fixed axes.

The series of Montenbruck & Gill (Satellite Orbits, 2000, sec. 3.3.2; ~0.1–1 % in distance,
~0.01° in direction), rotated to Earth-fixed axes with GMST (IAU 1982, pyerfa): ample for
orienting GNSS attitude and antenna offsets of at most a few metres. Precise Sun and Moon
positions for the force model come from :mod:`leopod.astro.ephemeris` (JPL DE421).
"""

from __future__ import annotations

import erfa
import numpy as np

from leopod.constants import GPST_MINUS_TAI_S, JD_J2000, TT_MINUS_TAI_S
from leopod.time.calendar import J2000_TT

__all__ = ["sun_position_ef"]

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
