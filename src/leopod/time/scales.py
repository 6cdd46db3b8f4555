"""Time scales (GPST, BDT, GST, TAI, TT, UTC) and two-part Julian dates.

Epochs are ``numpy.datetime64[ns]`` labels holding **GPS-time** readings (see
:mod:`leopod.time.calendar`). The offsets GPST -> TAI (+19 s) and TAI -> TT (+32.184 s) are
exact and applied in integer nanoseconds, as are BDT -> GPST (+14 s) and GST -> GPST (0 s);
:func:`to_gps_time` brings labels of any supported system to GPST; TAI - UTC (leap seconds) comes from the IERS
``Leap_Second.dat`` shipped with astropy-iers-data, never from the network.

Two-part Julian dates follow the erfa "date & time" split: ``jd1`` is the Julian date of the
preceding midnight (a half-integer, exact in float64) and ``jd2`` the fraction of day in
[0, 1) for TAI/TT (UT1 may fall slightly outside), so that a float64 ``jd2`` keeps ~1e-11 s.
UT1 and the other Earth orientation parameters are in :mod:`leopod.time.eop`.
"""

from __future__ import annotations

import functools

import numpy as np
from astropy_iers_data import IERS_LEAP_SECOND_FILE

from leopod.constants import BDT_MINUS_GPST_S, GPST_MINUS_TAI_S, GST_MINUS_GPST_S, TT_MINUS_TAI_S

__all__ = [
    "gps_to_tai",
    "gps_to_tt",
    "gps_to_utc",
    "jd_tai",
    "jd_tt",
    "julian_centuries_tt",
    "tai_minus_utc_s",
    "to_gps_time",
    "utc_to_gps",
    "TIME_SYSTEMS_TO_GPS",
]

_NS_PER_S = 1_000_000_000
_NS_PER_DAY = 86_400 * _NS_PER_S
#: Julian date and MJD of 1970-01-01T00:00, the origin of datetime64 (exact).
_JD_DATETIME64_EPOCH = 2_440_587.5
_MJD_DATETIME64_EPOCH = 40_587
#: Julian date of J2000.0 (2000-01-01T12:00 TT) and days per Julian century (IAU).
_JD_J2000 = 2_451_545.0
_DAYS_PER_CENTURY = 36_525.0
_GPST_TO_TAI_NS = round(-GPST_MINUS_TAI_S * _NS_PER_S)
_TAI_TO_TT_NS = round(TT_MINUS_TAI_S * _NS_PER_S)


# --------------------------------------------------------------------------- leap seconds
@functools.lru_cache(maxsize=4)
def _leap_second_table(path: str = IERS_LEAP_SECOND_FILE) -> tuple[np.ndarray, np.ndarray]:
    """MJD (UTC) from which each TAI-UTC value holds, and the values [s] (IERS Bulletin C)."""
    table = np.loadtxt(path, comments="#", ndmin=2)
    return table[:, 0].astype(np.int64), table[:, 4]


def _as_ns(times) -> np.ndarray:
    """Nanoseconds since 1970-01-01 of datetime64 labels, int64, at least 1-D."""
    return np.atleast_1d(np.asarray(times, dtype="datetime64[ns]")).astype(np.int64)


def _tai_minus_utc_from_tai_ns(tai_ns: np.ndarray) -> np.ndarray:
    mjd, dat = _leap_second_table()
    start_tai_ns = (mjd - _MJD_DATETIME64_EPOCH) * _NS_PER_DAY + np.round(dat * _NS_PER_S)
    k = np.searchsorted(start_tai_ns, tai_ns, side="right") - 1
    if np.any(k < 0):
        raise ValueError("epoch before 1972-01-01: TAI-UTC is not tabulated in Leap_Second.dat")
    return dat[k]


def tai_minus_utc_s(times) -> np.ndarray:
    """TAI - UTC [s] (leap seconds, IERS Bulletin C) at GPS-time epochs.

    Parameters
    ----------
    times : array_like of datetime64, shape (n,)
        GPS-time labels.

    Returns
    -------
    ndarray, shape (n,)
        TAI - UTC [s]; during an inserted leap second the previous value still holds.
    """
    return _tai_minus_utc_from_tai_ns(_as_ns(times) + _GPST_TO_TAI_NS)


def gps_to_tai(times) -> np.ndarray:
    """TAI labels (datetime64[ns]) of GPS-time epochs: TAI = GPST + 19 s (exact)."""
    return (_as_ns(times) + _GPST_TO_TAI_NS).astype("datetime64[ns]")


def gps_to_tt(times) -> np.ndarray:
    """TT labels (datetime64[ns]) of GPS-time epochs: TT = GPST + 51.184 s (exact)."""
    return (_as_ns(times) + _GPST_TO_TAI_NS + _TAI_TO_TT_NS).astype("datetime64[ns]")


def gps_to_utc(times) -> np.ndarray:
    """UTC labels (datetime64[ns]) of GPS-time epochs, UTC = TAI - (TAI - UTC).

    datetime64 cannot show 23:59:60: an epoch inside an inserted leap second gets the label
    of the first second of the next day (those labels occur twice).
    """
    tai_ns = _as_ns(times) + _GPST_TO_TAI_NS
    dat_ns = np.round(_tai_minus_utc_from_tai_ns(tai_ns) * _NS_PER_S).astype(np.int64)
    return (tai_ns - dat_ns).astype("datetime64[ns]")


def utc_to_gps(times_utc) -> np.ndarray:
    """GPS-time labels (datetime64[ns]) of UTC epochs (e.g. SLR normal points).

    Parameters
    ----------
    times_utc : array_like of datetime64, shape (n,)
        UTC labels (no 23:59:60).
    """
    utc_ns = _as_ns(times_utc)
    mjd, dat = _leap_second_table()
    k = np.searchsorted((mjd - _MJD_DATETIME64_EPOCH) * _NS_PER_DAY, utc_ns, side="right") - 1
    if np.any(k < 0):
        raise ValueError("epoch before 1972-01-01: TAI-UTC is not tabulated in Leap_Second.dat")
    dat_ns = np.round(dat[k] * _NS_PER_S).astype(np.int64)
    return (utc_ns + dat_ns - _GPST_TO_TAI_NS).astype("datetime64[ns]")


#: Time systems whose labels :func:`to_gps_time` converts to GPS time, with the constant
#: label offset system - GPST [s] (None: UTC, converted with the leap seconds). The keys are
#: the identifiers of RINEX 3.04 / RINEX clock 3.04 / SP3-d headers (GPS, GAL, BDT, TAI, UTC)
#: plus TT (IERS Conventions 2010, ch. 10).
TIME_SYSTEMS_TO_GPS: dict[str, float | None] = {
    "GPS": 0.0,
    "GAL": GST_MINUS_GPST_S,
    "BDT": BDT_MINUS_GPST_S,
    "TAI": -GPST_MINUS_TAI_S,
    "TT": TT_MINUS_TAI_S - GPST_MINUS_TAI_S,
    "UTC": None,
}

#: Why the other time-system identifiers of the RINEX / SP3 formats are not converted.
_UNSUPPORTED = {
    "GLO": "GLONASS time is UTC(SU) + 3 h, with leap seconds; leopod does not process "
           "GLONASS and does not convert GLONASS time",
    "QZS": "QZSS time is not converted by leopod (no QZSS signals in leopod.signals)",
    "IRN": "IRNSS/NavIC time is not converted by leopod (no IRNSS signals in leopod.signals)",
}


def to_gps_time(times, time_system: str) -> np.ndarray:
    """GPS-time labels of epochs labelled in another GNSS or astronomical time system.

    The offsets are exact and leap-second free: BDT = GPST - 14 s (BDS-SIS-ICD-B1I-3.0,
    IS-GPS-200), GST = GPST (Galileo OS SIS ICD 2.0), TAI = GPST + 19 s, TT = GPST + 51.184 s
    (IERS Conventions 2010, ch. 10); UTC labels use the leap seconds (:func:`utc_to_gps`).

    Parameters
    ----------
    times : array_like of datetime64, shape (n,)
        Labels in ``time_system``.
    time_system : str
        ``GPS``, ``GAL``, ``BDT``, ``TAI``, ``TT`` or ``UTC`` (case-insensitive, blanks
        stripped; the aliases ``GPST``, ``GST`` and ``BDS`` are accepted).

    Returns
    -------
    ndarray of datetime64[ns], shape (n,)
        GPS-time labels, converted in integer nanoseconds.

    Raises
    ------
    ValueError
        For GLONASS, QZSS and IRNSS time (not supported, the message says why) and for
        any other identifier.
    """
    system = time_system.strip().upper()
    system = {"GPST": "GPS", "GST": "GAL", "BDS": "BDT"}.get(system, system)
    ns = _as_ns(times)
    if system not in TIME_SYSTEMS_TO_GPS:
        why = _UNSUPPORTED.get(system, "unknown time system (known: "
                               + ", ".join(TIME_SYSTEMS_TO_GPS) + ")")
        raise ValueError(f"time system '{time_system}': {why}")
    offset_s = TIME_SYSTEMS_TO_GPS[system]
    if offset_s is None:
        return utc_to_gps(ns.astype("datetime64[ns]"))
    return (ns - round(offset_s * _NS_PER_S)).astype("datetime64[ns]")


# --------------------------------------------------------------------------- Julian dates
def _two_part_jd(ns: np.ndarray, extra_s=0.0) -> tuple[np.ndarray, np.ndarray]:
    """(jd1, jd2) of integer nanoseconds since 1970 plus ``extra_s`` seconds (float)."""
    day, rem_ns = np.divmod(ns, _NS_PER_DAY)
    jd1 = _JD_DATETIME64_EPOCH + day.astype(float)
    jd2 = (rem_ns.astype(float) + np.asarray(extra_s, dtype=float) * _NS_PER_S) / _NS_PER_DAY
    return jd1, jd2


def jd_tai(times) -> tuple[np.ndarray, np.ndarray]:
    """Two-part Julian date (jd1, jd2) of TAI at GPS-time epochs, shape (n,) each."""
    return _two_part_jd(_as_ns(times) + _GPST_TO_TAI_NS)


def jd_tt(times) -> tuple[np.ndarray, np.ndarray]:
    """Two-part Julian date (jd1, jd2) of TT at GPS-time epochs, shape (n,) each.

    ``jd1`` is a half-integer (preceding TT midnight), ``jd2`` in [0, 1); resolution ~1e-11 s.
    """
    return _two_part_jd(_as_ns(times) + _GPST_TO_TAI_NS + _TAI_TO_TT_NS)


def julian_centuries_tt(times) -> np.ndarray:
    """TT Julian centuries since J2000.0 at GPS-time epochs, shape (n,) (IERS 2010 eq. 5.2)."""
    return _centuries(*jd_tt(times))


def _centuries(jd1: np.ndarray, jd2: np.ndarray) -> np.ndarray:
    return ((jd1 - _JD_J2000) + jd2) / _DAYS_PER_CENTURY
