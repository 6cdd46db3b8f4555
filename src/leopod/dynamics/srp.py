"""Solar radiation pressure (SRP): cannonball and flat-plate (box-wing) models, Earth shadow.

Radiation pressure at the satellite (Montenbruck & Gill 2000, sec. 3.4.1)::

    P = P☉ (AU / |r☉ − r|)²,   P☉ = 4.56e-6 N/m²

Cannonball (M&G sec. 3.4.1; C_R = 1 + ε for a sphere)::

    a = −ν s P C_R (A/m) e☉,   e☉ = (r☉ − r)/|r☉ − r|

Flat plates (M&G sec. 3.4.1, with diffuse reflection; Milani, Nobili & Farinella 1987,
"Non-gravitational perturbations and satellite geodesy", ch. 3): a plate of area A, outward
unit normal n, specular and diffuse reflectivities ρ_s, ρ_d (absorbed fraction 1 − ρ_s − ρ_d)
lit at cos θ = n·e☉ > 0 feels::

    F = −P A cos θ [ (1 − ρ_s) e☉ + 2 (ρ_s cos θ + ρ_d/3) n ]

and ``a = ν s Σ F / m``. Plates with cos θ ≤ 0 are not lit; self-shadowing and thermal
re-emission are not modelled. ``s`` is the estimated SRP scale factor and ``ν`` the shadow
function of the conical Earth shadow (M&G sec. 3.4.2, eqs. 3.79–3.87): apparent radii
``a = asin(R☉/|r☉ − r|)`` of the Sun and ``b = asin(R⊕/|r|)`` of the Earth, their apparent
separation ``c = acos(−r·(r☉ − r)/(|r| |r☉ − r|))``; ν = 1 if c ≥ a + b, 0 if c ≤ b − a,
otherwise 1 minus the occulted fraction of the solar disc (eq. 3.85–3.87). The Earth is a
sphere of radius R⊕ (default the equatorial radius; pass a larger radius to account for the
absorbing atmosphere, e.g. +50 km).

Partial derivatives: ``∂a/∂s = a/s`` (returned as the unscaled acceleration); ``∂a/∂r``
through the Sun direction and distance is analytic, with the attitude (plate normals) and the
shadow function held fixed (in the penumbra |∂ν/∂r| ~ 1/(60 km) gives ≲ 2e-12 s⁻², 1e-6 of
the gravity gradient); ``∂a/∂v = 0``.

The plate forces of the POD (:class:`SolarRadiation` with ``plates``) take the normals from
the satellite's attitude law tabulated along a reference orbit
(:class:`leopod.dynamics.plates.Plates`).

Box-wing solar arrays that rotate about a body axis y to face the Sun have the normal
``e_panel = y × (e☉ × y)`` (Jiang et al. 2023, eq. 4), i.e. the Sun direction projected on the plane
orthogonal to y; see :class:`MacroModel` and :func:`plate_normals`.

:class:`SolarRadiation` is the force of the orbit integrator (cannonball or plates), with scale
factor(s).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numba
import numpy as np

from leopod.constants import AU_M, R_EARTH_EQUATOR_M, R_SUN_M, SOLAR_PRESSURE_1AU_N_M2
from leopod.dynamics.forces import _Scaled

__all__ = [
    "AU_M",
    "R_SUN_M",
    "SOLAR_PRESSURE_1AU_N_M2",
    "MacroModel",
    "SolarRadiation",
    "absent_plates",
    "plate_normals",
    "shadow_function",
    "srp_cannonball",
    "srp_plates",
]



@dataclass(frozen=True)
class MacroModel:
    """Flat-plate (box-wing) macro model of a satellite.

    Parameters
    ----------
    normal_body : array_like, shape (k, 3)
        Outward unit normals of the plates in the body frame (normalised on construction);
        ignored for Sun-tracking array faces (``panel`` ≠ 0).
    area_m2 : array_like, shape (k,)
        Plate areas [m²].
    specular, diffuse : array_like, shape (k,)
        Specular and diffuse reflectivities in the visible [1]; absorption is the rest.
    drag_coefficient : array_like, shape (k,)
        Drag coefficient C_D of each plate [1].
    mass_kg : float
        Satellite mass [kg].
    panel : array_like of int, shape (k,), optional
        0 for a body-fixed plate, +1 (−1) for the front (back) face of a solar array rotating
        about ``panel_axis_body`` to face the Sun (Jiang et al. 2023, eq. 4). Default: all 0.
    panel_axis_body : array_like, shape (3,)
        Rotation axis of the solar arrays in the body frame (default +Y).
    specular_ir, diffuse_ir : array_like, shape (k,), optional
        Specular and diffuse reflectivities in the infrared [1] (Earth's emitted radiation,
        :mod:`leopod.dynamics.earth_radiation`); absorption, the emissivity, is the rest.
        Default: those of the visible (a grey surface).
    """

    normal_body: np.ndarray
    area_m2: np.ndarray
    specular: np.ndarray
    diffuse: np.ndarray
    drag_coefficient: np.ndarray
    mass_kg: float
    panel: np.ndarray | None = None
    panel_axis_body: np.ndarray = field(default_factory=lambda: np.array([0.0, 1.0, 0.0]))
    specular_ir: np.ndarray | None = None
    diffuse_ir: np.ndarray | None = None

    def __post_init__(self):
        normal = np.atleast_2d(np.asarray(self.normal_body, dtype=float))
        k = normal.shape[0]
        if normal.shape != (k, 3):
            raise ValueError("normal_body must have shape (k, 3)")
        norm = np.linalg.norm(normal, axis=1, keepdims=True)
        panel = np.zeros(k, np.int64) if self.panel is None else np.asarray(self.panel, np.int64)
        if np.any((norm[:, 0] == 0.0) & (panel == 0)):
            raise ValueError("a body-fixed plate has a zero normal")
        values = {}
        for name in ("area_m2", "specular", "diffuse", "drag_coefficient", "specular_ir",
                     "diffuse_ir"):
            value = getattr(self, name)
            if value is None:       # infrared: as the visible
                value = values[name[:-3]]
            values[name] = np.broadcast_to(np.asarray(value, dtype=float), (k,))
        if np.any(values["area_m2"] < 0.0):
            raise ValueError("plate areas must not be negative")
        for band in ("", "_ir"):
            spec, diff = values["specular" + band], values["diffuse" + band]
            if np.any((spec < 0) | (diff < 0) | (spec + diff > 1.0)):
                raise ValueError(f"reflectivities{band or ''} must be >= 0 with specular + "
                                 "diffuse <= 1")
        if not np.all(np.isin(panel, (-1, 0, 1))) or panel.shape != (k,):
            raise ValueError("panel must hold one of -1, 0, +1 per plate")
        if self.mass_kg <= 0.0:
            raise ValueError("mass_kg must be positive")
        axis = np.asarray(self.panel_axis_body, dtype=float)
        object.__setattr__(self, "normal_body", normal / np.where(norm > 0.0, norm, 1.0))
        object.__setattr__(self, "panel", panel)
        object.__setattr__(self, "panel_axis_body", axis / np.linalg.norm(axis))
        for name, value in values.items():
            object.__setattr__(self, name, np.ascontiguousarray(value))


def plate_normals(model: MacroModel, rot_gcrf_to_body: np.ndarray, pos_m: np.ndarray,
                  sun_m: np.ndarray) -> np.ndarray:
    """Outward plate normals in GCRF for an attitude and Sun position.

    Parameters
    ----------
    model : MacroModel
    rot_gcrf_to_body : ndarray, shape (3, 3)
        Attitude: ``v_body = R @ v_gcrf`` (rows = body axes in GCRF).
    pos_m, sun_m : ndarray, shape (3,)
        GCRF positions of the satellite and of the Sun [m] (for Sun-tracking arrays).

    Returns
    -------
    ndarray, shape (k, 3)
        Unit normals in GCRF. A Sun-tracking face uses ``y × (e☉ × y)`` normalised
        (Jiang et al. 2023, eq. 4), or its body-fixed normal when the Sun is along the rotation
        axis y.
    """
    return _plate_normals(np.ascontiguousarray(rot_gcrf_to_body, dtype=float),
                          model.normal_body, model.panel, model.panel_axis_body,
                          np.asarray(pos_m, dtype=float), np.asarray(sun_m, dtype=float))


@numba.njit(cache=True)
def _plate_normals(rot, normal_body, panel, axis_body, pos, sun):  # pragma: no cover - numba
    """:func:`plate_normals` for the compiled force model: rot (3, 3) GCRF → body."""
    k = normal_body.shape[0]
    normals = normal_body @ rot
    any_panel = False
    for p in range(k):
        if panel[p] != 0:
            any_panel = True
    if not any_panel:
        return normals
    axis = axis_body @ rot
    d = sun - pos
    e = d / np.sqrt(d[0] ** 2 + d[1] ** 2 + d[2] ** 2)
    along = e[0] * axis[0] + e[1] * axis[1] + e[2] * axis[2]
    tracked = e - along * axis
    size = np.sqrt(tracked[0] ** 2 + tracked[1] ** 2 + tracked[2] ** 2)
    if size > 1e-12:
        for p in range(k):
            if panel[p] != 0:
                for i in range(3):
                    normals[p, i] = panel[p] * tracked[i] / size
    return normals


def absent_plates() -> tuple:
    """Kernel data of no plates (a cannonball) with the numba types of the plate data of
    :meth:`leopod.dynamics.plates.Plates.kernel_data`."""
    one = np.zeros(1)
    return (np.zeros((1, 3)), one, one, one, one, one, np.zeros(1, np.int64),
            np.array([0.0, 1.0, 0.0]), (0.0, 1.0, 2, np.zeros((2, 9))), 1.0, one)


@numba.njit(cache=True)
def _shadow(pos, sun, r_earth):
    """Conical shadow function ν of M&G (2000) eqs. 3.79–3.87 for one position."""
    d = sun - pos
    nd = np.sqrt(d[0] ** 2 + d[1] ** 2 + d[2] ** 2)
    nr = np.sqrt(pos[0] ** 2 + pos[1] ** 2 + pos[2] ** 2)
    a = np.arcsin(min(R_SUN_M / nd, 1.0))
    b = np.arcsin(min(r_earth / nr, 1.0))
    cos_c = -(pos[0] * d[0] + pos[1] * d[1] + pos[2] * d[2]) / (nr * nd)
    c = np.arccos(max(-1.0, min(1.0, cos_c)))
    if c >= a + b:
        return 1.0
    if c <= b - a:
        return 0.0
    if c <= a - b:  # annular eclipse: the Earth disc inside the solar disc
        return 1.0 - (b * b) / (a * a)
    x = (c * c + a * a - b * b) / (2.0 * c)
    y = np.sqrt(max(a * a - x * x, 0.0))
    area = (a * a * np.arccos(max(-1.0, min(1.0, x / a)))
            + b * b * np.arccos(max(-1.0, min(1.0, (c - x) / b))) - c * y)
    return min(1.0, max(0.0, 1.0 - area / (np.pi * a * a)))


@numba.njit(cache=True)
def _shadow_many(pos, sun, r_earth):
    out = np.empty(pos.shape[0])
    for i in range(pos.shape[0]):
        out[i] = _shadow(pos[i], sun[i], r_earth)
    return out


def shadow_function(pos_m, sun_m, r_earth_m: float = R_EARTH_EQUATOR_M):
    """Fraction ν of the solar disc seen from the satellite (conical Earth shadow).

    Montenbruck & Gill (2000), sec. 3.4.2, eqs. (3.79)–(3.87); spherical Earth of radius
    ``r_earth_m``.

    Parameters
    ----------
    pos_m : array_like, shape (3,) or (n, 3)
        Geocentric GCRF satellite position(s) [m].
    sun_m : array_like, shape (3,) or (n, 3)
        Geocentric GCRF Sun position(s) [m] (broadcast against ``pos_m``).
    r_earth_m : float
        Radius of the occulting Earth [m] (enlarge it to include the atmosphere).

    Returns
    -------
    float or ndarray, shape (n,)
        ν in [0, 1]: 0 in the umbra, 1 in full sunlight.
    """
    pos = np.asarray(pos_m, dtype=float)
    sun = np.asarray(sun_m, dtype=float)
    if pos.ndim == 1 and sun.ndim == 1:
        return _shadow(pos, sun, float(r_earth_m))
    pos, sun = np.broadcast_arrays(np.atleast_2d(pos), np.atleast_2d(sun))
    return _shadow_many(np.ascontiguousarray(pos), np.ascontiguousarray(sun), float(r_earth_m))


@numba.njit(cache=True)
def _cannonball(pos, sun, coef, r_earth, use_shadow):
    """Unscaled cannonball SRP and its position gradient (shadow held fixed)."""
    d = sun - pos
    nd = np.sqrt(d[0] ** 2 + d[1] ** 2 + d[2] ** 2)
    e = d / nd
    nu = _shadow(pos, sun, r_earth) if use_shadow else 1.0
    k = nu * SOLAR_PRESSURE_1AU_N_M2 * coef * AU_M * AU_M / (nd * nd)
    acc = -k * e
    grad = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            grad[i, j] = k / nd * ((1.0 if i == j else 0.0) - 3.0 * e[i] * e[j])
    return acc, grad


@numba.njit(cache=True)
def _plates(pos, sun, normals, area, spec, diff, mass, r_earth, use_shadow):
    """Unscaled flat-plate SRP and its position gradient (normals and shadow held fixed)."""
    d = sun - pos
    nd = np.sqrt(d[0] ** 2 + d[1] ** 2 + d[2] ** 2)
    e = d / nd
    nu = _shadow(pos, sun, r_earth) if use_shadow else 1.0
    g = np.zeros(3)  # sum of -A cos θ [...] (force per unit pressure) [m²]
    dg_de = np.zeros((3, 3))
    for p in range(normals.shape[0]):
        n = normals[p]
        c = n[0] * e[0] + n[1] * e[1] + n[2] * e[2]
        if c <= 0.0:
            continue
        ca = (1.0 - spec[p]) * area[p]
        cn = 2.0 * (spec[p] * c + diff[p] / 3.0) * area[p]
        dn = (4.0 * spec[p] * c + 2.0 * diff[p] / 3.0) * area[p]
        for i in range(3):
            g[i] -= c * (ca * e[i] + cn * n[i])
            for j in range(3):
                dg_de[i, j] -= ca * (e[i] * n[j] + (c if i == j else 0.0)) + dn * n[i] * n[j]
    k = nu * SOLAR_PRESSURE_1AU_N_M2 * AU_M * AU_M / (nd * nd * mass)
    acc = k * g
    # ∂e/∂r = −(I − e eᵀ)/|d|,  ∂|d|⁻²/∂r = 2 e / |d|³
    de_dr = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            de_dr[i, j] = -((1.0 if i == j else 0.0) - e[i] * e[j]) / nd
    grad = k * (dg_de @ de_dr)
    for i in range(3):
        for j in range(3):
            grad[i, j] += 2.0 * acc[i] * e[j] / nd
    return acc, grad


def _result(acc0, grad0, scale):
    """Assemble (acc, ∂a/∂r, ∂a/∂v, ∂a/∂s) from the unscaled acceleration."""
    return scale * acc0, scale * grad0, np.zeros((3, 3)), acc0.reshape(3, 1).copy()


def srp_cannonball(pos_m, sun_m, cr_area_mass_m2_kg: float, scale: float = 1.0, *,
                   r_earth_m: float = R_EARTH_EQUATOR_M, shadow: bool = True):
    """Cannonball solar radiation pressure with the conical Earth shadow.

    ``a = −ν s P☉ (AU/|r☉ − r|)² C_R (A/m) e☉`` (M&G 2000, sec. 3.4.1).

    Parameters
    ----------
    pos_m, sun_m : ndarray, shape (3,)
        Geocentric GCRF positions of the satellite and of the Sun [m].
    cr_area_mass_m2_kg : float
        C_R A/m [m²/kg].
    scale : float
        SRP scale factor s [1].
    r_earth_m : float
        Radius of the occulting Earth [m].
    shadow : bool
        Apply the shadow function (False: always lit).

    Returns
    -------
    acc : ndarray, shape (3,)
        Acceleration [m/s²].
    da_dr : ndarray, shape (3, 3)
        ∂a/∂r [1/s²] (shadow function held fixed).
    da_dv : ndarray, shape (3, 3)
        ∂a/∂v = 0 [1/s].
    da_dscale : ndarray, shape (3, 1)
        ∂a/∂s [m/s²].
    """
    acc0, grad0 = _cannonball(np.asarray(pos_m, dtype=float), np.asarray(sun_m, dtype=float),
                              float(cr_area_mass_m2_kg), float(r_earth_m), shadow)
    return _result(acc0, grad0, scale)


def srp_plates(pos_m, sun_m, normals, model: MacroModel, scale: float = 1.0, *,
               r_earth_m: float = R_EARTH_EQUATOR_M, shadow: bool = True):
    """Flat-plate (box-wing) solar radiation pressure with the conical Earth shadow.

    Parameters
    ----------
    pos_m, sun_m : ndarray, shape (3,)
        Geocentric GCRF positions of the satellite and of the Sun [m].
    normals : ndarray, shape (k, 3)
        GCRF outward unit normals of the plates (from :func:`plate_normals`).
    model : MacroModel
        Areas, reflectivities and mass.
    scale : float
        SRP scale factor s [1].
    r_earth_m : float
        Radius of the occulting Earth [m].
    shadow : bool
        Apply the shadow function (False: always lit).

    Returns
    -------
    acc, da_dr, da_dv, da_dscale
        As :func:`srp_cannonball`; ∂a/∂r holds the normals (attitude) fixed.
    """
    acc0, grad0 = _plates(np.asarray(pos_m, dtype=float), np.asarray(sun_m, dtype=float),
                          np.ascontiguousarray(normals, dtype=float), model.area_m2,
                          model.specular, model.diffuse, float(model.mass_kg),
                          float(r_earth_m), shadow)
    return _result(acc0, grad0, scale)


class SolarRadiation(_Scaled):
    """Solar radiation pressure with the conical Earth shadow on a cannonball or on the plates
    of a macro model, scale factor(s) ``srp_scale_k`` (M&G 2000, sec. 3.4;
    :func:`srp_cannonball`, :func:`srp_plates`).

    Parameters
    ----------
    env : ArcEnvironment
    cr_area_mass_m2_kg : float
        C_R A/m [m²/kg] of the cannonball (unused with ``plates``).
    edges_s : array_like, shape (n + 1,)
        Interval boundaries [s] of the scale factors.
    shadow : bool
        Apply the conical shadow.
    r_earth_m : float
        Radius of the occulting Earth [m].
    plates : leopod.dynamics.plates.Plates, optional
        Macro model and attitude (None: cannonball).
    apriori, estimate, sigma
        As :class:`leopod.dynamics.drag.Drag` (default: not estimated).
    """

    def __init__(self, env, cr_area_mass_m2_kg: float, edges_s, *, shadow: bool = True,
                 r_earth_m: float = R_EARTH_EQUATOR_M, plates=None, **kwargs):
        kwargs.setdefault("estimate", False)
        super().__init__(env, edges_s, "srp_scale", plates=plates, **kwargs)
        self.cr_area_mass_m2_kg = float(cr_area_mass_m2_kg)
        self.shadow, self.r_earth_m = bool(shadow), float(r_earth_m)

    def kernel_data(self) -> tuple:
        """``(edges_s, C_R A/m, Earth radius, shadow, plates?, plate data)`` (compiled force
        model; :meth:`leopod.dynamics.plates.Plates.kernel_data`)."""
        plates = absent_plates() if self.plates is None else self.plates.kernel_data()
        return (self.edges_s, self.cr_area_mass_m2_kg, self.r_earth_m, self.shadow,
                self.plates is not None, plates)

    def _unscaled(self, t_s, pos, vel, scale):
        sun = self.env.body_grid(t_s)[0, 0:3]
        if self.plates is None:
            return srp_cannonball(pos, sun, self.cr_area_mass_m2_kg, scale,
                                  r_earth_m=self.r_earth_m, shadow=self.shadow)
        return srp_plates(pos, sun, self.plates.normals(t_s, pos, sun), self.plates.model,
                          scale, r_earth_m=self.r_earth_m, shadow=self.shadow)
