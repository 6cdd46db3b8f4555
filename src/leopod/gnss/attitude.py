"""Attitude of GNSS satellites: nominal yaw steering and the published eclipse/turn laws.

Yaw-steering attitude (IGS convention, Montenbruck et al. 2015, Adv. Space Res. 56:1015):
+Z points to the geocentre, +Y = Z × e_sun (along the solar-panel axis), +X = Y × Z completes
the frame so that +X points to the Sun-lit hemisphere. The antenna phase centre is
``r_com + x e_X + y e_Y + z e_Z`` with the ANTEX offset (x, y, z).

Near the noon and midnight points at small Sun elevation β above the orbit plane the nominal
yaw ψ = atan2(−tan β, sin μ) (Kouba 2009, GPS Solut.; Bar-Sever 1996; μ the orbit angle from
midnight) would need yaw rates beyond the satellites' capability, and each family follows its
own law (:func:`model_yaw_rad`, :data:`FAMILIES`; the family from the ANTEX block type,
:func:`attitude_family`). All laws are expressed as the yaw of the IGS +X axis
(``X = cos ψ T − sin ψ N``: T along track, N the orbit normal), in which ANTEX offsets are given:

* GPS IIR (and III, whose published models follow IIR): noon and midnight turns at the maximum
  rate 0.20 °/s starting where the nominal rate reaches it (Kouba 2009, GPS Solut.);
* GPS IIF: noon turns at 0.11 °/s; a constant yaw rate through the Earth's shadow from the
  nominal yaw at entry to that at exit, the short way (Dilssner 2010; Kuang et al. 2017);
* Galileo IOV: auxiliary Sun vector for |β| < 2° within ±15°; FOC: a cosine law in time of
  period 5656 s for |β| < 4.1° within ±10° (European GNSS Service Centre 2017);
* BDS-3 CAST: constant-rate turn between the nominal yaws at ∓6° for |β| < 3° (Wang et al.
  2018); SECM: yaw steering with |β| held at 3° (Xia et al. 2019);
* BDS-2 IGSO/MEO orbit-normal (ψ = 0) for |β| < 4° (Guo et al. 2013; Dai et al. 2015), GEO
  always orbit-normal.

The laws are stateless functions of the epoch's geometry (β taken constant through a turn), so
a day of epochs and satellites is evaluated in one vectorised call. The Sun direction is taken
from the satellite (as in :func:`gnss_body_axes`; 0.01° from the geocentric one). The Sun
position comes from the low-precision series of :mod:`leopod.astro.sun`.
"""

from __future__ import annotations

import numpy as np

from leopod.constants import R_EARTH_EQUATOR_M
from leopod.frames.yaw import nominal_yaw_rad, orbit_angles, yaw_body_axes
from leopod.gnss.combinations import ionosphere_free

__all__ = ["FAMILIES", "attitude_family", "gnss_attitude_axes", "gnss_body_axes",
           "model_yaw_rad", "nominal_yaw_rad", "nominal_yaw_rate_rad_s", "orbit_angles",
           "satellite_families", "satellite_pco_if", "turn_half_width_rad", "yaw_body_axes"]


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


# ============================================================================ yaw models
# Attitude laws (families) and their parameters, each with its published source.
#: Maximum yaw rate of GPS Block IIR satellites [deg/s] (Kouba 2009, sec. "Block IIR").
YAW_RATE_GPS_IIR_DEG_S = 0.20
#: Maximum yaw rate of GPS Block IIF satellites [deg/s] (Dilssner 2010; Kouba 2017 update of the
#: eclipse model: noon turns at 0.11 deg/s).
YAW_RATE_GPS_IIF_DEG_S = 0.11
#: Galileo IOV modified-law limits: |beta| < 2 deg, |along-track Sun component| < sin 15 deg
#: (European GNSS Service Centre 2017, Galileo IOV satellite metadata, sec. 3).
GAL_IOV_BETA0_DEG, GAL_IOV_WINDOW_DEG = 2.0, 15.0
#: Galileo FOC modified law: |beta| < 4.1 deg, |orbit angle from noon/midnight| < 10 deg, yaw
#: a cosine in time of period 5656 s (European GNSS Service Centre 2017, FOC metadata, sec. 3).
GAL_FOC_BETA0_DEG, GAL_FOC_WINDOW_DEG, GAL_FOC_PERIOD_S = 4.1, 10.0, 5656.0
#: BDS-3 CAST: linear yaw between the nominal yaws at +-6 deg of orbit angle when |beta| < 3 deg;
#: BDS-3 SECM: nominal law with |beta| floored at 3 deg (Wang et al. 2018; Xia et al. 2019).
BDS3_BETA0_DEG, BDS3_CAST_WINDOW_DEG = 3.0, 6.0
#: BDS-2 IGSO/MEO switch to orbit-normal attitude below |beta| = 4 deg (Guo et al. 2013;
#: Dai et al. 2015); GEO satellites stay orbit-normal.
BDS2_ON_BETA_DEG = 4.0

#: ANTEX ``antenna_type`` prefix -> attitude family (longest prefix wins).
ANTEX_FAMILY = {
    "BLOCK IIR": "gps_iir", "BLOCK IIF": "gps_iif", "BLOCK III": "gps_iii",
    "GALILEO-1": "galileo_iov", "GALILEO-2": "galileo_foc",
    "BEIDOU-2G": "orbit_normal", "BEIDOU-2I": "bds2", "BEIDOU-2M": "bds2",
    "BEIDOU-3G": "orbit_normal", "BEIDOU-3M-CAST": "bds3_cast", "BEIDOU-3SM-CAST": "bds3_cast",
    "BEIDOU-3SI-CAST": "bds3_cast", "BEIDOU-3I": "bds3_cast",
    "BEIDOU-3M-SECM": "bds3_secm", "BEIDOU-3SM-SECM": "bds3_secm",
    "BEIDOU-3SI-SECM": "bds3_secm",
}
FAMILIES = ("nominal", "gps_iir", "gps_iif", "gps_iii", "galileo_iov", "galileo_foc",
            "bds3_cast", "bds3_secm", "bds2", "orbit_normal")


def attitude_family(antenna_type: str | None) -> str:
    """Attitude family of a satellite from its ANTEX ``antenna_type`` (``"BLOCK IIF"``).

    Unknown types (GPS IIA, GLONASS, QZSS, ...) get ``"nominal"`` yaw steering.
    """
    name = (antenna_type or "").strip().upper()
    best = max((p for p in ANTEX_FAMILY if name.startswith(p)), key=len, default=None)
    return ANTEX_FAMILY[best] if best else "nominal"


def satellite_families(antex, svs, epoch) -> np.ndarray:
    """Attitude family per satellite id from an ANTEX file (``"nominal"`` if absent).

    Parameters
    ----------
    antex : leopod.io.antex.AntexFile or None
    svs : sequence of str, shape (s,)
    epoch : datetime64

    Returns
    -------
    ndarray of str, shape (s,)
    """
    out = np.full(len(svs), "nominal", dtype=object)
    if antex is None:
        return out
    for j, sv in enumerate(svs):
        try:
            out[j] = attitude_family(antex.satellite(str(sv), epoch).antenna_type)
        except KeyError:
            continue
    return out


def nominal_yaw_rate_rad_s(beta_rad, mu_rad, mu_dot_rad_s):
    """dψ/dt = μ̇ tan β cos μ / (sin² μ + tan² β) [rad/s] (Kouba 2009, eq. 2)."""
    t = np.tan(beta_rad)
    return mu_dot_rad_s * t * np.cos(mu_rad) / (np.sin(mu_rad) ** 2 + t * t)


def _wrap(a):
    return (np.asarray(a) + np.pi) % (2.0 * np.pi) - np.pi


def turn_half_width_rad(beta_rad, mu_dot_rad_s, max_rate_rad_s):
    """Orbit angle before noon/midnight at which the nominal yaw rate reaches the maximum.

    Solves ``|ψ̇_n| = R`` of :func:`nominal_yaw_rate_rad_s` for ``c = |cos μ'|`` (μ' from the
    noon or midnight point): ``R c² + μ̇ |tan β| c − R (1 + tan² β) = 0``. For small angles this
    is Kouba's (2009) ``sqrt(β β₀ − β²)`` with ``β₀ = atan(μ̇/R)``. NaN where no turn is needed
    (``μ̇/|tan β| ≤ R``).
    """
    t = np.abs(np.tan(beta_rad))
    r = max_rate_rad_s
    c = (-mu_dot_rad_s * t + np.sqrt((mu_dot_rad_s * t) ** 2 + 4 * r * r * (1 + t * t))) / (2 * r)
    return np.where(c < 1.0, np.arccos(np.minimum(c, 1.0)), np.nan)


def _rate_limited_turn(yaw, beta, mu_p, mu_ref, mu_dot, rate):
    """Kouba (2009) turn at constant maximum rate ``rate`` around the point ``mu_ref``.

    ``mu_p`` is the orbit angle from that point, wrapped. The turn starts where the nominal
    rate reaches ``rate`` and ends where the turning yaw meets the nominal yaw again.
    """
    d = turn_half_width_rad(beta, mu_dot, rate)
    active = np.isfinite(d) & (mu_p >= -np.nan_to_num(d)) & (mu_p < np.pi / 2)
    if not active.any():
        return yaw
    d, b, mp, md, y = d[active], beta[active], mu_p[active], mu_dot[active], yaw[active]
    mu_s = mu_ref - d
    psi_s = nominal_yaw_rad(b, mu_s)
    sgn = np.where(np.tan(b) * np.cos(mu_s) >= 0, 1.0, -1.0)         # direction of the turn
    lin = rate * (mp + d) / md
    nom = np.mod(sgn * (y - psi_s), 2 * np.pi)
    out = yaw.copy()
    out[active] = _wrap(psi_s + sgn * np.minimum(lin, nom))
    return out


def _shadow_half_width_rad(beta, r_m):
    """Half-width in orbit angle of the cylindrical Earth shadow at midnight (NaN: no shadow)."""
    c = np.sqrt(1.0 - (R_EARTH_EQUATOR_M / r_m) ** 2) / np.cos(beta)
    return np.where(c < 1.0, np.arccos(np.minimum(c, 1.0)), np.nan)


def _linear_window(yaw, beta, mu_p, mu_ref, d):
    """Yaw linear in orbit angle (constant rate) between the nominal yaws at ∓d (short way)."""
    active = np.isfinite(d) & (np.abs(mu_p) <= np.nan_to_num(d))
    if not active.any():
        return yaw
    b, dd, mp = beta[active], d[active], mu_p[active]
    psi_in = nominal_yaw_rad(b, mu_ref - dd)
    psi_out = nominal_yaw_rad(b, mu_ref + dd)
    out = yaw.copy()
    out[active] = _wrap(psi_in + _wrap(psi_out - psi_in) * (mp + dd) / (2 * dd))
    return out


def model_yaw_rad(family, beta_rad, mu_rad, mu_dot_rad_s, r_m=None):
    """Yaw angle of the published attitude law of ``family`` [rad] (module docstring).

    Parameters
    ----------
    family : str or ndarray of str, shape (...)
        One of :data:`FAMILIES` (:func:`attitude_family`).
    beta_rad, mu_rad, mu_dot_rad_s : ndarray, shape (...)
        :func:`orbit_angles`.
    r_m : ndarray, shape (...), optional
        Geocentric radius [m] (shadow width of GPS IIF; default 26 560 km).

    Returns
    -------
    ndarray, shape (...)
        Yaw in (−π, π] [rad]; 0 is orbit-normal attitude (+X along track).

    Notes
    -----
    The laws are evaluated from the geometry of the epoch (β taken constant through a turn,
    as Kouba 2009 does): no state is carried between epochs, so every epoch and satellite is
    computed at once.
    """
    beta, mu, mu_dot = np.broadcast_arrays(*(np.asarray(a, float) for a in
                                             (beta_rad, mu_rad, mu_dot_rad_s)))
    shape = beta.shape
    beta, mu, mu_dot = beta.ravel(), mu.ravel(), mu_dot.ravel()
    fam = np.broadcast_to(np.asarray(family, dtype=object), shape).ravel()
    r = np.broadcast_to(np.asarray(26_560e3 if r_m is None else r_m, float), shape).ravel()
    yaw = nominal_yaw_rad(beta, mu)
    mu_noon = _wrap(mu - np.pi)
    out = yaw.copy()
    for name in set(fam):
        sel = fam == name
        b, m, md, y = beta[sel], mu[sel], mu_dot[sel], yaw[sel]
        mn = mu_noon[sel]
        if name in ("gps_iir", "gps_iii"):
            rate = np.radians(YAW_RATE_GPS_IIR_DEG_S)
            y = _rate_limited_turn(y, b, mn, np.pi, md, rate)
            y = _rate_limited_turn(y, b, m, 0.0, md, rate)
        elif name == "gps_iif":
            y = _rate_limited_turn(y, b, mn, np.pi, md, np.radians(YAW_RATE_GPS_IIF_DEG_S))
            y = _linear_window(y, b, m, 0.0, _shadow_half_width_rad(b, r[sel]))
        elif name == "galileo_iov":
            b0 = np.radians(GAL_IOV_BETA0_DEG)
            s_t = np.cos(b) * np.sin(m)                 # along-track Sun component
            win = (np.abs(b) < b0) & (np.abs(s_t) < np.sin(np.radians(GAL_IOV_WINDOW_DEG)))
            sgn = np.where(b >= 0, 1.0, -1.0)
            s_n = (0.5 * (np.sin(b0) * sgn + np.sin(b))
                   + 0.5 * (np.sin(b0) * sgn - np.sin(b))
                   * np.cos(np.pi * np.abs(s_t) / np.sin(np.radians(GAL_IOV_WINDOW_DEG))))
            y = np.where(win, np.arctan2(-s_n, s_t), y)
        elif name == "galileo_foc":
            y = _galileo_foc(y, b, m, mn, md)
        elif name == "bds3_cast":
            b0, w = np.radians(BDS3_BETA0_DEG), np.radians(BDS3_CAST_WINDOW_DEG)
            d = np.where(np.abs(b) < b0, w, np.nan)
            y = _linear_window(y, b, mn, np.pi, d)
            y = _linear_window(y, b, m, 0.0, d)
        elif name == "bds3_secm":
            b0 = np.radians(BDS3_BETA0_DEG)
            bf = np.where(np.abs(b) < b0, np.where(b >= 0, b0, -b0), b)
            y = nominal_yaw_rad(bf, m)
        elif name == "bds2":
            y = np.where(np.abs(b) < np.radians(BDS2_ON_BETA_DEG), 0.0, y)
        elif name == "orbit_normal":
            y = np.zeros_like(y)
        elif name != "nominal":
            raise ValueError(f"unknown GNSS attitude family {name!r} (one of {FAMILIES})")
        out[sel] = y
    return out.reshape(shape)


def _galileo_foc(y, b, m, mn, md):
    """Galileo FOC: ψ = 90° sgn ψ₀ + (ψ₀ − 90° sgn ψ₀) cos(2π t / 5656 s), t from entry."""
    b0, w = np.radians(GAL_FOC_BETA0_DEG), np.radians(GAL_FOC_WINDOW_DEG)
    out = y.copy()
    for mp, ref in ((mn, np.pi), (m, 0.0)):
        t = (mp + w) / md
        win = (np.abs(b) < b0) & (t >= 0) & (t <= GAL_FOC_PERIOD_S / 2)
        if not win.any():
            continue
        psi0 = nominal_yaw_rad(b[win], ref - w)
        half = np.where(psi0 >= 0, 1.0, -1.0) * np.pi / 2
        out[win] = _wrap(half + (psi0 - half) * np.cos(2 * np.pi * t[win] / GAL_FOC_PERIOD_S))
    return out


def gnss_attitude_axes(pos_m: np.ndarray, vel_m_s: np.ndarray, sun_m: np.ndarray,
                       family=None) -> np.ndarray:
    """Body axes of GNSS satellites under their attitude laws, shape (..., 3, 3).

    Parameters
    ----------
    pos_m, vel_m_s : ndarray, shape (..., 3)
        Positions [m] and inertial velocities [m/s] (Earth-fixed frame: add ω × r).
    sun_m : ndarray, shape (..., 3)
        Sun positions in the same frame [m] (broadcast).
    family : str or ndarray of str, shape (...), optional
        Attitude family per satellite (:func:`satellite_families`); None: nominal yaw
        steering of :func:`gnss_body_axes` (the ``gnss_attitude: nominal`` setting).
        Where the velocity gives no orbit normal the axes are those of nominal yaw steering.
    """
    if family is None:
        return gnss_body_axes(pos_m, sun_m)
    sun_m = np.broadcast_to(sun_m, np.broadcast_shapes(np.shape(sun_m), np.shape(pos_m)))
    beta, mu, mu_dot = orbit_angles(pos_m, vel_m_s, sun_m)
    with np.errstate(invalid="ignore", divide="ignore"):
        yaw = model_yaw_rad(family, beta, mu, mu_dot, np.linalg.norm(pos_m, axis=-1))
        axes = yaw_body_axes(pos_m, vel_m_s, yaw)
    bad = ~np.isfinite(axes).all(axis=(-2, -1))
    if bad.any():                       # no orbit normal (zero velocity): nominal yaw steering
        axes[bad] = gnss_body_axes(pos_m[bad], sun_m[bad])
    return axes
