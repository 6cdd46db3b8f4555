"""Station displacements: solid Earth tide, pole tide, ocean loading (IERS Conventions 2010 ch. 7).

Why one module of 518 lines: the three displacements of IERS Conventions 2010 ch. 7 (solid Earth
tide, pole tide, ocean loading, 100-150 lines each) share the local axes and the Doodson
arguments, and station_displacements sums them for its callers.

All functions return Earth-fixed (ITRF) displacement vectors [m], vectorised over n epochs
(one station position per epoch, so points of several stations can be mixed). Local axes are
the geocentric (spherical) unit vectors ``r̂`` (radial), ``ê`` (east) and ``n̂`` (north) at
the station, with geocentric latitude φ and longitude λ, as in the IERS software
DEHANTTIDEINEL; geodetic axes would differ by < 0.2°, i.e. < 0.01 mm here.

Solid Earth tides (sec. 7.1.1), in the steps of the Conventions:

* step 1, frequency independent: degree-2 and -3 in-phase displacements with the nominal Love
  and Shida numbers, the latitude dependence of h2, l2 (eqs. 7.5–7.7), the out-of-phase parts
  of the diurnal and semidiurnal tides (eqs. 7.10, 7.11) and the contributions of l^(1)
  (eqs. 7.8, 7.9);
* step 2, frequency dependent: the in- and out-of-phase corrections of the diurnal band
  (eq. 7.12) and of the long-period band (eq. 7.13), with the amplitudes of Tables 7.3a, 7.3b.

Permanent tide: not removed. The ITRF is "conventional tide free" (sec. 7.1.1, last
paragraph): the displacement includes the permanent part (−12 cm radial at the poles), exactly
as DEHANTTIDEINEL returns it with its optional step 3 left out.

Pole tide (sec. 7.1.4, eq. 7.26, with the secular pole of the 2018 update,
:func:`leopod.dynamics.pole_tides.wobble_rad`)::

    S_r = −33 sin 2θ (m1 cos λ + m2 sin λ) mm,  S_θ = −9 cos 2θ (m1 cos λ + m2 sin λ) mm,
    S_λ = 9 cos θ (m1 sin λ − m2 cos λ) mm       (θ colatitude, m1, m2 in arcsec).

Ocean loading (sec. 7.1.2): ``Δc = Σ_j f_j A_cj cos(χ_j(t) + u_j − Φ_cj)`` for the eleven
constituents of a BLQ file (c = up, west, south; A [m], Φ Greenwich phase lags). χ_j is the
astronomical argument in the convention of the BLQ files and of the IERS routine ARG2
(Doodson argument, +90° for K1 and −90° for O1, P1, Q1); f_j, u_j are the nodal factors of
Pugh (1987, Table 4.3). The IERS-recommended HARDISP adds ~330 minor waves by admittance
interpolation; leaving them out costs up to ~1 mm at coastal sites.

Time arguments: TT seconds since J2000.0 and Greenwich mean sidereal time (IAU 2006,
``erfa.gmst06``); :func:`station_displacements` derives them, the Sun and Moon (JPL DE421 via
:class:`leopod.dynamics.third_body.Ephemeris`) and the EOP from GPS-time epochs.

References
----------
1. Petit, G. & Luzum, B. (eds.) (2010). IERS Conventions (2010), IERS Technical Note 36,
   ch. 7 (and the 2018 update of sec. 7.1.4); software DEHANTTIDEINEL, ARG2.
2. Mathews, P.M., Dehant, V. & Gipson, J.M. (1997). Tidal station displacements. J. Geophys.
   Res. 102(B9), 20469–20477.
3. Pugh, D.T. (1987). Tides, Surges and Mean Sea-Level. Wiley, Table 4.3 (nodal factors).
"""

from __future__ import annotations

from dataclasses import dataclass

import erfa
import numpy as np

from leopod.astro.arguments import doodson_arguments, fundamental_arguments
from leopod.astro.ephemeris import Ephemeris
from leopod.constants import GM_EARTH_M3_S2, GM_MOON_M3_S2, GM_SUN_M3_S2, R_EARTH_EQUATOR_M
from leopod.dynamics.pole_tides import wobble_rad
from leopod.frames.earth_rotation import gcrf_from_itrf_matrices
from leopod.time.calendar import J2000_TT
from leopod.time.eop import EarthOrientation, default_earth_orientation, jd_ut1
from leopod.time.scales import gps_to_tt, jd_tt

__all__ = [
    "StationDisplacements",
    "local_axes",
    "ocean_loading_arguments",
    "ocean_loading_displacement",
    "pole_tide_displacement",
    "solid_tide_displacement",
    "station_displacements",
    "tt_seconds_j2000",
]

_MM = 1e-3
_RAD_PER_ARCSEC = np.pi / (180.0 * 3600.0)

# ------------------------------------------------------------------ solid tides, step 1
#: Nominal degree-2 Love and Shida numbers and their latitude dependence,
#: h2 = 0.6078 − 0.0006 [(3 sin²φ − 1)/2], l2 = 0.0847 + 0.0002 [(3 sin²φ − 1)/2]
#: (IERS Conventions 2010, eq. 7.7 and Table 7.2).
_H2, _H2_LAT, _L2, _L2_LAT = 0.6078, -0.0006, 0.0847, 0.0002
#: Degree-3 Love and Shida numbers (IERS Conventions 2010, sec. 7.1.1, eq. 7.6).
_H3, _L3 = 0.292, 0.015
#: Imaginary parts (out of phase) of h2, l2: diurnal and semidiurnal bands (eqs. 7.10, 7.11).
_HI_DIURNAL, _LI_DIURNAL = -0.0025, -0.0007
_HI_SEMIDIURNAL, _LI_SEMIDIURNAL = -0.0022, -0.0007
#: l^(1) of the diurnal and semidiurnal bands (eqs. 7.8, 7.9).
_L1_DIURNAL, _L1_SEMIDIURNAL = 0.0012, 0.0024

# ------------------------------------------------------------------ solid tides, step 2
# IERS Conventions 2010, Table 7.3a, with the terms down to 0.01 mm as used by the IERS routine
# DEHANTTIDEINEL (subroutine STEP2DIU); the printed table lists the terms >= 0.05 mm (and
# gives K1 ΔR(op) as -0.78 mm where the routine has -0.80 mm). Columns: Doodson number,
# multipliers of the Doodson arguments (τ, s, h, p, N', p_s), ΔR(ip), ΔR(op), ΔT(ip), ΔT(op)
# [mm]. The routine's row "0 1 0 1 -1" (tide 156.564, not a tide of Table 6.5a) is read as
# 166.564, the tide between 166.556 and 167.355 of its frequency-ordered list; its amplitude
# is 0.01 mm.
_TABLE_7_3A = """
125.755  1 -3  0  2  0  0  -0.01  0.00  0.00  0.00
127.555  1 -3  2  0  0  0  -0.01  0.00  0.00  0.00
135.645  1 -2  0  1 -1  0  -0.02  0.00  0.00  0.00
135.655  1 -2  0  1  0  0  -0.08  0.00 -0.01  0.01
137.455  1 -2  2 -1  0  0  -0.02  0.00  0.00  0.00
145.545  1 -1  0  0 -1  0  -0.10  0.00  0.00  0.00
145.555  1 -1  0  0  0  0  -0.51  0.00 -0.02  0.03
147.555  1 -1  2  0  0  0   0.01  0.00  0.00  0.00
153.655  1  0 -2  1  0  0   0.01  0.00  0.00  0.00
155.455  1  0  0 -1  0  0   0.02  0.00  0.00  0.00
155.655  1  0  0  1  0  0   0.06  0.00  0.00  0.00
155.665  1  0  0  1  1  0   0.01  0.00  0.00  0.00
157.455  1  0  2 -1  0  0   0.01  0.00  0.00  0.00
162.556  1  1 -3  0  0  1  -0.06  0.00  0.00  0.00
163.545  1  1 -2  0 -1  0   0.01  0.00  0.00  0.00
163.555  1  1 -2  0  0  0  -1.23 -0.07  0.06  0.01
164.554  1  1 -1  0  0 -1   0.02  0.00  0.00  0.00
164.556  1  1 -1  0  0  1   0.04  0.00  0.00  0.00
165.545  1  1  0  0 -1  0  -0.22  0.01  0.01  0.00
165.555  1  1  0  0  0  0  12.00 -0.80 -0.67 -0.03
165.565  1  1  0  0  1  0   1.73 -0.12 -0.10  0.00
165.575  1  1  0  0  2  0  -0.04  0.00  0.00  0.00
166.554  1  1  1  0  0 -1  -0.50 -0.01  0.03  0.00
166.556  1  1  1  0  0  1   0.01  0.00  0.00  0.00
166.564  1  1  1  0  1 -1  -0.01  0.00  0.00  0.00
167.355  1  1  2 -2  0  0  -0.01  0.00  0.00  0.00
167.555  1  1  2  0  0  0  -0.11  0.01  0.01  0.00
173.655  1  2 -2  1  0  0  -0.01  0.00  0.00  0.00
175.455  1  2  0 -1  0  0  -0.02  0.00  0.00  0.00
"""

# IERS Conventions 2010, Table 7.3b (long-period band), columns as Table 7.3a.
_TABLE_7_3B = """
055.565  0  0  0  0  1  0   0.47  0.16  0.23  0.07
057.555  0  0  2  0  0  0  -0.20 -0.11 -0.12 -0.05
065.455  0  1  0 -1  0  0  -0.11 -0.09 -0.08 -0.04
075.555  0  2  0  0  0  0  -0.13 -0.15 -0.11 -0.07
075.565  0  2  0  0  1  0  -0.05 -0.06 -0.05 -0.03
"""


def _parse_step2(text: str) -> tuple[np.ndarray, np.ndarray]:
    """Doodson multipliers (k, 6) and amplitudes ΔR(ip), ΔR(op), ΔT(ip), ΔT(op) (k, 4) [m]."""
    rows = [line.split() for line in text.strip().splitlines()]
    mult = np.array([[int(v) for v in r[1:7]] for r in rows], dtype=float)
    amp = np.array([[float(v) for v in r[7:11]] for r in rows]) * _MM
    return mult, amp


_STEP2_DIURNAL = _parse_step2(_TABLE_7_3A)
_STEP2_LONG = _parse_step2(_TABLE_7_3B)

# ------------------------------------------------------------------------- ocean loading
# Doodson numbers of the eleven BLQ constituents (order of leopod.io.blq.BLQ_CONSTITUENTS) and
# the phase offset [deg] of the BLQ/ARG2 convention (IERS software ARG2: +90° for K1, −90° for
# O1, P1, Q1, because the potential of those diurnal waves is a sine in Cartwright–Tayler).
_OL_DOODSON = ("255.555", "273.555", "245.655", "275.555", "165.555", "145.555", "163.555",
               "135.655", "075.555", "065.455", "057.555")
_OL_PHASE_OFFSET_DEG = np.array([0.0, 0.0, 0.0, 0.0, 90.0, -90.0, -90.0, -90.0, 0.0, 0.0, 0.0])
#: Nodal factors of Pugh (1987), Table 4.3: f = f0 + f1 cos N, u = u1 sin N [deg], N the
#: longitude of the Moon's ascending node; S2, P1 and Ssa have f = 1, u = 0.
_OL_F0 = np.array([1.0, 1.0, 1.0, 1.024, 1.006, 1.009, 1.0, 1.009, 1.043, 1.0, 1.0])
_OL_F1 = np.array([-0.037, 0.0, -0.037, 0.286, 0.115, 0.187, 0.0, 0.187, 0.414, -0.130, 0.0])
_OL_U1_DEG = np.array([-2.1, 0.0, -2.1, -17.7, -8.9, 10.8, 0.0, 10.8, -23.7, 0.0, 0.0])


def _doodson_multipliers(number: str) -> np.ndarray:
    """Multipliers of (τ, s, h, p, N', p_s) of a Doodson number ``"ABC.DEF"``."""
    digits = [int(c) for c in number.replace(".", "")]
    return np.array([digits[0]] + [d - 5 for d in digits[1:]], dtype=float)


_OL_MULT = np.array([_doodson_multipliers(d) for d in _OL_DOODSON])


# ------------------------------------------------------------------------------ geometry
def local_axes(pos_m) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Geocentric radial, east and north unit vectors at Earth-fixed positions.

    Parameters
    ----------
    pos_m : array_like, shape (n, 3) or (3,)
        Earth-fixed positions [m].

    Returns
    -------
    r_hat, e_hat, n_hat : ndarray, shape (n, 3)
        ``r̂ = r/|r|``, ``ê = (−sin λ, cos λ, 0)``, ``n̂ = (−sin φ cos λ, −sin φ sin λ, cos φ)``
        with geocentric latitude φ and longitude λ.
    """
    pos = np.atleast_2d(np.asarray(pos_m, dtype=float))
    r_hat = pos / np.linalg.norm(pos, axis=1, keepdims=True)
    lon = np.arctan2(pos[:, 1], pos[:, 0])
    sin_lat = r_hat[:, 2]
    cos_lat = np.hypot(r_hat[:, 0], r_hat[:, 1])
    zero = np.zeros_like(lon)
    e_hat = np.stack([-np.sin(lon), np.cos(lon), zero], axis=1)
    n_hat = np.stack([-sin_lat * np.cos(lon), -sin_lat * np.sin(lon), cos_lat], axis=1)
    return r_hat, e_hat, n_hat


def _to_itrf(radial, east, north, pos_m) -> np.ndarray:
    """ITRF vectors (n, 3) from radial, east and north components (n,) at positions (n, 3)."""
    r_hat, e_hat, n_hat = local_axes(pos_m)
    return radial[:, None] * r_hat + east[:, None] * e_hat + north[:, None] * n_hat


def _broadcast_positions(pos_m, n: int) -> np.ndarray:
    pos = np.asarray(pos_m, dtype=float)
    return np.broadcast_to(pos, (n, 3)) if pos.ndim == 1 else pos


# ----------------------------------------------------------------------- solid tides
@dataclass(frozen=True)
class _Body:
    """Geometry of a tide-raising body seen from the station, arrays over n epochs."""

    fac2_m: np.ndarray      # (GM_j/GM_E) R_e^4 / R_j^3
    fac3_m: np.ndarray      # (GM_j/GM_E) R_e^5 / R_j^4
    unit: np.ndarray        # R̂_j (n, 3)
    sin_lat: np.ndarray     # sin Φ_j
    cos_lat: np.ndarray     # cos Φ_j
    lon: np.ndarray         # λ_j


def _body(pos_m: np.ndarray, gm_m3_s2: float) -> _Body:
    dist = np.linalg.norm(pos_m, axis=1)
    unit = pos_m / dist[:, None]
    ratio = R_EARTH_EQUATOR_M / dist
    fac2 = gm_m3_s2 / GM_EARTH_M3_S2 * R_EARTH_EQUATOR_M * ratio**3
    return _Body(fac2, fac2 * ratio, unit, unit[:, 2], np.hypot(unit[:, 0], unit[:, 1]),
                 np.arctan2(unit[:, 1], unit[:, 0]))


def _step1_in_phase(pos: np.ndarray, body: _Body) -> np.ndarray:
    """Degree 2 and 3 in-phase displacement, IERS 2010 eqs. (7.5)–(7.7) (vectorial form)."""
    r_hat = pos / np.linalg.norm(pos, axis=1, keepdims=True)
    lat_term = 1.5 * r_hat[:, 2] ** 2 - 0.5          # (3 sin²φ − 1)/2
    h2 = _H2 + _H2_LAT * lat_term
    l2 = _L2 + _L2_LAT * lat_term
    c = np.einsum("ni,ni->n", body.unit, r_hat)       # R̂_j · r̂
    transverse = body.unit - c[:, None] * r_hat
    deg2 = (h2 * (1.5 * c**2 - 0.5))[:, None] * r_hat + (3.0 * l2 * c)[:, None] * transverse
    deg3 = ((_H3 * (2.5 * c**3 - 1.5 * c))[:, None] * r_hat
            + (_L3 * (7.5 * c**2 - 1.5))[:, None] * transverse)
    return body.fac2_m[:, None] * deg2 + body.fac3_m[:, None] * deg3


def _step1_corrections(pos: np.ndarray, body: _Body) -> np.ndarray:
    """Out-of-phase (eqs. 7.10, 7.11) and l^(1) (eqs. 7.8, 7.9) parts of step 1."""
    r = np.linalg.norm(pos, axis=1)
    sin_phi = pos[:, 2] / r
    cos_phi = np.hypot(pos[:, 0], pos[:, 1]) / r
    dlon = np.arctan2(pos[:, 1], pos[:, 0]) - body.lon           # λ − λ_j
    sin2_body = 2.0 * body.sin_lat * body.cos_lat                # sin 2Φ_j
    cos2_body = body.cos_lat**2                                  # cos²Φ_j
    p21 = 3.0 * body.sin_lat * body.cos_lat                      # P_2^1(sin Φ_j)
    p22 = 3.0 * body.cos_lat**2                                  # P_2^2(sin Φ_j)
    sin2phi, cos2phi = 2.0 * sin_phi * cos_phi, cos_phi**2 - sin_phi**2
    # out of phase, diurnal (7.10) and semidiurnal (7.11)
    radial = (-0.75 * _HI_DIURNAL * sin2_body * sin2phi * np.sin(dlon)
              - 0.75 * _HI_SEMIDIURNAL * cos2_body * cos_phi**2 * np.sin(2.0 * dlon))
    north = (-1.5 * _LI_DIURNAL * sin2_body * cos2phi * np.sin(dlon)
             + 0.75 * _LI_SEMIDIURNAL * cos2_body * sin2phi * np.sin(2.0 * dlon))
    east = (-1.5 * _LI_DIURNAL * sin2_body * sin_phi * np.cos(dlon)
            - 1.5 * _LI_SEMIDIURNAL * cos2_body * cos_phi * np.cos(2.0 * dlon))
    # l^(1), diurnal (7.8) and semidiurnal (7.9)
    north += (-_L1_DIURNAL * sin_phi**2 * p21 * np.cos(dlon)
              - 0.5 * _L1_SEMIDIURNAL * sin_phi * cos_phi * p22 * np.cos(2.0 * dlon))
    east += (_L1_DIURNAL * sin_phi * cos2phi * p21 * np.sin(dlon)
             - 0.5 * _L1_SEMIDIURNAL * sin_phi**2 * cos_phi * p22 * np.sin(2.0 * dlon))
    f = body.fac2_m
    return _to_itrf(f * radial, f * east, f * north, pos)


def _step2(pos: np.ndarray, t_tt_s_j2000, gmst_rad) -> np.ndarray:
    """Frequency-dependent corrections, IERS 2010 eqs. (7.12), (7.13), Tables 7.3a, 7.3b."""
    beta = doodson_arguments(t_tt_s_j2000, gmst_rad)              # (n, 6)
    r = np.linalg.norm(pos, axis=1)
    sin_phi = pos[:, 2] / r
    cos_phi = np.hypot(pos[:, 0], pos[:, 1]) / r
    lon = np.arctan2(pos[:, 1], pos[:, 0])
    # diurnal band (7.12)
    mult, amp = _STEP2_DIURNAL
    arg = beta @ mult.T + lon[:, None]                            # θ_f + λ, (n, k)
    s, c = np.sin(arg), np.cos(arg)
    radial = (s @ amp[:, 0] + c @ amp[:, 1]) * 2.0 * sin_phi * cos_phi
    east = (c @ amp[:, 2] - s @ amp[:, 3]) * sin_phi
    north = (s @ amp[:, 2] + c @ amp[:, 3]) * (cos_phi**2 - sin_phi**2)
    # long-period band (7.13)
    mult, amp = _STEP2_LONG
    arg = beta @ mult.T
    s, c = np.sin(arg), np.cos(arg)
    radial = radial + (c @ amp[:, 0] + s @ amp[:, 1]) * (1.5 * sin_phi**2 - 0.5)
    north = north + (c @ amp[:, 2] + s @ amp[:, 3]) * 2.0 * sin_phi * cos_phi
    return _to_itrf(radial, east, north, pos)


def solid_tide_displacement(pos_m, sun_itrf_m, moon_itrf_m, t_tt_s_j2000,
                            gmst_rad) -> np.ndarray:
    """Solid Earth tide displacement of stations, IERS Conventions (2010) sec. 7.1.1.

    Steps 1 and 2 (module docstring); conventional tide-free (the permanent tide is kept).

    Parameters
    ----------
    pos_m : array_like, shape (n, 3) or (3,)
        ITRF station positions [m].
    sun_itrf_m, moon_itrf_m : array_like, shape (n, 3)
        Geocentric Earth-fixed positions of the Sun and the Moon [m].
    t_tt_s_j2000 : array_like, shape (n,)
        TT seconds since J2000.0.
    gmst_rad : array_like, shape (n,)
        Greenwich mean sidereal time [rad] (``erfa.gmst06``).

    Returns
    -------
    ndarray, shape (n, 3)
        ITRF displacement [m].
    """
    sun = np.atleast_2d(np.asarray(sun_itrf_m, dtype=float))
    moon = np.atleast_2d(np.asarray(moon_itrf_m, dtype=float))
    pos = _broadcast_positions(pos_m, sun.shape[0])
    out = _step2(pos, t_tt_s_j2000, gmst_rad)
    for body in (_body(sun, GM_SUN_M3_S2), _body(moon, GM_MOON_M3_S2)):
        out += _step1_in_phase(pos, body) + _step1_corrections(pos, body)
    return out


# ------------------------------------------------------------------------------ pole tide
#: Radial and horizontal pole-tide coefficients [mm/arcsec], IERS Conventions 2010, eq. 7.26.
_POLE_RADIAL_MM, _POLE_HORIZONTAL_MM = -33.0, 9.0


def pole_tide_displacement(pos_m, xp_rad, yp_rad, t_tt_s_j2000) -> np.ndarray:
    """Solid Earth pole tide displacement, IERS Conventions (2010) eq. (7.26), 2018 pole.

    ``S_r = −33 sin 2θ (m1 cos λ + m2 sin λ)``, ``S_θ = −9 cos 2θ (m1 cos λ + m2 sin λ)``,
    ``S_λ = 9 cos θ (m1 sin λ − m2 cos λ)`` [mm, m_i in arcsec], θ colatitude (S_θ positive
    to the south), with the wobble m1, m2 relative to the secular pole
    (:func:`leopod.dynamics.pole_tides.wobble_rad`).

    Parameters
    ----------
    pos_m : array_like, shape (n, 3) or (3,)
        ITRF station positions [m].
    xp_rad, yp_rad : array_like, shape (n,)
        Pole coordinates [rad].
    t_tt_s_j2000 : array_like, shape (n,)
        TT seconds since J2000.0.

    Returns
    -------
    ndarray, shape (n, 3)
        ITRF displacement [m].
    """
    m1, m2 = (np.atleast_1d(w) / _RAD_PER_ARCSEC for w in wobble_rad(xp_rad, yp_rad,
                                                                       t_tt_s_j2000))
    pos = _broadcast_positions(pos_m, m1.size)
    r = np.linalg.norm(pos, axis=1)
    cos_theta = pos[:, 2] / r                              # colatitude θ: cos θ = sin φ
    sin_theta = np.hypot(pos[:, 0], pos[:, 1]) / r
    lon = np.arctan2(pos[:, 1], pos[:, 0])
    in_phase = m1 * np.cos(lon) + m2 * np.sin(lon)
    s_r = _POLE_RADIAL_MM * 2.0 * sin_theta * cos_theta * in_phase
    s_theta = -_POLE_HORIZONTAL_MM * (cos_theta**2 - sin_theta**2) * in_phase
    s_lambda = _POLE_HORIZONTAL_MM * cos_theta * (m1 * np.sin(lon) - m2 * np.cos(lon))
    return _to_itrf(s_r * _MM, s_lambda * _MM, -s_theta * _MM, pos)


# -------------------------------------------------------------------------- ocean loading
def ocean_loading_arguments(t_tt_s_j2000, gmst_rad) -> tuple[np.ndarray, np.ndarray,
                                                            np.ndarray]:
    """Astronomical arguments and nodal factors of the eleven BLQ constituents.

    Parameters
    ----------
    t_tt_s_j2000 : array_like, shape (n,)
        TT seconds since J2000.0.
    gmst_rad : array_like, shape (n,)
        Greenwich mean sidereal time [rad].

    Returns
    -------
    chi_rad : ndarray, shape (n, 11)
        χ_j: Doodson argument plus the ARG2 phase offset, in [0, 2π) [rad], order of
        :data:`leopod.io.blq.BLQ_CONSTITUENTS`.
    f : ndarray, shape (n, 11)
        Nodal amplitude factors (Pugh 1987, Table 4.3).
    u_rad : ndarray, shape (n, 11)
        Nodal phase corrections [rad].
    """
    beta = doodson_arguments(t_tt_s_j2000, gmst_rad)
    chi = np.mod(beta @ _OL_MULT.T + np.radians(_OL_PHASE_OFFSET_DEG), 2.0 * np.pi)
    node = fundamental_arguments(t_tt_s_j2000)[:, 4:5]         # N = Ω, (n, 1)
    f = _OL_F0 + _OL_F1 * np.cos(node)
    u = np.radians(_OL_U1_DEG) * np.sin(node)
    return chi, f, u


def ocean_loading_displacement(pos_m, amplitude_m, phase_deg, t_tt_s_j2000,
                               gmst_rad) -> np.ndarray:
    """Ocean tide loading displacement from BLQ coefficients, IERS Conventions 2010 sec. 7.1.2.

    ``Δc = Σ_j f_j A_cj cos(χ_j + u_j − Φ_cj)`` for c = up, west, south (module docstring).

    Parameters
    ----------
    pos_m : array_like, shape (n, 3) or (3,)
        ITRF station positions [m] (for the local axes).
    amplitude_m : array_like, shape (n, 3, 11) or (3, 11)
        Amplitudes [m] of the components (up, west, south) per constituent
        (:data:`leopod.io.blq.BLQ_CONSTITUENTS`), e.g. from :func:`leopod.io.blq.read_blq`.
    phase_deg : array_like, shape (n, 3, 11) or (3, 11)
        Greenwich phase lags [deg].
    t_tt_s_j2000 : array_like, shape (n,)
        TT seconds since J2000.0.
    gmst_rad : array_like, shape (n,)
        Greenwich mean sidereal time [rad].

    Returns
    -------
    ndarray, shape (n, 3)
        ITRF displacement [m].
    """
    chi, f, u = ocean_loading_arguments(t_tt_s_j2000, gmst_rad)
    n = chi.shape[0]
    amp = np.broadcast_to(np.asarray(amplitude_m, dtype=float), (n, 3, 11))
    phase = np.radians(np.broadcast_to(np.asarray(phase_deg, dtype=float), (n, 3, 11)))
    comp = np.einsum("nck,nk->nc", amp * np.cos((chi + u)[:, None, :] - phase), f)
    pos = _broadcast_positions(pos_m, n)
    return _to_itrf(comp[:, 0], -comp[:, 1], -comp[:, 2], pos)


# ----------------------------------------------------------------------------- together
@dataclass(frozen=True)
class StationDisplacements:
    """ITRF displacements of station positions [m], arrays of shape (n, 3).

    Attributes
    ----------
    solid_tide_m, pole_tide_m, ocean_loading_m : ndarray, shape (n, 3)
        Solid Earth tide (conventional tide free), solid Earth pole tide and ocean loading
        (zero where not modelled).
    """

    solid_tide_m: np.ndarray
    pole_tide_m: np.ndarray
    ocean_loading_m: np.ndarray

    @property
    def total_m(self) -> np.ndarray:
        """Sum of the three displacements [m], shape (n, 3)."""
        return self.solid_tide_m + self.pole_tide_m + self.ocean_loading_m


def tt_seconds_j2000(times) -> np.ndarray:
    """TT seconds since J2000.0 of GPS-time epochs (datetime64), shape (n,)."""
    return (gps_to_tt(times) - J2000_TT).astype(np.int64) * 1e-9


def station_displacements(times, pos_m, *, eop: EarthOrientation | None = None,
                          ephemeris: Ephemeris | None = None, solid_tide: bool = True,
                          pole_tide: bool = True, blq_amplitude_m=None,
                          blq_phase_deg=None) -> StationDisplacements:
    """Solid Earth tide, pole tide and ocean loading displacements at GPS-time epochs.

    Sun and Moon from the JPL ephemeris rotated to the ITRF with the full IAU 2006/2000A
    transformation and EOP (:func:`leopod.frames.earth_rotation.gcrf_from_itrf_matrices`),
    GMST from ``erfa.gmst06`` with UT1 of the EOP, pole coordinates from the same EOP.

    Parameters
    ----------
    times : array_like of datetime64, shape (n,)
        GPS-time epochs.
    pos_m : array_like, shape (n, 3) or (3,)
        ITRF station positions [m].
    eop : EarthOrientation, optional
        EOP source (default: installed IERS data).
    ephemeris : Ephemeris, optional
        Sun and Moon ephemeris (default DE421).
    solid_tide, pole_tide : bool
        Model these displacements (else zero).
    blq_amplitude_m, blq_phase_deg : array_like, shape (n, 3, 11) or (3, 11), optional
        Ocean loading coefficients (:func:`ocean_loading_displacement`); NaN rows give no
        loading for those epochs. None: no ocean loading.

    Returns
    -------
    StationDisplacements
    """
    t = np.atleast_1d(np.asarray(times, dtype="datetime64[ns]"))
    n = t.size
    pos = _broadcast_positions(pos_m, n)
    zero = np.zeros((n, 3))
    if n == 0 or not (solid_tide or pole_tide or blq_amplitude_m is not None):
        return StationDisplacements(zero, zero.copy(), zero.copy())
    eop = default_earth_orientation() if eop is None else eop
    values = eop.at(t)
    tt_s = tt_seconds_j2000(t)
    gmst = erfa.gmst06(*jd_ut1(t, values), *jd_tt(t))
    solid = zero
    if solid_tide:
        eph = Ephemeris() if ephemeris is None else ephemeris
        rot, _ = gcrf_from_itrf_matrices(t, eop)
        sun = np.einsum("nji,nj->ni", rot, eph.sun_m(tt_s))
        moon = np.einsum("nji,nj->ni", rot, eph.moon_m(tt_s))
        solid = solid_tide_displacement(pos, sun, moon, tt_s, gmst)
    pole = pole_tide_displacement(pos, values.xp_rad, values.yp_rad, tt_s) if pole_tide \
        else zero.copy()
    ocean = zero.copy()
    if blq_amplitude_m is not None:
        ocean = np.nan_to_num(ocean_loading_displacement(pos, blq_amplitude_m, blq_phase_deg,
                                                         tt_s, gmst), nan=0.0)
    return StationDisplacements(solid, pole, ocean)
