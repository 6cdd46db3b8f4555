"""Geocentric Sun and Moon positions from a JPL planetary ephemeris (default DE421).

JPL DE421 (Folkner et al. 2008, IPN Progress Report 42-178), shipped in the ``skyfield-data``
package and read with ``jplephem``; positions are ICRF-aligned, i.e. GCRF axes for geocentric
vectors. The time argument of DE421 is TDB; TT is used instead (|TDB−TT| < 2 ms, which moves
the Moon by < 2 m and changes a LEO's lunar acceleration by < 1e-13 m/s²).
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np

from leopod.constants import JD_J2000

__all__ = ["Ephemeris"]


def _de421_path() -> Path:
    import skyfield_data

    return Path(skyfield_data.__file__).parent / "data" / "de421.bsp"


@lru_cache(maxsize=2)
def _kernel(path: str):
    from jplephem.spk import SPK

    return SPK.open(path)


class Ephemeris:
    """Geocentric Sun and Moon positions from a JPL SPK kernel (default DE421).

    Parameters
    ----------
    path : str or Path, optional
        SPK file; default: DE421 from the skyfield-data package.
    """

    def __init__(self, path: str | Path | None = None):
        self.path = str(path or _de421_path())
        self._spk = _kernel(self.path)

    def _vec(self, center: int, target: int, jd1, jd2) -> np.ndarray:
        return np.asarray(self._spk[center, target].compute(jd1, jd2)).T * 1e3

    def moon_m(self, t_tt_s_j2000) -> np.ndarray:
        """Geocentric Moon position [m], shape (n, 3), at TT seconds since J2000.0."""
        jd1, jd2 = _jd(t_tt_s_j2000)
        return self._vec(3, 301, jd1, jd2) - self._vec(3, 399, jd1, jd2)

    def sun_m(self, t_tt_s_j2000) -> np.ndarray:
        """Geocentric Sun position [m], shape (n, 3), at TT seconds since J2000.0."""
        jd1, jd2 = _jd(t_tt_s_j2000)
        earth = self._vec(0, 3, jd1, jd2) + self._vec(3, 399, jd1, jd2)
        return self._vec(0, 10, jd1, jd2) - earth


def _jd(t_s):
    """Two-part Julian date (TT used for TDB) from seconds since J2000.0."""
    t = np.atleast_1d(np.asarray(t_s, dtype=float))
    days = np.floor(t / 86400.0)
    return JD_J2000 + days, (t - days * 86400.0) / 86400.0
