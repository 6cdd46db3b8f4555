"""GNSS constellations and clocks of the simulated world: analytic orbits and random walks.

Orbits are circular (or, :class:`KeplerOrbit`, elliptic) with the secular J2 drift of their
angles, so the GNSS constellations need no external file. Their inertial frame is taken as the GCRF: the
closed-loop simulator (:mod:`leopod.simulate.observations`) solves the light time in it and
writes Earth-fixed products with the IERS 2010 transformation
(:func:`leopod.frames.earth_rotation.gcrf_to_itrf`), the transformation the estimator uses.
Time ``t`` is GPS seconds since the world's epoch.

:func:`earth_fixed` (a rotation about Z by ``θ0 + ω t`` with the nominal Earth rotation rate,
no precession, nutation or polar motion) is a minimal analytic Earth for tests that need an
exactly invertible world (e.g. brute-force laser ranging); simulated products do not use it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from leopod.constants import GM_EARTH_M3_S2, OMEGA_EARTH_RAD_S, R_EARTH_EQUATOR_M

__all__ = ["BDS3_MEO_ALTITUDE_M", "BDS3_MEO_INCLINATION_DEG", "BDS3_MEO_PRNS", "CircularOrbit",
           "KeplerOrbit", "RandomWalkClock", "beidou2_constellation", "beidou3_constellation",
           "earth_fixed",
           "gps_constellation", "walker_constellation"]

_J2 = 1.0826359e-3  # Earth dynamic form factor, IERS Conventions 2010 Table 1.1
_KEPLER_ITERATIONS = 6  # Newton steps of Kepler's equation (converged to rounding for e <= 0.1)

#: BDS-3 MEO nominal altitude [m] and inclination [deg]: 21 528 km, 55°, Walker 24/3/1
#: (Yang Y. et al. 2019, "Introduction to BeiDou-3 navigation satellite system", Navigation
#: 66(1):7-18, doi:10.1002/navi.291).
BDS3_MEO_ALTITUDE_M = 21_528.0e3
BDS3_MEO_INCLINATION_DEG = 55.0
#: PRNs of the 24 BDS-3 MEO satellites of the nominal constellation, C19-C30, C32-C37,
#: C41-C46 (IGS MGEX BeiDou constellation status, mgex.igs.org/IGS_MGEX_Status_BDS.php;
#: C38-C40 are the BDS-3 IGSO satellites).
BDS3_MEO_PRNS = tuple(f"C{k:02d}" for k in (*range(19, 31), *range(32, 38), *range(41, 47)))


@dataclass(frozen=True)
class CircularOrbit:
    """Circular orbit with secular J2 precession of node and argument of latitude.

    Attributes
    ----------
    a_m : float
        Semi-major axis [m].
    inc_deg : float
        Inclination [deg].
    raan_deg : float
        Right ascension of the ascending node at t = 0 [deg].
    u0_deg : float
        Argument of latitude at t = 0 [deg].
    j2 : bool
        Apply the secular J2 rates (Vallado, Fundamentals of Astrodynamics, 4th ed., eq. 9-41).
    """

    a_m: float
    inc_deg: float
    raan_deg: float
    u0_deg: float
    j2: bool = True

    def _rates(self):
        n = np.sqrt(GM_EARTH_M3_S2 / self.a_m**3)
        if not self.j2:
            return n, 0.0
        inc = np.radians(self.inc_deg)
        k = 1.5 * _J2 * (R_EARTH_EQUATOR_M / self.a_m) ** 2 * n
        raan_dot = -k * np.cos(inc)
        u_dot = n + k * (2.0 - 2.5 * np.sin(inc) ** 2) + k * (1.0 - 1.5 * np.sin(inc) ** 2)
        return u_dot, raan_dot

    def inertial(self, t_s) -> tuple[np.ndarray, np.ndarray]:
        """Inertial position [m] and velocity [m/s], shape (..., 3), at times ``t_s`` [s]."""
        t = np.asarray(t_s, dtype=float)
        u_dot, raan_dot = self._rates()
        u = np.radians(self.u0_deg) + u_dot * t
        raan = np.radians(self.raan_deg) + raan_dot * t
        inc = np.radians(self.inc_deg)
        cu, su, cO, sO, ci, si = np.cos(u), np.sin(u), np.cos(raan), np.sin(raan), np.cos(inc), np.sin(inc)
        pos = self.a_m * np.stack([cO * cu - sO * su * ci, sO * cu + cO * su * ci, su * si], axis=-1)
        # d/dt with u and raan varying
        dx_du = np.stack([-cO * su - sO * cu * ci, -sO * su + cO * cu * ci, cu * si], axis=-1)
        dx_dO = np.stack([-sO * cu - cO * su * ci, cO * cu - sO * su * ci, np.zeros_like(u)], axis=-1)
        vel = self.a_m * (dx_du * u_dot + dx_dO * raan_dot)
        return pos, vel


@dataclass(frozen=True)
class KeplerOrbit:
    """Elliptic orbit with the secular J2 drift of node, perigee and mean anomaly.

    Secular rates (Vallado, Fundamentals of Astrodynamics, 4th ed., eq. 9-41, with
    ``p = a (1 − e²)``, ``k = (3/4) n J2 (R/p)²``): ``Ω̇ = −2 k cos i``,
    ``ω̇ = k (4 − 5 sin² i)``, ``Ṁ = n + k √(1 − e²) (2 − 3 sin² i)``; for ``e = 0`` the same
    motion as :class:`CircularOrbit` with ``u0 = ω0 + M0``. Kepler's equation is solved by
    Newton's method (Montenbruck & Gill, Satellite Orbits, 2000, eq. 2.49).

    Attributes
    ----------
    a_m : float
        Semi-major axis [m].
    eccentricity : float
        Eccentricity (< 1).
    inc_deg, raan_deg, argp_deg, m0_deg : float
        Inclination, node, argument of perigee and mean anomaly at t = 0 [deg].
    j2 : bool
        Apply the secular J2 rates.
    """

    a_m: float
    eccentricity: float
    inc_deg: float
    raan_deg: float
    argp_deg: float
    m0_deg: float
    j2: bool = True

    def _rates(self):
        n = np.sqrt(GM_EARTH_M3_S2 / self.a_m**3)
        if not self.j2:
            return n, 0.0, 0.0
        e2 = self.eccentricity**2
        s2 = np.sin(np.radians(self.inc_deg)) ** 2
        k = 0.75 * n * _J2 * (R_EARTH_EQUATOR_M / (self.a_m * (1.0 - e2))) ** 2
        return (n + k * np.sqrt(1.0 - e2) * (2.0 - 3.0 * s2),
                -2.0 * k * np.cos(np.radians(self.inc_deg)), k * (4.0 - 5.0 * s2))

    def inertial(self, t_s) -> tuple[np.ndarray, np.ndarray]:
        """Inertial position [m] and velocity [m/s], shape (..., 3), at times ``t_s`` [s].

        The velocity is the exact time derivative: the Keplerian velocity plus the rotation
        of the orbit by the node and perigee rates.
        """
        t = np.asarray(t_s, dtype=float)
        m_dot, raan_dot, argp_dot = self._rates()
        e = self.eccentricity
        mean = np.radians(self.m0_deg) + m_dot * t
        ecc = mean.copy()
        for _ in range(_KEPLER_ITERATIONS):
            ecc = ecc - (ecc - e * np.sin(ecc) - mean) / (1.0 - e * np.cos(ecc))
        b = np.sqrt(1.0 - e**2)
        cos_e, sin_e = np.cos(ecc), np.sin(ecc)
        # perifocal position and its derivative (dE/dt = Ṁ / (1 − e cos E))
        xp, yp = self.a_m * (cos_e - e), self.a_m * b * sin_e
        de = m_dot / (1.0 - e * cos_e)
        vxp, vyp = -self.a_m * sin_e * de, self.a_m * b * cos_e * de
        raan = np.radians(self.raan_deg) + raan_dot * t
        argp = np.radians(self.argp_deg) + argp_dot * t
        inc = np.radians(self.inc_deg)
        p_vec, q_vec = _perifocal_axes(raan, argp, inc)
        pos = xp[..., None] * p_vec + yp[..., None] * q_vec
        vel = vxp[..., None] * p_vec + vyp[..., None] * q_vec
        z = np.array([0.0, 0.0, 1.0])
        normal = np.cross(p_vec, q_vec)
        vel = vel + raan_dot * np.cross(z, pos) + argp_dot * np.cross(normal, pos)
        return pos, vel


def _perifocal_axes(raan: np.ndarray, argp: np.ndarray, inc: float):
    """Unit vectors P (to perigee) and Q (90° ahead in the orbit), shape (..., 3)."""
    co, so, cw, sw = np.cos(raan), np.sin(raan), np.cos(argp), np.sin(argp)
    ci, si = np.cos(inc), np.sin(inc)
    p_vec = np.stack([co * cw - so * sw * ci, so * cw + co * sw * ci, sw * si], axis=-1)
    q_vec = np.stack([-co * sw - so * cw * ci, -so * sw + co * cw * ci, cw * si], axis=-1)
    return p_vec, q_vec


def gps_constellation() -> dict[str, CircularOrbit]:
    """A nominal 24-slot GPS constellation: 6 planes (55°), 4 slots each, a = 26 559.7 km.

    Slot phases follow the pattern of the baseline 24-slot constellation (SPS Performance
    Standard 2020, Table 3.1-1) only approximately: equally spaced slots with a 15° shift
    per plane. Satellites are named G01..G24.
    """
    sats = {}
    k = 1
    for plane in range(6):
        for slot in range(4):
            sats[f"G{k:02d}"] = CircularOrbit(26_559.7e3, 55.0, 60.0 * plane,
                                              90.0 * slot + 15.0 * plane, j2=True)
            k += 1
    return sats


def walker_constellation(ids, n_planes: int, phasing: int, a_m: float, inc_deg: float,
                         raan0_deg: float = 0.0, j2: bool = True) -> dict[str, CircularOrbit]:
    """Walker delta constellation T/P/F of circular orbits (Walker 1984, J. Br. Interplanet.
    Soc. 37:559-572).

    T = len(ids) satellites in P = ``n_planes`` planes (S = T/P each): plane p has the node
    ``Ω_p = Ω_0 + 360° p / P``; satellite s of plane p has the argument of latitude at t = 0
    ``u = 360° s / S + 360° F p / T`` (F = ``phasing``). ``ids`` fill plane 0 slot 0..S-1,
    then plane 1, ...

    Parameters
    ----------
    ids : sequence of str
        Satellite ids, T of them (a multiple of ``n_planes``).
    n_planes, phasing : int
        P and F (0 <= F < P).
    a_m, inc_deg, raan0_deg : float
        Semi-major axis [m], inclination [deg], node of plane 0 [deg].
    j2 : bool
        Secular J2 rates (:class:`CircularOrbit`).

    Returns
    -------
    dict of str to CircularOrbit
    """
    ids = list(ids)
    total = len(ids)
    if total == 0 or total % n_planes or not 0 <= phasing < n_planes:
        raise ValueError(f"Walker {total}/{n_planes}/{phasing} is not a valid constellation")
    per_plane = total // n_planes
    sats = {}
    for k, sat in enumerate(ids):
        plane, slot = divmod(k, per_plane)
        raan_deg = raan0_deg + 360.0 * plane / n_planes
        u0_deg = 360.0 * slot / per_plane + 360.0 * phasing * plane / total
        sats[sat] = CircularOrbit(a_m, inc_deg, raan_deg % 360.0, u0_deg % 360.0, j2=j2)
    return sats


def beidou3_constellation() -> dict[str, CircularOrbit]:
    """The nominal BDS-3 MEO constellation: Walker 24/3/1, a = R_E + 21 528 km ≈ 27 906 km,
    i = 55°, with the secular J2 drift (Yang et al. 2019; Keplerian period 12 h 53 min,
    13 revolutions in 7 sidereal days).

    Satellites are the 24 MEO PRNs of :data:`BDS3_MEO_PRNS`, assigned in PRN order to the
    slots of planes A, B, C (8 each): the PRN of each slot is nominal, not the operational
    assignment.
    """
    return walker_constellation(BDS3_MEO_PRNS, 3, 1, R_EARTH_EQUATOR_M + BDS3_MEO_ALTITUDE_M,
                                BDS3_MEO_INCLINATION_DEG)


def beidou2_constellation() -> dict[str, CircularOrbit]:
    """A nominal BDS-2 constellation: 5 GEO, 7 IGSO and 3 MEO satellites on circular orbits.

    Orbit types, altitudes and inclinations of BDS-SIS-ICD-B1I-3.0 (2019), sec. 3: GEO and
    IGSO at 35 786 km (a = 42 164 km; GEO at i = 0°, IGSO at 55°), MEO at 21 528 km and 55°.
    PRNs as in the IGS MGEX BeiDou status from 2016 on (:data:`leopod.gnss.scb.BDS2_ORBIT_TYPE`):
    GEO C01-C05; IGSO C06-C10, C13, C16 in three planes 120° apart; MEO C11, C12, C14 in the
    slots of a Walker 24/3/1 shell. Nodes and phases are illustrative (the world has no
    Earth-fixed longitude for the GEO and IGSO satellites); the simulated BDS-2 geometry
    serves tests of the satellite-induced code bias, not a realistic visibility.
    """
    a_geo = 42_164.0e3
    sats = {f"C{p:02d}": CircularOrbit(a_geo, 0.0, 0.0, 72.0 * k) for k, p in
            enumerate(range(1, 6))}
    for k, prn in enumerate((6, 7, 8, 9, 10, 13, 16)):
        sats[f"C{prn:02d}"] = CircularOrbit(a_geo, 55.0, 120.0 * (k % 3), 51.0 * k)
    meo = walker_constellation([f"M{k:02d}" for k in range(24)], 3, 1,
                               R_EARTH_EQUATOR_M + BDS3_MEO_ALTITUDE_M, BDS3_MEO_INCLINATION_DEG)
    for prn, slot in zip((11, 12, 14), ("M00", "M03", "M09"), strict=True):
        sats[f"C{prn:02d}"] = meo[slot]
    return dict(sorted(sats.items()))


def earth_fixed(t_s, pos_in: np.ndarray, vel_in: np.ndarray | None = None, theta0_rad: float = 0.0):
    """Rotate inertial vectors to Earth-fixed at times ``t_s`` (rotation about Z by θ0 + ωt).

    Parameters
    ----------
    t_s : array_like, shape (...)
    pos_in : ndarray, shape (..., 3)
    vel_in : ndarray, shape (..., 3), optional
        Inertial velocity; returned as Earth-fixed velocity ``R v − ω × r_ef``.

    Returns
    -------
    pos_ef : ndarray, shape (..., 3)
    vel_ef : ndarray, shape (..., 3) or None
    """
    theta = theta0_rad + OMEGA_EARTH_RAD_S * np.asarray(t_s, dtype=float)
    c, s = np.cos(theta)[..., None], np.sin(theta)[..., None]
    x, y, z = pos_in[..., 0:1], pos_in[..., 1:2], pos_in[..., 2:3]
    pos = np.concatenate([c * x + s * y, -s * x + c * y, z], axis=-1)
    if vel_in is None:
        return pos, None
    vx, vy, vz = vel_in[..., 0:1], vel_in[..., 1:2], vel_in[..., 2:3]
    vel = np.concatenate([c * vx + s * vy, -s * vx + c * vy, vz], axis=-1)
    omega = np.array([0.0, 0.0, OMEGA_EARTH_RAD_S])
    vel = vel - np.cross(omega, pos)
    return pos, vel


@dataclass(frozen=True)
class RandomWalkClock:
    """Clock offset = bias + drift·t + a smooth random walk + steps, reproducible from a seed.

    The random part is a random walk sampled every ``step_s`` and interpolated linearly, so
    its value at any time is deterministic and continuous across day boundaries. ``jumps``
    add steps: the millisecond clock jumps of receivers that keep their clock within 1 ms of
    GPS time by resetting it (Guo & Zhang 2014).

    Attributes
    ----------
    bias_s, drift_s_s, walk_s_sqrt_s : float
        Offset [s], drift [s/s], random-walk intensity [s/√s].
    seed : int
    step_s : float
    span_s : float
        Length of the pre-drawn walk [s] (the campaign's duration).
    jumps : tuple of (float, float)
        Steps ``(t_s, size_s)``: from time ``t_s`` on [s] the offset is larger by ``size_s``
        [s].
    """

    bias_s: float
    drift_s_s: float
    walk_s_sqrt_s: float
    seed: int
    step_s: float = 30.0
    span_s: float = 10 * 86400.0
    jumps: tuple[tuple[float, float], ...] = ()

    def __call__(self, t_s) -> np.ndarray:
        t = np.asarray(t_s, dtype=float)
        n = int(self.span_s / self.step_s) + 3
        rng = np.random.default_rng(self.seed)
        walk = np.concatenate([[0.0], np.cumsum(rng.normal(0.0, self.walk_s_sqrt_s * np.sqrt(self.step_s), n))])
        grid = (np.arange(walk.size) - 1) * self.step_s
        steps = sum((size * (t >= t_jump) for t_jump, size in self.jumps), np.zeros_like(t))
        return self.bias_s + self.drift_s_s * t + np.interp(t, grid, walk) + steps
