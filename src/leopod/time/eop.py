"""Earth orientation parameters: IERS series, interpolation and sub-daily tidal terms.

EOP come from the IERS 20 C04 series (astropy-iers-data ``IERS_B_FILE``) extended by the IERS
rapid service/prediction file finals2000A (``IERS_A_FILE``) after the end of C04, or from any
finals2000A file. They are interpolated as the IERS recommends (IERS Conventions 2010, sec.
5.5.1; IERS Gazette 13 / ``interp.f``): 4-point Lagrange interpolation of the daily values with
UT1 handled as UT1-TAI (continuous across leap seconds), plus the diurnal/semi-diurnal
ocean-tide terms in polar motion and UT1 (IERS Conventions 2010, Tables 8.2a/b and 8.3a/b, the
71-term ``PMUT1_OCEANS`` model) and the libration terms (Tables 5.1a diurnal part, 5.1b). Not
modelled: the zonal tides in UT1 are not removed before interpolation (the cubic interpolation
error they cause is < 1 µs), and LOD is returned as interpolated daily values (sub-daily tidal
LOD, < 0.15 ms, is not added). Time scales and Julian dates are in :mod:`leopod.time.scales`.
"""

from __future__ import annotations

import functools
import io
import logging
from dataclasses import dataclass, fields
from pathlib import Path

import erfa
import numba
import numpy as np
from astropy_iers_data import IERS_A_FILE, IERS_B_FILE

from leopod.constants import SECONDS_PER_DAY
from leopod.numerics.interpolate import interpolate_table
from leopod.time.scales import (
    _GPST_TO_TAI_NS,
    _MJD_DATETIME64_EPOCH,
    _NS_PER_DAY,
    _TAI_TO_TT_NS,
    _as_ns,
    _centuries,
    _leap_second_table,
    _tai_minus_utc_from_tai_ns,
    _two_part_jd,
)

__all__ = [
    "EarthOrientation",
    "EopValues",
    "default_earth_orientation",
    "jd_ut1",
    "libration_eop",
    "ocean_tide_eop",
]

logger = logging.getLogger(__name__)

_UAS_TO_RAD = erfa.DAS2R * 1e-6


def jd_ut1(times, eop: EarthOrientation | EopValues | None = None):
    """Two-part Julian date (jd1, jd2) of UT1 at GPS-time epochs, UT1 = TAI + (UT1 - TAI).

    Parameters
    ----------
    times : array_like of datetime64, shape (n,)
        GPS-time labels.
    eop : EarthOrientation or EopValues, optional
        EOP source, or values already evaluated at ``times``; default
        :func:`default_earth_orientation`.
    """
    if eop is None:
        eop = default_earth_orientation()
    if isinstance(eop, EarthOrientation):
        eop = eop.at(times)
    return _two_part_jd(_as_ns(times) + _GPST_TO_TAI_NS, eop.ut1_minus_tai_s)


# --------------------------------------------------------------------------- sub-daily EOP
def _parse_table(text: str, ncol: int) -> np.ndarray:
    return np.loadtxt(io.StringIO(text), ndmin=2).reshape(-1, ncol)


# Multipliers of (GMST + pi, l, l', F, D, Omega); x sin, x cos, y sin, y cos [µas];
# UT1 sin, UT1 cos [µs]. IERS Conventions 2010, Tables 8.2a, 8.2b, 8.3a, 8.3b (diurnal and
# semi-diurnal ocean-tide EOP variations, Ray et al. 1994; the PMUT1_OCEANS listing of interp.f).
_OCEAN_TIDES = _parse_table("""
1 -1  0 -2 -2 -2    -0.05    0.94   -0.94   -0.05   0.396  -0.078
1 -2  0 -2  0 -1     0.06    0.64   -0.64    0.06   0.195  -0.059
1 -2  0 -2  0 -2     0.30    3.42   -3.42    0.30   1.034  -0.314
1  0  0 -2 -2 -1     0.08    0.78   -0.78    0.08   0.224  -0.073
1  0  0 -2 -2 -2     0.46    4.15   -4.15    0.45   1.187  -0.387
1 -1  0 -2  0 -1     1.19    4.96   -4.96    1.19   0.966  -0.474
1 -1  0 -2  0 -2     6.24   26.31  -26.31    6.23   5.118  -2.499
1  1  0 -2 -2 -1     0.24    0.94   -0.94    0.24   0.172  -0.090
1  1  0 -2 -2 -2     1.28    4.99   -4.99    1.28   0.911  -0.475
1  0  0 -2  0  0    -0.28   -0.77    0.77   -0.28  -0.093   0.070
1  0  0 -2  0 -1     9.22   25.06  -25.06    9.22   3.025  -2.280
1  0  0 -2  0 -2    48.82  132.91 -132.90   48.82  16.020 -12.069
1 -2  0  0  0  0    -0.32   -0.86    0.86   -0.32  -0.103   0.078
1  0  0  0 -2  0    -0.66   -1.72    1.72   -0.66  -0.194   0.154
1 -1  0 -2  2 -2    -0.42   -0.92    0.92   -0.42  -0.083   0.074
1  1  0 -2  0 -1    -0.30   -0.64    0.64   -0.30  -0.057   0.050
1  1  0 -2  0 -2    -1.61   -3.46    3.46   -1.61  -0.308   0.271
1 -1  0  0  0  0    -4.48   -9.61    9.61   -4.48  -0.856   0.751
1 -1  0  0  0 -1    -0.90   -1.93    1.93   -0.90  -0.172   0.151
1  1  0  0 -2  0    -0.86   -1.81    1.81   -0.86  -0.161   0.137
1  0 -1 -2  2 -2     1.54    3.03   -3.03    1.54   0.315  -0.189
1  0  0 -2  2 -1    -0.29   -0.58    0.58   -0.29  -0.062   0.035
1  0  0 -2  2 -2    26.13   51.25  -51.25   26.13   5.512  -3.095
1  0  1 -2  2 -2    -0.22   -0.42    0.42   -0.22  -0.047   0.025
1  0 -1  0  0  0    -0.61   -1.20    1.20   -0.61  -0.134   0.070
1  0  0  0  0  1     1.54    3.00   -3.00    1.54   0.348  -0.171
1  0  0  0  0  0   -77.48 -151.74  151.74  -77.48 -17.620   8.548
1  0  0  0  0 -1   -10.52  -20.56   20.56  -10.52  -2.392   1.159
1  0  0  0  0 -2     0.23    0.44   -0.44    0.23   0.052  -0.025
1  0  1  0  0  0    -0.61   -1.19    1.19   -0.61  -0.144   0.065
1  0  0  2 -2  2    -1.09   -2.11    2.11   -1.09  -0.267   0.111
1 -1  0  0  2  0    -0.69   -1.43    1.43   -0.69  -0.288   0.043
1  1  0  0  0  0    -3.46   -7.28    7.28   -3.46  -1.610   0.187
1  1  0  0  0 -1    -0.69   -1.44    1.44   -0.69  -0.320   0.037
1  0  0  0  2  0    -0.37   -1.06    1.06   -0.37  -0.407  -0.005
1  2  0  0  0  0    -0.17   -0.51    0.51   -0.17  -0.213  -0.005
1  0  0  2  0  2    -1.10   -3.42    3.42   -1.09  -1.436  -0.037
1  0  0  2  0  1    -0.70   -2.19    2.19   -0.70  -0.921  -0.023
1  0  0  2  0  0    -0.15   -0.46    0.46   -0.15  -0.193  -0.005
1  1  0  2  0  2    -0.03   -0.59    0.59   -0.03  -0.396  -0.024
1  1  0  2  0  1    -0.02   -0.38    0.38   -0.02  -0.253  -0.015
2 -3  0 -2  0 -2    -0.49   -0.04    0.63    0.24  -0.089  -0.011
2 -1  0 -2 -2 -2    -1.33   -0.17    1.53    0.68  -0.224  -0.032
2 -2  0 -2  0 -2    -6.08   -1.61    3.13    3.35  -0.637  -0.177
2  0  0 -2 -2 -2    -7.59   -2.05    3.44    4.23  -0.745  -0.222
2  0  1 -2 -2 -2    -0.52   -0.14    0.22    0.29  -0.049  -0.015
2 -1 -1 -2  0 -2     0.47    0.11   -0.10   -0.27   0.033   0.013
2 -1  0 -2  0 -1     2.12    0.49   -0.41   -1.23   0.141   0.058
2 -1  0 -2  0 -2   -56.87  -12.93   11.15   32.88  -3.795  -1.556
2 -1  1 -2  0 -2    -0.54   -0.12    0.10    0.31  -0.035  -0.015
2  1  0 -2 -2 -2   -11.01   -2.40    1.89    6.41  -0.698  -0.298
2  1  1 -2 -2 -2    -0.51   -0.11    0.08    0.30  -0.032  -0.014
2 -2  0 -2  2 -2     0.98    0.11   -0.11   -0.58   0.050   0.022
2  0 -1 -2  0 -2     1.13    0.11   -0.13   -0.67   0.056   0.025
2  0  0 -2  0 -1    12.32    1.00   -1.41   -7.31   0.605   0.266
2  0  0 -2  0 -2  -330.15  -26.96   37.58  195.92 -16.195  -7.140
2  0  1 -2  0 -2    -1.01   -0.07    0.11    0.60  -0.049  -0.021
2 -1  0 -2  2 -2     2.47   -0.28   -0.44   -1.48   0.111   0.034
2  1  0 -2  0 -2     9.40   -1.44   -1.88   -5.65   0.425   0.117
2 -1  0  0  0  0    -2.35    0.37    0.47    1.41  -0.106  -0.029
2 -1  0  0  0 -1    -1.04    0.17    0.21    0.62  -0.047  -0.013
2  0 -1 -2  2 -2    -8.51    3.50    3.29    5.11  -0.437  -0.019
2  0  0 -2  2 -2  -144.13   63.56   59.23   86.56  -7.547  -0.159
2  0  1 -2  2 -2     1.19   -0.56   -0.52   -0.72   0.064   0.000
2  0  0  0  0  1     0.49   -0.25   -0.23   -0.29   0.027  -0.001
2  0  0  0  0  0   -38.48   19.14   17.72   23.11  -2.104   0.041
2  0  0  0  0 -1   -11.44    5.75    5.32    6.87  -0.627   0.015
2  0  0  0  0 -2    -1.24    0.63    0.58    0.75  -0.068   0.002
2  1  0  0  0  0    -1.77    1.79    1.71    1.04  -0.146   0.037
2  1  0  0  0 -1    -0.77    0.78    0.75    0.45  -0.064   0.017
2  0  0  2  0  2    -0.33    0.62    0.65    0.19  -0.049   0.018
""", 12)

# Diurnal libration in polar motion: multipliers; x sin, x cos, y sin, y cos [µas].
# IERS Conventions 2010, Table 5.1a (quasi-diurnal part; the long-period part is in the EOP).
_PM_LIBRATION = _parse_table("""
1 -1  0 -2  0 -1    -0.4   0.3  -0.3  -0.4
1 -1  0 -2  0 -2    -2.3   1.3  -1.3  -2.3
1  1  0 -2 -2 -2    -0.4   0.3  -0.3  -0.4
1  0  0 -2  0 -1    -2.1   1.2  -1.2  -2.1
1  0  0 -2  0 -2   -11.4   6.5  -6.5 -11.4
1 -1  0  0  0  0     0.8  -0.5   0.5   0.8
1  0  0 -2  2 -2    -4.8   2.7  -2.7  -4.8
1  0  0  0  0  0    14.3  -8.2   8.2  14.3
1  0  0  0  0 -1     1.9  -1.1   1.1   1.9
1  1  0  0  0  0     0.8  -0.4   0.4   0.8
""", 10)

# Semi-diurnal libration in UT1: multipliers; UT1 sin, UT1 cos [µs].
# IERS Conventions 2010, Table 5.1b.
_UT1_LIBRATION = _parse_table("""
2 -2  0 -2  0 -2     0.05  -0.03
2  0  0 -2 -2 -2     0.06  -0.03
2 -1  0 -2  0 -2     0.35  -0.20
2  1  0 -2 -2 -2     0.07  -0.04
2  0  0 -2  0 -1    -0.07   0.04
2  0  0 -2  0 -2     1.75  -1.01
2  1  0 -2  0 -2    -0.05   0.03
2  0 -1 -2  2 -2     0.04  -0.03
2  0  0 -2  2 -2     0.76  -0.44
2  0  0  0  0  0     0.21  -0.12
2  0  0  0  0 -1     0.06  -0.04
""", 8)


def _tidal_arguments(t_tt_cy: np.ndarray, gmst_rad: np.ndarray) -> np.ndarray:
    """(GMST + pi, l, l', F, D, Omega) [rad], shape (6, n) (IERS Conventions 2010, eq. 5.43)."""
    t = np.asarray(t_tt_cy, dtype=float)
    return np.stack([np.asarray(gmst_rad, dtype=float) + np.pi, erfa.fal03(t), erfa.falp03(t),
                     erfa.faf03(t), erfa.fad03(t), erfa.faom03(t)])


@numba.njit(cache=True)
def _harmonic_sum(table: np.ndarray, args: np.ndarray) -> np.ndarray:
    """Σ_j (a_j sin θ_j + b_j cos θ_j), θ_j = table[j, :6] · args, per (sin, cos) column pair.

    ``table`` has shape (lines, 6 + 2k), ``args`` (6, n); returns shape (k, n).
    """
    n_out = (table.shape[1] - 6) // 2
    out = np.zeros((n_out, args.shape[1]))
    for i in range(args.shape[1]):
        for j in range(table.shape[0]):
            theta = 0.0
            for a in range(6):
                theta += table[j, a] * args[a, i]
            sin, cos = np.sin(theta), np.cos(theta)
            for k in range(n_out):
                out[k, i] += table[j, 6 + 2 * k] * sin + table[j, 7 + 2 * k] * cos
    return out


def ocean_tide_eop(t_tt_cy, gmst_rad):
    """Diurnal/semi-diurnal ocean-tide variations of polar motion and UT1.

    IERS Conventions 2010, sec. 8.2, Tables 8.2a/b (pole) and 8.3a/b (UT1): 71 tidal lines.
    They agree with the Class-1 routine ORTHO_EOP to a few µas and a few 0.1 µs.

    Parameters
    ----------
    t_tt_cy : array_like, shape (n,)
        TT Julian centuries since J2000.0 (for the Delaunay arguments).
    gmst_rad : array_like, shape (n,)
        Greenwich mean sidereal time [rad] (from UT1).

    Returns
    -------
    dxp_rad, dyp_rad, dut1_s : ndarray, shape (n,)
        Corrections to add to the interpolated x_p, y_p [rad] and UT1 [s].
    """
    x, y, ut1 = _harmonic_sum(_OCEAN_TIDES, _tidal_arguments(t_tt_cy, gmst_rad))
    return x * _UAS_TO_RAD, y * _UAS_TO_RAD, ut1 * 1e-6


def libration_eop(t_tt_cy, gmst_rad):
    """Libration (tidal gravitation on the triaxial Earth) in polar motion and UT1.

    IERS Conventions 2010, sec. 5.5.1.2 and 5.5.3.3: Table 5.1a (10 diurnal terms, < 20 µas)
    and Table 5.1b (11 semi-diurnal UT1 terms, < 3 µs). Same arguments as
    :func:`ocean_tide_eop`.

    Returns
    -------
    dxp_rad, dyp_rad, dut1_s : ndarray, shape (n,)
    """
    args = _tidal_arguments(t_tt_cy, gmst_rad)
    x, y = _harmonic_sum(_PM_LIBRATION, args)
    (ut1,) = _harmonic_sum(_UT1_LIBRATION, args)
    return x * _UAS_TO_RAD, y * _UAS_TO_RAD, ut1 * 1e-6


# --------------------------------------------------------------------------- EOP tables
@dataclass(frozen=True)
class EopValues:
    """Earth orientation parameters at a set of epochs (every field has shape (n,)).

    Attributes
    ----------
    xp_rad, yp_rad : ndarray
        Pole coordinates x_p, y_p of the CIP in the ITRS [rad].
    dut1_s : ndarray
        UT1 - UTC [s] (jumps by 1 s at leap seconds).
    ut1_minus_tai_s : ndarray
        UT1 - TAI [s] (continuous).
    lod_s : ndarray
        Excess length of day [s] (daily values, interpolated).
    dx_rad, dy_rad : ndarray
        Celestial pole offsets dX, dY w.r.t. the IAU 2006/2000A model [rad].
    """

    xp_rad: np.ndarray
    yp_rad: np.ndarray
    dut1_s: np.ndarray
    ut1_minus_tai_s: np.ndarray
    lod_s: np.ndarray
    dx_rad: np.ndarray
    dy_rad: np.ndarray

    def subset(self, index) -> EopValues:
        """The values at ``index`` (any numpy index of the epoch axis)."""
        return EopValues(**{f.name: getattr(self, f.name)[index] for f in fields(self)})


def _float_or_nan(text: str) -> float:
    text = text.strip()
    return float(text) if text else np.nan


@functools.lru_cache(maxsize=4)
def _read_c04(path: str) -> np.ndarray:
    """IERS 20 C04 columns MJD, x ["], y ["], UT1-UTC [s], dX ["], dY ["], LOD [s]."""
    with open(path) as f:
        first = next((line for line in f if line.strip() and not line.startswith("#")), "")
    if len(first.split()) != 21:
        raise ValueError(f"{path}: expected the 21 columns of IERS 20 C04, got "
                         f"{len(first.split())}")
    # only the seven columns used are converted (2.5 times faster than all 21)
    return np.loadtxt(path, comments="#", ndmin=2, usecols=(4, 5, 6, 7, 8, 9, 12))


@functools.lru_cache(maxsize=4)
def _read_finals(path: str) -> np.ndarray:
    """finals2000A Bulletin-A columns MJD, x ["], y ["], UT1-UTC [s], dX ["], dY ["], LOD [s].

    Rows without polar motion or UT1 are dropped; missing dX, dY (NaN) and LOD (NaN) are
    filled by :class:`EarthOrientation`.
    """
    rows = []
    with open(path) as f:
        for lineno, line in enumerate(f, 1):
            try:
                rows.append([float(line[7:15]), _float_or_nan(line[18:27]),
                             _float_or_nan(line[37:46]), _float_or_nan(line[58:68]),
                             _float_or_nan(line[97:106]) * 1e-3,
                             _float_or_nan(line[116:125]) * 1e-3,
                             _float_or_nan(line[79:86]) * 1e-3])
            except ValueError as err:
                raise ValueError(f"{path}, line {lineno}: not a finals2000A record ({err})") from None
    table = np.array(rows, dtype=float).reshape(-1, 7)
    return table[np.isfinite(table[:, 1:4]).all(axis=1)]


def _forward_fill(values: np.ndarray) -> np.ndarray:
    """Replace NaN by the last finite value before it (leading NaN become 0)."""
    good = np.isfinite(values)
    last = np.maximum.accumulate(np.where(good, np.arange(values.size), -1))
    return np.where(last >= 0, values[np.maximum(last, 0)], 0.0)


class EarthOrientation:
    """Daily EOP table with IERS-recommended interpolation to arbitrary GPS-time epochs.

    Parameters
    ----------
    mjd_utc : array_like, shape (m,)
        Table epochs, MJD at 0h UTC, strictly increasing (at least 4).
    xp_rad, yp_rad : array_like, shape (m,)
        Pole coordinates [rad].
    dut1_s : array_like, shape (m,)
        UT1 - UTC [s].
    lod_s : array_like, shape (m,)
        Excess length of day [s]; NaN entries are replaced by -d(UT1-TAI)/dt of the table.
    dx_rad, dy_rad : array_like, shape (m,)
        Celestial pole offsets w.r.t. IAU 2006/2000A [rad]; NaN entries hold the last value.
    subdaily : bool
        Add the ocean-tide and libration terms (:func:`ocean_tide_eop`,
        :func:`libration_eop`) to the interpolated x_p, y_p and UT1 (default True).
    source : str
        Description of the data origin (for logs and provenance).
    """

    def __init__(self, mjd_utc, xp_rad, yp_rad, dut1_s, lod_s, dx_rad, dy_rad, *,
                 subdaily: bool = True, source: str = "user table"):
        mjd = np.asarray(mjd_utc, dtype=float)
        if mjd.size < 4 or np.any(np.diff(mjd) <= 0):
            raise ValueError(f"EOP table ({source}): need >= 4 strictly increasing epochs")
        mjd_int = np.round(mjd).astype(np.int64)
        # table epochs and UT1-TAI on the continuous TAI axis [s since 1970]
        tai_ns = (mjd_int - _MJD_DATETIME64_EPOCH) * _NS_PER_DAY
        mjd_ls, dat_ls = _leap_second_table()
        dat = dat_ls[np.clip(np.searchsorted(mjd_ls, mjd_int, side="right") - 1, 0, None)]
        self._t_tai_s = tai_ns * 1e-9 + dat
        ut1_tai = np.asarray(dut1_s, dtype=float) - dat
        lod = np.asarray(lod_s, dtype=float)
        lod = np.where(np.isfinite(lod), lod,
                       -np.gradient(ut1_tai, self._t_tai_s) * SECONDS_PER_DAY)
        self._columns = np.column_stack([xp_rad, yp_rad, ut1_tai, lod,
                                         _forward_fill(np.asarray(dx_rad, dtype=float)),
                                         _forward_fill(np.asarray(dy_rad, dtype=float))])
        self.mjd_utc = mjd
        self.subdaily = subdaily
        self.source = source

    @classmethod
    def from_iers_data(cls, c04_path: str | Path = IERS_B_FILE,
                       finals_path: str | Path | None = IERS_A_FILE, *,
                       subdaily: bool = True) -> EarthOrientation:
        """IERS 20 C04, extended after its last day by the finals2000A Bulletin-A values.

        By default both files come from the installed astropy-iers-data package. The C04
        celestial pole offsets refer to IAU 2006/2000A (IERS EOP 20 C04 product metadata);
        those of finals2000A are labelled "w.r.t. IAU2000A" but agree with C04 to 0.05 mas
        over 2000-2024 (a IAU 2000A reference would differ by up to 0.13 mas), so both are
        used as IAU 2006/2000A offsets.
        """
        table = _read_c04(str(c04_path))
        source = f"IERS 20 C04 ({c04_path})"
        if finals_path is not None:
            finals = _read_finals(str(finals_path))
            source += f" + finals2000A ({finals_path}) after MJD {table[-1, 0]:.0f}"
            table = np.vstack([table, finals[finals[:, 0] > table[-1, 0]]])
        return cls._from_arcsec_table(table, subdaily, source)

    @classmethod
    def from_finals(cls, path: str | Path, *, subdaily: bool = True) -> EarthOrientation:
        """EOP from an IERS finals2000A file (Bulletin-A columns, incl. predictions)."""
        return cls._from_arcsec_table(_read_finals(str(path)), subdaily, f"finals2000A ({path})")

    @classmethod
    def _from_arcsec_table(cls, t: np.ndarray, subdaily: bool, source: str):
        """Table rows MJD, x ["], y ["], UT1-UTC [s], dX ["], dY ["], LOD [s] from 1972 on
        (before 1972 UTC had no integer TAI-UTC)."""
        t = t[t[:, 0] >= _leap_second_table()[0][0]]
        logger.debug("EOP %s: MJD %.0f to %.0f", source, t[0, 0], t[-1, 0])
        return cls(t[:, 0], t[:, 1] * erfa.DAS2R, t[:, 2] * erfa.DAS2R, t[:, 3], t[:, 6],
                   t[:, 4] * erfa.DAS2R, t[:, 5] * erfa.DAS2R, subdaily=subdaily, source=source)

    def at(self, times) -> EopValues:
        """EOP at GPS-time epochs.

        Parameters
        ----------
        times : array_like of datetime64, shape (n,)
            GPS-time labels within the table (after its first and before its last epoch).

        Returns
        -------
        EopValues
            Values of shape (n,).

        Raises
        ------
        ValueError
            If an epoch lies outside the table.
        """
        tai_ns = _as_ns(times) + _GPST_TO_TAI_NS
        values, _ = interpolate_table(self._t_tai_s, self._columns, tai_ns * 1e-9, order=3)
        if not np.isfinite(values).all():
            raise ValueError(f"epoch outside the EOP table ({self.source}: MJD "
                             f"{self.mjd_utc[0]:.0f} to {self.mjd_utc[-1]:.0f})")
        xp, yp, ut1_tai, lod, dx, dy = values.T
        if self.subdaily:
            t_cy, gmst = self._tidal_time(tai_ns, ut1_tai)
            for dxp, dyp, dut1 in (ocean_tide_eop(t_cy, gmst), libration_eop(t_cy, gmst)):
                xp, yp, ut1_tai = xp + dxp, yp + dyp, ut1_tai + dut1
        dut1_s = ut1_tai + _tai_minus_utc_from_tai_ns(tai_ns)
        return EopValues(xp, yp, dut1_s, ut1_tai, lod, dx, dy)

    @staticmethod
    def _tidal_time(tai_ns: np.ndarray, ut1_tai: np.ndarray):
        """TT centuries and GMST (IAU 2006, from the interpolated UT1) for the tidal terms."""
        tt1, tt2 = _two_part_jd(tai_ns + _TAI_TO_TT_NS)
        ut1, ut2 = _two_part_jd(tai_ns, ut1_tai)
        return _centuries(tt1, tt2), erfa.gmst06(ut1, ut2, tt1, tt2)


@functools.lru_cache(maxsize=1)
def default_earth_orientation() -> EarthOrientation:
    """The EOP of the installed astropy-iers-data (C04 + finals2000A), loaded once."""
    return EarthOrientation.from_iers_data()
