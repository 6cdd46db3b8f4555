"""Solid Earth tides in the geopotential: IERS Conventions (2010), sec. 6.2.

Corrections ΔC̄nm, ΔS̄nm (fully normalised, to be added to the static field) in the steps of
the Conventions:

Step 1 (frequency independent), eq. (6.6) for n = 2, 3 and eq. (6.7) for n = 4::

    ΔC̄nm − i ΔS̄nm = k_nm/(2n + 1) Σ_j (GM_j/GM_E) (R_e/r_j)^(n+1) P̄nm(sin Φ_j) e^(−i m λ_j)
    ΔC̄4m − i ΔS̄4m = k⁽⁺⁾_2m/5 Σ_j (GM_j/GM_E) (R_e/r_j)³ P̄2m(sin Φ_j) e^(−i m λ_j)

with j = Moon, Sun (Earth-fixed geocentric positions r_j, latitude Φ_j, east longitude λ_j) and
the anelastic Love numbers of Table 6.3 (complex for n = 2).

Step 2 (frequency dependence of k2m), eq. (6.8a-c) with θ_f = m(θ_g + π) − N·F (N the
Delaunay multipliers of the wave, F = (l, l', F, D, Ω) of eq. 5.43, θ_g = GMST)::

    ΔC̄20 = Σ_f(2,0) [ip cos θ_f − op sin θ_f]
    ΔC̄21 = Σ_f(2,1) [ip sin θ_f + op cos θ_f],   ΔS̄21 = Σ_f(2,1) [ip cos θ_f − op sin θ_f]
    ΔC̄22 = Σ_f(2,2) ip cos θ_f,                  ΔS̄22 = −Σ_f(2,2) ip sin θ_f

with the in-phase (ip = A_m δk_f^R H_f) and out-of-phase (op = A_m δk_f^I H_f) amplitudes of
Tables 6.5a-c.

Permanent tide (sec. 6.2.2). Step 1 contains the time average of the zonal tide, eq. (6.14)
``(ΔC̄20)_perm = A0 H0 k20`` with ``A0 = 1/(R_e √(4π)) = 4.4228e-8 m⁻¹``, ``H0 = −0.31460 m``
and k20 = 0.30190 (the value of step 1): −4.2007e-9. A field in the *zero-tide* system
already contains it (its C̄20 includes the permanent deformation), so for such a field it is
subtracted (eq. 6.13, "step 3"); a *tide-free* field takes the corrections as they are.

Time arguments are TT seconds since J2000.0 (TT used for TDB in the fundamental arguments).
"""

from __future__ import annotations

import math

import numpy as np

from leopod.astro.arguments import fundamental_arguments
from leopod.constants import (
    GM_EARTH_M3_S2,
    GM_MOON_M3_S2,
    GM_SUN_M3_S2,
    H0_PERMANENT_TIDE_M,
    R_EARTH_EQUATOR_M,
)

__all__ = [
    "H0_PERMANENT_TIDE_M",
    "SOLID_TIDE_MAX_DEGREE",
    "STEP2_TABLES",
    "TIDE_SYSTEMS",
    "permanent_tide_c20",
    "solid_earth_tides",
    "solid_tide_step1",
    "solid_tide_step2",
]

#: Highest degree of the solid-tide corrections (degree 4 from eq. 6.7).
SOLID_TIDE_MAX_DEGREE = 4
#: Tide systems of a static field that the corrections can be added to (ICGEM names).
TIDE_SYSTEMS = ("tide_free", "zero_tide")

_S_PER_CENTURY = 86400.0 * 36525.0

# IERS Conventions (2010), Table 6.3: nominal anelastic Love numbers k_nm (complex for n = 2,
# Re k − i |Im k| as tabulated) and k⁽⁺⁾_nm of eq. (6.7), indexed [n][m].
_K_NM = {2: (0.30190 - 0.0j, 0.29830 - 0.00144j, 0.30102 - 0.00130j),
         3: (0.093, 0.093, 0.093, 0.094)}
_K_PLUS_2M = (-0.00089, -0.00080, -0.00057)


# IERS Conventions (2010), Table 6.5a: corrections for the frequency dependence of k21 (diurnal
# band; nominal k21 = 0.29830 − 0.00144 i). Columns: Darwin name ("-" if none), Doodson
# number, Delaunay multipliers l l' F D Ω, amplitudes ip = A1 δkf^R Hf and op = A1 δkf^I Hf
# in units of 1e-12.
_TABLE_6_5A = """
2Q1 125,755  2  0  2  0  2   -0.1   0.0
sig1 127,555  0  0  2  2  2   -0.1   0.0
- 135,645  1  0  2  0  1   -0.1   0.0
Q1 135,655  1  0  2  0  2   -0.7   0.1
rho1 137,455 -1  0  2  2  2   -0.1   0.0
- 145,545  0  0  2  0  1   -1.3   0.1
O1 145,555  0  0  2  0  2   -6.8   0.6
tau1 147,555  0  0  0  2  0    0.1   0.0
Ntau1 153,655  1  0  2 -2  2    0.1   0.0
- 155,445 -1  0  2  0  1    0.1   0.0
Lk1 155,455 -1  0  2  0  2    0.4   0.0
No1 155,655  1  0  0  0  0    1.3  -0.1
- 155,665  1  0  0  0  1    0.3   0.0
chi1 157,455 -1  0  0  2  0    0.3   0.0
- 157,465 -1  0  0  2  1    0.1   0.0
pi1 162,556  0  1  2 -2  2   -1.9   0.1
- 163,545  0  0  2 -2  1    0.5   0.0
P1 163,555  0  0  2 -2  2  -43.4   2.9
- 164,554  0 -1  2 -2  2    0.6   0.0
S1 164,556  0  1  0  0  0    1.6  -0.1
- 165,345 -2  0  2  0  1    0.1   0.0
- 165,535  0  0  0  0 -2    0.1   0.0
- 165,545  0  0  0  0 -1   -8.8   0.5
K1 165,555  0  0  0  0  0  470.9 -30.2
- 165,565  0  0  0  0  1   68.1  -4.6
- 165,575  0  0  0  0  2   -1.6   0.1
- 166,455 -1  0  0  1  0    0.1   0.0
- 166,544  0 -1  0  0 -1   -0.1   0.0
psi1 166,554  0 -1  0  0  0  -20.6  -0.3
- 166,556  0  1 -2  2 -2    0.3   0.0
- 166,564  0 -1  0  0  1   -0.3   0.0
- 167,355 -2  0  0  2  0   -0.2   0.0
- 167,365 -2  0  0  2  1   -0.1   0.0
phi1 167,555  0  0 -2  2 -2   -5.0   0.3
- 167,565  0  0 -2  2 -1    0.2   0.0
- 168,554  0 -1 -2  2 -2   -0.2   0.0
theta1 173,655  1  0  0 -2  0   -0.5   0.0
- 173,665  1  0  0 -2  1   -0.1   0.0
- 175,445 -1  0  0  0 -1    0.1   0.0
J1 175,455 -1  0  0  0  0   -2.1   0.1
- 175,465 -1  0  0  0  1   -0.4   0.0
So1 183,555  0  0  0 -2  0   -0.2   0.0
- 185,355 -2  0  0  0  0   -0.1   0.0
Oo1 185,555  0  0 -2  0 -2   -0.6   0.0
- 185,565  0  0 -2  0 -1   -0.4   0.0
- 185,575  0  0 -2  0  0   -0.1   0.0
nu1 195,455 -1  0 -2  0 -2   -0.1   0.0
- 195,465 -1  0 -2  0 -1   -0.1   0.0
"""

# IERS Conventions (2010), Table 6.5b: corrections for the frequency dependence of k20 (zonal
# tides; nominal k20 = 0.30190). Columns as Table 6.5a, ip = A0 Hf δkf^R, op = A0 Hf δkf^I,
# units 1e-12.
_TABLE_6_5B = """
- 055,565  0  0  0  0  1   16.6  -6.7
- 055,575  0  0  0  0  2   -0.1   0.1
Sa 056,554  0 -1  0  0  0   -1.2   0.8
Ssa 057,555  0  0 -2  2 -2   -5.5   4.3
- 057,565  0  0 -2  2 -1    0.1  -0.1
- 058,554  0 -1 -2  2 -2   -0.3   0.2
Msm 063,655  1  0  0 -2  0   -0.3   0.7
- 065,445 -1  0  0  0 -1    0.1  -0.2
Mm 065,455 -1  0  0  0  0   -1.2   3.7
- 065,465 -1  0  0  0  1    0.1  -0.2
- 065,655  1  0 -2  0 -2    0.1  -0.2
Msf 073,555  0  0  0 -2  0    0.0   0.6
- 075,355 -2  0  0  0  0    0.0   0.3
Mf 075,555  0  0 -2  0 -2    0.6   6.3
- 075,565  0  0 -2  0 -1    0.2   2.6
- 075,575  0  0 -2  0  0    0.0   0.2
Mstm 083,655  1  0 -2 -2 -2    0.1   0.2
Mtm 085,455 -1  0 -2  0 -2    0.4   1.1
- 085,465 -1  0 -2  0 -1    0.2   0.5
Msqm 093,555  0  0 -2 -2 -2    0.1   0.2
Mqm 095,355 -2  0 -2  0 -2    0.1   0.1
"""

# IERS Conventions (2010), Table 6.5c: corrections for the frequency dependence of k22
# (sectorial tides; nominal k22 = 0.30102 − 0.00130 i); real part only, amplitude
# A2 δkf Hf in units of 1e-12 (op column 0).
_TABLE_6_5C = """
N2 245,655  1  0  2  0  2   -0.3   0.0
M2 255,555  0  0  2  0  2   -1.2   0.0
"""


def _parse_table(text: str) -> dict:
    """Rows of a typed step-2 table: names, Doodson numbers, Delaunay multipliers, ip, op."""
    rows = [line.split() for line in text.strip().splitlines()]
    return {"name": [r[0] for r in rows], "doodson": [r[1] for r in rows],
            "delaunay": np.array([[int(v) for v in r[2:7]] for r in rows]),
            "ip": np.array([float(r[7]) for r in rows]) * 1e-12,
            "op": np.array([float(r[8]) for r in rows]) * 1e-12}


#: Step-2 tables keyed by order m (IERS Conventions 2010, Tables 6.5b, 6.5a, 6.5c).
STEP2_TABLES = {0: _parse_table(_TABLE_6_5B), 1: _parse_table(_TABLE_6_5A),
                2: _parse_table(_TABLE_6_5C)}


def _tide_harmonics(pos_m: np.ndarray, radius_m: float) -> np.ndarray:
    """``(R/r)^(n+1) P̄nm(sin Φ) e^(−imλ)`` for n = 2, 3 of a body; shape (k, 4, 4) complex.

    Uses ``P̄nm(sin Φ) e^(−imλ) = N̄nm ((x − iy)/r)^m d^m P_n/du^m (u = z/r)`` with
    ``N̄nm = sqrt((2 − δ_m0)(2n + 1)(n − m)!/(n + m)!)`` (no Condon-Shortley phase).
    """
    pos = np.atleast_2d(np.asarray(pos_m, dtype=float))
    r = np.linalg.norm(pos, axis=1)
    u = pos[:, 2] / r
    w = (pos[:, 0] - 1j * pos[:, 1]) / r
    q = radius_m / r
    one = np.ones_like(u)
    derivs = {(2, 0): 0.5 * (3.0 * u**2 - 1.0), (2, 1): 3.0 * u, (2, 2): 3.0 * one,
              (3, 0): 0.5 * (5.0 * u**3 - 3.0 * u), (3, 1): 0.5 * (15.0 * u**2 - 3.0),
              (3, 2): 15.0 * u, (3, 3): 15.0 * one}
    out = np.zeros((len(u), 4, 4), dtype=complex)
    for (n, m), dp in derivs.items():
        norm = math.sqrt((2 - (m == 0)) * (2 * n + 1) * math.factorial(n - m)
                         / math.factorial(n + m))
        out[:, n, m] = q ** (n + 1) * norm * dp * w**m
    return out


def solid_tide_step1(sun_itrf_m, moon_itrf_m, *, gm_earth_m3_s2: float = GM_EARTH_M3_S2,
                     radius_m: float = R_EARTH_EQUATOR_M) -> tuple[np.ndarray, np.ndarray]:
    """Frequency-independent solid-tide corrections, IERS Conventions (2010) eq. (6.6), (6.7).

    Parameters
    ----------
    sun_itrf_m, moon_itrf_m : array_like, shape (n, 3)
        Earth-fixed (ITRF) geocentric positions of the Sun and the Moon [m].
    gm_earth_m3_s2 : float
        GM_E of the field the corrections are added to [m³/s²].
    radius_m : float
        Reference radius R_e of that field [m].

    Returns
    -------
    dC, dS : numpy.ndarray, shape (n, 5, 5)
        ΔC̄nm, ΔS̄nm [1], indexed [epoch, n, m]; non-zero for n = 2..4, m <= min(n, 3).
    """
    harm = (GM_MOON_M3_S2 / gm_earth_m3_s2 * _tide_harmonics(moon_itrf_m, radius_m)
            + GM_SUN_M3_S2 / gm_earth_m3_s2 * _tide_harmonics(sun_itrf_m, radius_m))
    z = np.zeros((harm.shape[0], SOLID_TIDE_MAX_DEGREE + 1, SOLID_TIDE_MAX_DEGREE + 1),
                 dtype=complex)
    for n, k_m in _K_NM.items():
        for m, k in enumerate(k_m):
            z[:, n, m] = k / (2 * n + 1) * harm[:, n, m]
    for m, k_plus in enumerate(_K_PLUS_2M):
        z[:, 4, m] = k_plus / 5.0 * harm[:, 2, m]
    return z.real.copy(), -z.imag


def solid_tide_step2(t_tt_s_j2000, gmst_rad) -> tuple[np.ndarray, np.ndarray]:
    """Frequency-dependent corrections of step 2, IERS Conventions (2010) eq. (6.8a-c).

    Parameters
    ----------
    t_tt_s_j2000 : array_like, shape (n,)
        TT seconds since J2000.0.
    gmst_rad : array_like, shape (n,)
        Greenwich mean sidereal time θ_g [rad] (e.g. ``erfa.gmst06``; not the Earth rotation
        angle, which differs by the accumulated precession in right ascension).

    Returns
    -------
    dC, dS : numpy.ndarray, shape (n, 5, 5)
        ΔC̄2m, ΔS̄2m (m = 0, 1, 2) [1]; other entries 0.
    """
    fund = fundamental_arguments(t_tt_s_j2000)
    theta_g = np.atleast_1d(np.asarray(gmst_rad, dtype=float)) + np.pi
    shape = (fund.shape[0], SOLID_TIDE_MAX_DEGREE + 1, SOLID_TIDE_MAX_DEGREE + 1)
    dc, ds = np.zeros(shape), np.zeros(shape)
    for m, table in STEP2_TABLES.items():
        theta = m * theta_g[:, None] - fund @ table["delaunay"].T  # (n, waves)
        cos, sin = np.cos(theta), np.sin(theta)
        cos_ip, sin_ip, cos_op, sin_op = (cos @ table["ip"], sin @ table["ip"],
                                          cos @ table["op"], sin @ table["op"])
        if m == 1:  # eq. (6.8b): ΔC̄21 − iΔS̄21 = −i Σ (ip + i op) e^(iθ)
            dc[:, 2, 1] = sin_ip + cos_op
            ds[:, 2, 1] = cos_ip - sin_op
        else:  # eq. (6.8a, c): ΔC̄2m − iΔS̄2m = Σ (ip + i op) e^(iθ), op = 0 for m = 2
            dc[:, 2, m] = cos_ip - sin_op
            ds[:, 2, m] = -(sin_ip + cos_op) if m else 0.0
    return dc, ds


def permanent_tide_c20(k20: float = _K_NM[2][0].real,
                       radius_m: float = R_EARTH_EQUATOR_M) -> float:
    """Permanent part of the solid-tide ΔC̄20, IERS Conventions (2010) eq. (6.14).

    ``(ΔC̄20)_perm = A0 H0 k20`` with ``A0 = 1/(R_e √(4π))`` (4.4228e-8 m⁻¹ for the IERS R_e)
    and ``H0 = −0.31460 m``.

    Parameters
    ----------
    k20 : float
        Love number (default 0.30190, Table 6.3, as used in step 1).
    radius_m : float
        R_e [m].

    Returns
    -------
    float
        (ΔC̄20)_perm [1] (−4.2007e-9 by default).
    """
    return H0_PERMANENT_TIDE_M * k20 / (radius_m * np.sqrt(4.0 * np.pi))


def solid_earth_tides(t_tt_s_j2000, gmst_rad, sun_itrf_m, moon_itrf_m, *,
                      tide_system: str, frequency_dependent: bool = True,
                      gm_earth_m3_s2: float = GM_EARTH_M3_S2,
                      radius_m: float = R_EARTH_EQUATOR_M) -> tuple[np.ndarray, np.ndarray]:
    """Solid Earth tide corrections (steps 1, 2 and the permanent tide), IERS 2010 sec. 6.2.

    Parameters
    ----------
    t_tt_s_j2000 : array_like, shape (n,)
        TT seconds since J2000.0.
    gmst_rad : array_like, shape (n,)
        Greenwich mean sidereal time [rad].
    sun_itrf_m, moon_itrf_m : array_like, shape (n, 3)
        Earth-fixed geocentric positions of the Sun and the Moon [m].
    tide_system : {"tide_free", "zero_tide"}
        Tide system of the static field the corrections are added to (the ICGEM header
        keyword). For "zero_tide" the permanent part (ΔC̄20)_perm of eq. (6.14) is removed
        (eq. 6.13).
    frequency_dependent : bool
        Add the step-2 corrections (Tables 6.5a-c).
    gm_earth_m3_s2, radius_m : float
        GM_E [m³/s²] and R_e [m] of the static field.

    Returns
    -------
    dC, dS : numpy.ndarray, shape (n, 5, 5)
        ΔC̄nm, ΔS̄nm [1] for n <= 4.

    Raises
    ------
    ValueError
        For another tide system (e.g. "mean_tide", "unknown").
    """
    if tide_system not in TIDE_SYSTEMS:
        raise ValueError(f"tide system '{tide_system}' is not supported; expected one of "
                         f"{TIDE_SYSTEMS}")
    dc, ds = solid_tide_step1(sun_itrf_m, moon_itrf_m, gm_earth_m3_s2=gm_earth_m3_s2,
                              radius_m=radius_m)
    if frequency_dependent:
        dc2, ds2 = solid_tide_step2(t_tt_s_j2000, gmst_rad)
        dc += dc2
        ds += ds2
    if tide_system == "zero_tide":
        dc[:, 2, 0] -= permanent_tide_c20(radius_m=radius_m)
    return dc, ds
