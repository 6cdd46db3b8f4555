"""Solid Earth and ocean pole tides in the geopotential: IERS Conventions (2010), sec. 6.4-6.5.

The centrifugal potential of polar motion deforms the Earth and the oceans. With the wobble
variables (m1, m2) of sec. 7.1.4, ``m1 = xp − xs``, ``m2 = −(yp − ys)`` [arcsec], relative to
the secular pole (xs, ys) of the same section (as updated on 1 February 2018: the linear
"secular pole" replaces the cubic-plus-linear IERS (2010) mean pole of Table 7.7)::

    xs = 55.0 + 1.677 (t − 2000) mas,   ys = 320.5 + 3.460 (t − 2000) mas   (t in years)

the corrections are

* solid Earth pole tide, eq. (6.22):
  ``ΔC̄21 = −1.333e-9 (m1 + 0.0115 m2)``,  ``ΔS̄21 = −1.333e-9 (m2 − 0.0115 m1)``;
* ocean pole tide (Desai 2002 self-consistent equilibrium model), degree-2 terms of eq. (6.24)
  (the terms of the full Desai model beyond degree 2 are not implemented; they are an order
  of magnitude smaller):
  ``ΔC̄21 = −2.1778e-10 (m1 − 0.01724 m2)``,  ``ΔS̄21 = −1.7232e-10 (m2 − 0.03365 m1)``.

The year t is counted from J2000.0 (2000-01-01 12:00 TT) in Julian years; the half-day offset
from the calendar year 2000.0 moves the secular pole by less than 0.005 mas.
"""

from __future__ import annotations

import numpy as np

__all__ = ["ocean_pole_tide", "secular_pole_rad", "solid_pole_tide", "wobble_rad"]

_RAD_PER_ARCSEC = np.pi / (180.0 * 3600.0)
_RAD_PER_MAS = _RAD_PER_ARCSEC * 1e-3
_S_PER_JULIAN_YEAR = 365.25 * 86400.0

# IERS Conventions (2010), sec. 7.1.4 as updated in 2018: secular pole at 2000 [mas] and
# rate [mas/year].
_SECULAR_POLE_2000_MAS = (55.0, 320.5)
_SECULAR_POLE_RATE_MAS_YR = (1.677, 3.460)

# IERS Conventions (2010), eq. (6.22): solid Earth pole tide, m in arcsec.
_SOLID_POLE_SCALE = -1.333e-9
_SOLID_POLE_RATIO = 0.0115

# IERS Conventions (2010), eq. (6.24), degree 2 (Desai 2002): ocean pole tide, m in arcsec.
_OCEAN_POLE_C21 = (-2.1778e-10, -0.01724)
_OCEAN_POLE_S21 = (-1.7232e-10, -0.03365)


def secular_pole_rad(t_tt_s_j2000) -> tuple[np.ndarray, np.ndarray]:
    """Secular pole (xs, ys), IERS Conventions (2010) sec. 7.1.4 (2018 update).

    Parameters
    ----------
    t_tt_s_j2000 : array_like, shape (n,)
        TT seconds since J2000.0.

    Returns
    -------
    xs, ys : numpy.ndarray, shape (n,)
        Secular pole coordinates [rad].
    """
    years = np.atleast_1d(np.asarray(t_tt_s_j2000, dtype=float)) / _S_PER_JULIAN_YEAR
    xs = (_SECULAR_POLE_2000_MAS[0] + _SECULAR_POLE_RATE_MAS_YR[0] * years) * _RAD_PER_MAS
    ys = (_SECULAR_POLE_2000_MAS[1] + _SECULAR_POLE_RATE_MAS_YR[1] * years) * _RAD_PER_MAS
    return xs, ys


def wobble_rad(xp_rad, yp_rad, t_tt_s_j2000) -> tuple[np.ndarray, np.ndarray]:
    """Wobble variables m1 = xp − xs, m2 = −(yp − ys), IERS Conventions (2010) sec. 7.1.4.

    Parameters
    ----------
    xp_rad, yp_rad : array_like, shape (n,)
        Pole coordinates (IERS EOP, e.g. C04) [rad].
    t_tt_s_j2000 : array_like, shape (n,)
        TT seconds since J2000.0.

    Returns
    -------
    m1, m2 : numpy.ndarray, shape (n,)
        Wobble variables [rad].
    """
    xs, ys = secular_pole_rad(t_tt_s_j2000)
    return np.asarray(xp_rad, dtype=float) - xs, -(np.asarray(yp_rad, dtype=float) - ys)


def solid_pole_tide(xp_rad, yp_rad, t_tt_s_j2000) -> tuple[np.ndarray, np.ndarray]:
    """Solid Earth pole tide ΔC̄21, ΔS̄21, IERS Conventions (2010) eq. (6.22).

    Parameters
    ----------
    xp_rad, yp_rad : array_like, shape (n,)
        Pole coordinates [rad].
    t_tt_s_j2000 : array_like, shape (n,)
        TT seconds since J2000.0.

    Returns
    -------
    dC21, dS21 : numpy.ndarray, shape (n,)
        Corrections to C̄21, S̄21 [1].
    """
    m1, m2 = (w / _RAD_PER_ARCSEC for w in wobble_rad(xp_rad, yp_rad, t_tt_s_j2000))
    return (_SOLID_POLE_SCALE * (m1 + _SOLID_POLE_RATIO * m2),
            _SOLID_POLE_SCALE * (m2 - _SOLID_POLE_RATIO * m1))


def ocean_pole_tide(xp_rad, yp_rad, t_tt_s_j2000) -> tuple[np.ndarray, np.ndarray]:
    """Ocean pole tide ΔC̄21, ΔS̄21, degree-2 terms of IERS Conventions (2010) eq. (6.24).

    Parameters
    ----------
    xp_rad, yp_rad : array_like, shape (n,)
        Pole coordinates [rad].
    t_tt_s_j2000 : array_like, shape (n,)
        TT seconds since J2000.0.

    Returns
    -------
    dC21, dS21 : numpy.ndarray, shape (n,)
        Corrections to C̄21, S̄21 [1].
    """
    m1, m2 = (w / _RAD_PER_ARCSEC for w in wobble_rad(xp_rad, yp_rad, t_tt_s_j2000))
    return (_OCEAN_POLE_C21[0] * (m1 + _OCEAN_POLE_C21[1] * m2),
            _OCEAN_POLE_S21[0] * (m2 + _OCEAN_POLE_S21[1] * m1))
