"""Earth radiation pressure (ERP): reflected sunlight (albedo) and emitted infrared.

Model of Knocke, Ries & Tapley (1988, "Earth radiation pressure effects on satellites",
AIAA 88-4292): the cap of a spherical Earth (radius R) seen from the satellite at distance r
is cut into a central element and ``rings`` rings of 6, 12, … elements (N = 1 + 3 n (n + 1);
n = 2 gives Knocke's 19) of equal *projected, attenuated* area, i.e. of equal share of the
view factor. A surface element dA at central angle ψ from the sub-satellite point, at distance
ρ (ρ² = q = r² + R² − 2 r R cos ψ), with cos α (at the element) and cos β (at the satellite,
from nadir), radiating as a Lambertian surface of exitance E (in units of the solar flux)
gives the satellite the irradiance ``E cos α dA / (π ρ²)`` from its direction; its radial part
integrates in closed form (with D = r² − R², h = r − R)::

    F(q) = ∫ cos α cos β dA / (π ρ²) = [D² (1/h² − 1/q) − (q − h²)] / (4 r²)

from F(h²) = 0 at nadir to F(D) = (R/r)² at the horizon (the view factor of a sphere; M&G
2000, sec. 3.4.3). Ring boundaries split F evenly, the elements sit at the middle of their
ring's share of F (the central one at nadir) and evenly in azimuth, and each element of
radial share F_tot/N contributes the irradiance ``E F_tot / (N cos β)`` from its direction, E
at its centre::

    E = a(φ) max(0, d·e☉)  (albedo),      E = e(φ) / 4  (infrared)

with the latitude-dependent albedo and emissivity (second-degree zonal model, Knocke et al.
1988)::

    a = 0.34 + 0.10 cos(ω (t − t₀)) P₁(sin φ) + 0.29 P₂(sin φ)
    e = 0.68 − 0.07 cos(ω (t − t₀)) P₁(sin φ) − 0.18 P₂(sin φ)

ω = 2π / 365.25 d, t₀ = 1981-12-22 (JD 2444960.5); φ the latitude of the element above the
CIP equator (its pole ``R ẑ`` from the tabulated Earth rotation). Each element exerts the
pressure ``P☉ (AU/|r☉|)² w`` from the source direction e = −s/ρ (satellite to element) and
acts as sunlight does:

* on a cannonball ``a = −s P C_R (A/m) Σ w e`` (the sphere of :mod:`leopod.dynamics.srp`);
* on flat plates the plate formula of :mod:`leopod.dynamics.srp` per element and plate, with
  the visible reflectivities for the albedo and the infrared ones for the emission.

For a uniform Earth (a, e constant, emission only) the sum is exact for any number of rings:
``a = s P C_R (A/m) (e/4) (R/r)²`` radially outward, ~5e-9 m/s² for GRACE at 480 km; the
rings resolve the terminator and the latitude terms (tests/dynamics/test_earth_radiation.py).
The ring elements are placed in the frame of the along-track direction (velocity projected
on the horizontal plane), which turns smoothly along any orbit, also over the poles.

Partial derivatives: ``∂a/∂s = a/s``; ``∂a/∂r`` and ``∂a/∂v`` are neglected: |a|/r ≈ 1e-15
s⁻², 1e-9 of the gravity gradient (a test bounds the finite difference).
"""

from __future__ import annotations

import numba
import numpy as np

from leopod.constants import AU_M, R_EARTH_EQUATOR_M, SOLAR_PRESSURE_1AU_N_M2
from leopod.dynamics.forces import _Scaled
from leopod.dynamics.plates import Plates, plate_normals_at
from leopod.dynamics.srp import absent_plates
from leopod.numerics.interpolate import lagrange_equidistant

__all__ = ["KNOCKE_1988", "EarthRadiation", "earth_radiation", "knocke_albedo_emissivity"]

#: Knocke et al. (1988) coefficients: a0, a1 (seasonal P₁ amplitude, cos), a2, e0, e1, e2.
KNOCKE_1988 = np.array([0.34, 0.10, 0.29, 0.68, -0.07, -0.18])
#: t₀ of the seasonal term (1981-12-22, JD 2444960.5) in TT seconds since J2000.0.
KNOCKE_T0_J2000_S = (2444960.5 - 2451545.0) * 86400.0
_YEAR_S = 365.25 * 86400.0


def knocke_albedo_emissivity(sin_lat, t_tt_j2000_s: float, coefficients=KNOCKE_1988):
    """Albedo and infrared emissivity of Knocke et al. (1988) at latitudes and a TT epoch.

    Parameters
    ----------
    sin_lat : array_like, shape (n,)
        Sine of the latitude [1].
    t_tt_j2000_s : float
        TT seconds since J2000.0.
    coefficients : array_like, shape (6,)
        a0, a1, a2, e0, e1, e2 (default :data:`KNOCKE_1988`).

    Returns
    -------
    albedo, emissivity : ndarray, shape (n,)
    """
    return _albedo_emissivity(np.asarray(sin_lat, dtype=float),
                              np.cos(2.0 * np.pi * (t_tt_j2000_s - KNOCKE_T0_J2000_S) / _YEAR_S),
                              np.asarray(coefficients, dtype=float))


@numba.njit(cache=True)
def _albedo_emissivity(s, season, c):  # pragma: no cover - numba
    p2 = 1.5 * s * s - 0.5
    return (c[0] + c[1] * season * s + c[2] * p2, c[3] + c[4] * season * s + c[5] * p2)


@numba.njit(cache=True)
def _plate_force(e, pressure, normals, area, spec, diff, out):  # pragma: no cover - numba
    """Add the force per unit mass·pressure of radiation from direction e on the plates,
    ``−Σ A cos θ [(1 − ρs) e + 2 (ρs cos θ + ρd/3) n]`` (M&G 2000 sec. 3.4.1), × pressure."""
    for p in range(normals.shape[0]):
        c = normals[p, 0] * e[0] + normals[p, 1] * e[1] + normals[p, 2] * e[2]
        if c <= 0.0:
            continue
        ca = (1.0 - spec[p]) * area[p]
        cn = 2.0 * (spec[p] * c + diff[p] / 3.0) * area[p]
        for i in range(3):
            out[i] -= pressure * c * (ca * e[i] + cn * normals[p, i])


@numba.njit(cache=True)
def _erp(pos, vel, sun, pole, season, coefficients, rings, r_earth, coef, normals,
         plates):  # pragma: no cover - numba
    """Unscaled ERP acceleration (3,) [m/s²] (module docstring): cannonball (``coef`` = C_R
    A/m) when ``normals`` has no rows, else the plates of the kernel data ``plates``."""
    r = np.sqrt(pos[0] ** 2 + pos[1] ** 2 + pos[2] ** 2)
    up = pos / r
    along = vel - (vel[0] * up[0] + vel[1] * up[1] + vel[2] * up[2]) * up
    along /= np.sqrt(along[0] ** 2 + along[1] ** 2 + along[2] ** 2)
    side = np.array([up[1] * along[2] - up[2] * along[1], up[2] * along[0] - up[0] * along[2],
                     up[0] * along[1] - up[1] * along[0]])
    dsun = np.sqrt(sun[0] ** 2 + sun[1] ** 2 + sun[2] ** 2)
    e_sun = sun / dsun
    pressure = SOLAR_PRESSURE_1AU_N_M2 * (AU_M / dsun) ** 2
    h2 = (r - r_earth) ** 2
    dd = r * r - r_earth * r_earth
    f_total = (r_earth / r) ** 2
    n_total = 1 + 3 * rings * (rings + 1)
    share = f_total / n_total
    acc = np.zeros(3)
    e = np.empty(3)
    d = np.empty(3)
    previous = 0
    for ring in range(rings + 1):
        count = 1 if ring == 0 else 6 * ring
        if ring == 0:
            q = h2
        else:           # F⁻¹ at the middle of the ring's share: the smaller root in q
            middle = (previous + 0.5 * count) / n_total
            b = 4.0 * r * r * f_total * middle - dd * dd / h2 - h2
            q = 0.5 * (-b - np.sqrt(max(b * b - 4.0 * dd * dd, 0.0)))
        previous += count
        rho = np.sqrt(q)
        cos_psi = (r * r + r_earth * r_earth - q) / (2.0 * r * r_earth)
        sin_psi = np.sqrt(max(0.0, 1.0 - cos_psi * cos_psi))
        cos_beta = (r - r_earth * cos_psi) / rho
        view = pressure * share / cos_beta
        for m in range(count):
            az = 2.0 * np.pi * (m + 0.5) / count
            ca, sa = np.cos(az), np.sin(az)
            for i in range(3):
                d[i] = cos_psi * up[i] + sin_psi * (ca * along[i] + sa * side[i])
                e[i] = (r_earth * d[i] - pos[i]) / rho        # towards the element
            sin_lat = d[0] * pole[0] + d[1] * pole[1] + d[2] * pole[2]
            albedo, emissivity = _albedo_emissivity(sin_lat, season, coefficients)
            cos_sun = d[0] * e_sun[0] + d[1] * e_sun[1] + d[2] * e_sun[2]
            visible = view * albedo * max(cos_sun, 0.0)
            infrared = view * emissivity / 4.0
            if normals.shape[0] == 0:
                for i in range(3):
                    acc[i] -= coef * (visible + infrared) * e[i]
            else:
                _plate_force(e, visible, normals, plates[1], plates[2], plates[3], acc)
                _plate_force(e, infrared, normals, plates[1], plates[4], plates[5], acc)
    if normals.shape[0] > 0:
        for i in range(3):
            acc[i] /= plates[9]
    return acc


def earth_radiation(pos_m, vel_m_s, sun_m, t_tt_j2000_s: float, cr_area_mass_m2_kg: float,
                    *, pole=(0.0, 0.0, 1.0), rings: int = 2,
                    r_earth_m: float = R_EARTH_EQUATOR_M, coefficients=KNOCKE_1988,
                    normals=None, model=None) -> np.ndarray:
    """Earth radiation pressure on a cannonball or on plates (module docstring).

    Parameters
    ----------
    pos_m, vel_m_s, sun_m : array_like, shape (3,)
        GCRF position [m], velocity [m/s] and geocentric Sun [m].
    t_tt_j2000_s : float
        TT seconds since J2000.0 (season of the albedo and emissivity).
    cr_area_mass_m2_kg : float
        C_R A/m of the cannonball [m²/kg] (ignored with plates).
    pole : array_like, shape (3,)
        GCRF unit vector of the pole of the latitudes (CIP).
    rings : int
        Rings around the central element (2: Knocke's 19 elements).
    r_earth_m : float
        Radius of the radiating sphere [m].
    coefficients : array_like, shape (6,)
        Albedo and emissivity model (:data:`KNOCKE_1988`; a1 = e1 = a2 = e2 = 0: uniform).
    normals : ndarray, shape (k, 3), optional
        GCRF plate normals (:func:`leopod.dynamics.srp.plate_normals`); with ``model``.
    model : MacroModel, optional
        The plates (areas, reflectivities, mass).

    Returns
    -------
    ndarray, shape (3,)
        Acceleration [m/s²] (scale 1).
    """
    if (normals is None) != (model is None):
        raise ValueError("earth_radiation: give plate normals and their model together")
    if model is None:
        normals_k, data = np.zeros((0, 3)), absent_plates()
    else:
        normals_k = np.ascontiguousarray(normals, dtype=float)
        data = (model.normal_body, model.area_m2, model.specular, model.diffuse,
                model.specular_ir, model.diffuse_ir, model.panel, model.panel_axis_body,
                absent_plates()[8], float(model.mass_kg), model.drag_coefficient)
    season = np.cos(2.0 * np.pi * (t_tt_j2000_s - KNOCKE_T0_J2000_S) / _YEAR_S)
    return _erp(*(np.asarray(x, dtype=float) for x in (pos_m, vel_m_s, sun_m, pole)), season,
                np.asarray(coefficients, dtype=float), int(rings), float(r_earth_m),
                float(cr_area_mass_m2_kg), normals_k, data)


@numba.njit(cache=True)
def erp_kernel(t, pos, vel, rotation_grid, body_grid, erp):  # pragma: no cover - numba
    """Unscaled ERP acceleration at t [s] from the :meth:`EarthRadiation.kernel_data` tuple
    ``erp`` (after its offset and edges) and the Earth-rotation and Sun/Moon grids."""
    tt_ref, coef, rings, r_earth, coefficients, use_plates, plates = erp
    rot = np.empty(9)
    lagrange_equidistant(t, rotation_grid[0], rotation_grid[1], rotation_grid[2],
                         rotation_grid[3], rot)
    pole = np.array([rot[2], rot[5], rot[8]])          # ITRF ẑ in GCRF
    bodies = np.empty(9)
    lagrange_equidistant(t, body_grid[0], body_grid[1], body_grid[2], body_grid[3], bodies)
    sun = bodies[0:3].copy()
    season = np.cos(2.0 * np.pi * (tt_ref + t - KNOCKE_T0_J2000_S) / _YEAR_S)
    if use_plates:
        normals = plate_normals_at(t, pos, sun, plates)
    else:
        normals = np.zeros((0, 3))
    return _erp(pos, vel, sun, pole, season, coefficients, rings, r_earth, coef, normals,
                plates)


class EarthRadiation(_Scaled):
    """Earth radiation pressure (albedo + infrared, Knocke et al. 1988), scale factor(s)
    ``erp_scale_k`` (module docstring).

    Parameters
    ----------
    env : ArcEnvironment
    cr_area_mass_m2_kg : float
        C_R A/m of the cannonball [m²/kg] (unused with ``plates``).
    edges_s : array_like, shape (n + 1,)
        Interval boundaries [s] of the scale factors.
    rings : int
        Rings of the visible cap (2: 19 elements).
    r_earth_m : float
        Radius of the radiating Earth [m].
    plates : Plates, optional
        Macro model and attitude (None: cannonball).
    apriori, estimate, sigma
        As :class:`leopod.dynamics.drag.Drag` (default: not estimated).
    """

    def __init__(self, env, cr_area_mass_m2_kg: float, edges_s, *, rings: int = 2,
                 r_earth_m: float = R_EARTH_EQUATOR_M, plates: Plates | None = None,
                 **kwargs):
        kwargs.setdefault("estimate", False)
        super().__init__(env, edges_s, "erp_scale", plates=plates, **kwargs)
        self.cr_area_mass_m2_kg = float(cr_area_mass_m2_kg)
        self.rings, self.r_earth_m = int(rings), float(r_earth_m)

    def kernel_data(self) -> tuple:
        """``(edges_s, (tt_ref, C_R A/m, rings, R, coefficients, plates?, plate data))``."""
        plates = absent_plates() if self.plates is None else self.plates.kernel_data()
        return self.edges_s, (self.env.tt_j2000_ref_s, self.cr_area_mass_m2_kg, self.rings,
                              self.r_earth_m, KNOCKE_1988, self.plates is not None, plates)

    def _unscaled(self, t_s, pos, vel, scale):
        acc0 = erp_kernel(t_s, pos, vel, self.env.rotation_grid.args(),
                          self.env.body_grid.args(), self.kernel_data()[1])
        zero = np.zeros((3, 3))
        return scale * acc0, zero, zero.copy(), acc0.reshape(3, 1).copy()
