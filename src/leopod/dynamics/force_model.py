"""Configurable force model in the GCRF for one orbit arc, built from a plain dict.

Forces (each a :class:`leopod.dynamics.forces.Force`; time ``t_s`` = TT seconds since the
reference epoch ``t_ref`` of the arc, a GPS-time datetime64 label; since TT − GPST is constant,
``t_s`` is also GPS seconds since ``t_ref``):

* :class:`EarthGravity` — static spherical-harmonic field (:class:`GravityField`) plus the tidal
  ΔC̄nm, ΔS̄nm of :class:`leopod.dynamics.tides.TideModel` (solid Earth steps 1-2, ocean
  FES2004, solid and ocean pole tides; IERS Conventions 2010 ch. 6), evaluated in the ITRF and
  rotated: ``a = R ∇U(Rᵀ r)``, ``∂a/∂r = R G Rᵀ`` (G = ∇∇U; the tidal part of G, < 1e-7 of it,
  is neglected);
* :class:`ThirdBodies` — Sun and Moon point masses with the indirect term (Montenbruck & Gill
  2000, eq. 3.37), DE421;
* :class:`Relativity` — IERS Conventions 2010 eq. (10.12) (partials neglected, ~1e-9 relative);
* :class:`Drag` — cannonball, Harris–Priester or NRLMSISE-00 density, a scale factor per
  interval (M&G 2000, sec. 3.5);
* :class:`SolarRadiation` — cannonball with the conical Earth shadow, scale factor(s)
  (M&G 2000, sec. 3.4);
* :class:`Empirical` — constant + once-per-revolution accelerations per interval
  (:mod:`leopod.dynamics.empirical`).

Slowly varying inputs are precomputed on time grids by :class:`ArcEnvironment` and interpolated
with Lagrange polynomials on equidistant nodes (numba): the ITRF → GCRF matrix (IAU 2006/2000A
with EOP, :func:`leopod.frames.earth_rotation.gcrf_from_itrf_matrices`; 60-s nodes, 8 points:
matrix elements agree with direct evaluation to 1e-13, the resolution of the direct
computation itself, i.e. 1-ns epochs and ``erfa.era00``), the geocentric Sun and Moon (600-s
nodes, 8 points: < 2 mm and < 0.1 mm) and, in :class:`EarthGravity`, the tidal corrections
(300-s nodes, 6 points: 2e-11 relative): being linear in ΔC̄, ΔS̄, the coefficient tables of the
acceleration sums are interpolated directly. Per call (Swarm-A, degree 120 with its gradient):
gravity ~40 µs, MSIS drag ~50 µs (Harris–Priester ~30 µs), the others ~2-7 µs each
(benchmarks/dynamics_full.py).

Configuration (:func:`build_force_model`): a dict with one section per force; a force is off
when its section is absent, ``None``, ``False`` or has ``enabled: False``. Keys (defaults)::

    environment: rotation_step_s (60), ephemeris_step_s (600), ephemeris (None: DE421 of
                skyfield-data) -- grids shared by the forces (not a force)
    gravity:    field (ICGEM path or xarray Dataset from read_icgem), max_degree (120 or the
                field's degree if lower), gradient_degree (None: full degree; lower is
                faster, partials approximate)         -- off: point mass GM_E (IERS 2010)
    tides:      solid (True), ocean (FES2004 path or None), ocean_max_degree (30),
                solid_pole (True), ocean_pole (True), step_s (300)  -- applied to gravity
    third_body: sun (True), moon (True)
    relativity: lense_thirring (True), de_sitter (True)
    drag:       cd_area_mass_m2_kg, or drag_coefficient (2.3) with area_m2 and mass_kg;
                density ("msis" if space_weather is given, else "harris_priester"),
                space_weather (CelesTrak CSV),
                msis_version (0), hp_exponent (6), interval_s (None: one scale for the arc)
    srp:        cr_area_mass_m2_kg, or reflectivity_coefficient (1.3) with area_m2, mass_kg;
                shadow (True), r_earth_m (R_E), interval_s (None)
    empirical:  interval_s (10800), directions (["T", "N"]), terms (["const", "cos", "sin"])

and, in the drag, srp and empirical sections, ``apriori`` (scale 1, empirical 0), ``estimate``
(drag and empirical True, srp False) and ``sigma`` (a priori constraint, None = free), read by
:func:`apriori_parameters`, :func:`estimated_parameters` and :func:`constraint_sigmas`.
"""

from __future__ import annotations

import functools
import logging
from abc import abstractmethod
from collections.abc import Mapping
from pathlib import Path

import erfa
import numba
import numpy as np
import xarray as xr

from leopod.astro.ephemeris import Ephemeris
from leopod.constants import (
    C_LIGHT_M_S,
    EARTH_ANGULAR_MOMENTUM_M2_S,
    GM_EARTH_M3_S2,
    GM_MOON_M3_S2,
    GM_SUN_M3_S2,
    GPST_MINUS_TAI_S,
    OMEGA_EARTH_RAD_S,
    R_EARTH_EQUATOR_M,
    TT_MINUS_TAI_S,
)
from leopod.dynamics.drag import HarrisPriesterDensity, MsisDensity, drag_cannonball
from leopod.dynamics.empirical import EmpiricalModel, empirical_acceleration
from leopod.dynamics.forces import Force, ForceModel, PointMassGravity
from leopod.dynamics.gravity_field import (
    GravityField,
    acceleration_sums,
    acceleration_table,
    decimal_year,
    field_sums,
    recursion_tables,
)
from leopod.dynamics.ocean_tides import OceanTides
from leopod.dynamics.srp import srp_cannonball
from leopod.dynamics.tides import TideModel
from leopod.frames.earth_rotation import gcrf_from_itrf_matrices
from leopod.io.icgem import read_icgem
from leopod.io.space_weather import read_space_weather
from leopod.numerics.interpolate import lagrange_equidistant, lagrange_equidistant_many
from leopod.time.calendar import J2000_TT
from leopod.time.eop import EarthOrientation, default_earth_orientation, jd_ut1
from leopod.time.scales import jd_tt

__all__ = ["ArcEnvironment", "Drag", "EarthGravity", "Empirical", "Relativity",
           "SolarRadiation", "ThirdBodies", "apriori_parameters", "build_force_model",
           "constraint_sigmas", "estimated_parameters", "interval_edges"]

logger = logging.getLogger(__name__)

_TT_MINUS_GPST_NS = round((TT_MINUS_TAI_S - GPST_MINUS_TAI_S) * 1e9)
_ROTATION_POINTS = 8          # Lagrange points of the ITRF->GCRF matrix (degree 7)
_EPHEMERIS_POINTS = 8         # ... of the Sun and Moon positions
_TIDE_POINTS = 6              # ... of the tidal coefficient tables
_SUN_VELOCITY_STEP_S = 60.0   # half step of the central difference giving the Sun's velocity
#: Default drag coefficient C_D of a compact LEO (M&G 2000, sec. 3.5.1: 2.0-2.3 typical) [1].
DEFAULT_DRAG_COEFFICIENT = 2.3
#: Default radiation pressure coefficient C_R = 1 + ε of a cannonball (M&G 2000, sec. 3.4.1) [1].
DEFAULT_REFLECTIVITY_COEFFICIENT = 1.3


# ------------------------------------------------------------------------- interpolation


class _Grid:
    """Values tabulated on equidistant epochs covering [t_start, t_end] with margins."""

    def __init__(self, t_start_s: float, t_end_s: float, step_s: float, n_points: int, fn):
        margin = (n_points // 2 + 1) * step_s
        n = int(np.ceil((t_end_s - t_start_s + 2 * margin) / step_s)) + 1
        self.t_first = t_start_s - margin
        self.step = float(step_s)
        self.n_points = n_points
        self.t_nodes = self.t_first + step_s * np.arange(n)
        self.values = np.ascontiguousarray(fn(self.t_nodes).reshape(n, -1), dtype=float)
        self.span = (t_start_s - step_s, t_end_s + step_s)

    def args(self) -> tuple:
        return self.t_first, self.step, self.n_points, self.values

    def __call__(self, t_s) -> np.ndarray:
        """Interpolated rows at the epochs ``t_s`` (n,) -> (n, k)."""
        t = np.atleast_1d(np.asarray(t_s, dtype=float))
        return lagrange_equidistant_many(t, *self.args())


# ------------------------------------------------------------------------- environment


class ArcEnvironment:
    """Earth rotation, Sun and Moon on time grids over one arc, for the forces to share.

    Parameters
    ----------
    t_ref : datetime64
        Reference epoch of the arc (GPS-time label); force times are TT s since it.
    t_start_s, t_end_s : float
        Arc [TT s since ``t_ref``]; grids extend a few nodes beyond.
    eop : EarthOrientation, optional
        EOP source (default: installed IERS data).
    ephemeris : Ephemeris, optional
        Sun and Moon ephemeris (default DE421).
    rotation_step_s, ephemeris_step_s : float
        Node spacing of the ITRF->GCRF matrix (60 s) and of the Sun and Moon (600 s).
    """

    def __init__(self, t_ref, t_start_s: float, t_end_s: float, *,
                 eop: EarthOrientation | None = None, ephemeris: Ephemeris | None = None,
                 rotation_step_s: float = 60.0, ephemeris_step_s: float = 600.0):
        if not t_end_s > t_start_s:
            raise ValueError(f"empty arc: t_end_s {t_end_s} <= t_start_s {t_start_s}")
        self.t_ref = np.datetime64(t_ref, "ns")
        tt_ref = self.t_ref + np.timedelta64(_TT_MINUS_GPST_NS, "ns")
        #: TT seconds since J2000.0 of ``t_ref`` [s].
        self.tt_j2000_ref_s = float((tt_ref - J2000_TT).astype(np.int64)) * 1e-9
        self.t_start_s, self.t_end_s = float(t_start_s), float(t_end_s)
        self.eop = default_earth_orientation() if eop is None else eop
        self.ephemeris = Ephemeris() if ephemeris is None else ephemeris
        self.rotation_grid = _Grid(t_start_s, t_end_s, rotation_step_s, _ROTATION_POINTS,
                                   lambda t: self.rotation_direct(t)[0])
        self.body_grid = _Grid(t_start_s, t_end_s, ephemeris_step_s, _EPHEMERIS_POINTS,
                               self.bodies_direct)

    def times(self, t_s) -> np.ndarray:
        """GPS-time labels (datetime64[ns]) of epochs ``t_s`` [s since ``t_ref``]."""
        ns = np.round(np.atleast_1d(np.asarray(t_s, dtype=float)) * 1e9).astype(np.int64)
        return self.t_ref + ns.astype("timedelta64[ns]")

    def tt_j2000_s(self, t_s) -> np.ndarray:
        """TT seconds since J2000.0 of epochs ``t_s``."""
        return self.tt_j2000_ref_s + np.asarray(t_s, dtype=float)

    def rotation_direct(self, t_s) -> tuple[np.ndarray, np.ndarray]:
        """ITRF -> GCRF matrices (n, 3, 3) and their rates, computed without interpolation."""
        return gcrf_from_itrf_matrices(self.times(t_s), self.eop)

    def rotation(self, t_s) -> np.ndarray:
        """Interpolated ITRF -> GCRF matrices, shape (n, 3, 3)."""
        return self.rotation_grid(t_s).reshape(-1, 3, 3)

    def bodies_direct(self, t_s) -> np.ndarray:
        """DE421 without interpolation, (n, 9): GCRF Sun position [m], Sun velocity [m/s]
        (central difference over ±60 s), Moon position [m]."""
        tt = self.tt_j2000_s(t_s)
        h = _SUN_VELOCITY_STEP_S
        sun_vel = (self.ephemeris.sun_m(tt + h) - self.ephemeris.sun_m(tt - h)) / (2 * h)
        return np.hstack([self.ephemeris.sun_m(tt), sun_vel, self.ephemeris.moon_m(tt)])

    def sun_m(self, t_s) -> np.ndarray:
        """Interpolated geocentric GCRF Sun positions [m], shape (n, 3)."""
        return self.body_grid(t_s)[:, 0:3]

    def moon_m(self, t_s) -> np.ndarray:
        """Interpolated geocentric GCRF Moon positions [m], shape (n, 3)."""
        return self.body_grid(t_s)[:, 6:9]

    def check(self, t_s: float) -> None:
        """Raise ValueError if ``t_s`` is outside the grids (the arc ± one node)."""
        lo, hi = self.rotation_grid.span
        if not lo <= t_s <= hi:
            raise ValueError(f"epoch {t_s} s outside the arc [{self.t_start_s}, "
                             f"{self.t_end_s}] s of the force model")


# ------------------------------------------------------------------------------- gravity


#: Positions of the gradient components in the nine sums of ``GravityField.kernel_args``:
#: a_x, a_y, a_z, then xx, xy, xz, yy, yz, zz (:mod:`leopod.dynamics.gravity_field`).
_GRAD_INDEX = np.array([[3, 4, 5], [4, 6, 7], [5, 7, 8]])


@numba.njit(cache=True)
def _rotation_at(t, grid, rot):  # pragma: no cover - numba
    """Interpolated ITRF -> GCRF matrix at t into rot (3, 3)."""
    flat = np.empty(9)
    lagrange_equidistant(t, grid[0], grid[1], grid[2], grid[3], flat)
    for i in range(3):
        for j in range(3):
            rot[i, j] = flat[3 * i + j]


@numba.njit(cache=True)
def _gravity_kernel(t, pos, rot_grid, full_gradient, sum_args, grad_args, with_tides,
                    tide_args, tide_grid, acc, grad):  # pragma: no cover - numba
    """GCRF acceleration ``R ∇U(Rᵀ r)`` and gradient ``R G Rᵀ`` of the field (+ tides)."""
    rot = np.empty((3, 3))
    _rotation_at(t, rot_grid, rot)
    pos_ef = np.empty(3)
    for i in range(3):
        pos_ef[i] = rot[0, i] * pos[0] + rot[1, i] * pos[1] + rot[2, i] * pos[2]
    sums = np.empty(9)
    acc_ef = np.empty(3)
    if full_gradient:
        field_sums(pos_ef, *sum_args, sums)
        acc_ef[:] = sums[:3]
    else:
        acceleration_sums(pos_ef, *sum_args, acc_ef)
        field_sums(pos_ef, *grad_args, sums)
    if with_tides:
        flat = np.empty(tide_grid[3].shape[1])
        lagrange_equidistant(t, tide_grid[0], tide_grid[1], tide_grid[2], tide_grid[3], flat)
        tide_acc = np.empty(3)
        acceleration_sums(pos_ef, *tide_args, flat.reshape(flat.shape[0] // 6, 6), tide_acc)
        for i in range(3):
            acc_ef[i] += tide_acc[i]
    g_ef = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            g_ef[i, j] = sums[_GRAD_INDEX[i, j]]
    grad[:, :] = rot @ g_ef @ rot.T
    for i in range(3):
        acc[i] = rot[i, 0] * acc_ef[0] + rot[i, 1] * acc_ef[1] + rot[i, 2] * acc_ef[2]


class EarthGravity(Force):
    """Static gravity field plus tidal corrections, in the GCRF (no parameters).

    ``a = R ∇(U + ΔU_tides)(Rᵀ r)`` with R the ITRF -> GCRF matrix interpolated from
    ``env``; ``∂a/∂r = R G Rᵀ``, G the gradient of the static field (of ``gradient_field`` if
    given, e.g. a lower degree for speed). The tidal ΔC̄nm, ΔS̄nm of ``tides`` are computed on
    a grid (``tide_step_s``) and their acceleration-sum tables (linear in ΔC̄, ΔS̄) interpolated
    in time; the tidal part of G (< 1e-7 of G) is neglected.

    Parameters
    ----------
    field : GravityField
        Static field (GM and R of the model are used for its coefficients and the tides).
    env : ArcEnvironment
    tides : TideModel, optional
        Tidal corrections; its ``tide_system`` must be the field's (see :func:`build_force_model`).
    gradient_field : GravityField, optional
        Field whose gradient gives ``∂a/∂r`` (default: ``field``).
    tide_step_s : float
        Node spacing of the tidal corrections [s] (default 300).
    """

    def __init__(self, field: GravityField, env: ArcEnvironment, tides: TideModel | None = None,
                 *, gradient_field: GravityField | None = None, tide_step_s: float = 300.0):
        self.field, self.env, self.tides = field, env, tides
        self.parameters = []
        self._full = gradient_field is None
        if self._full:
            self._sum_args = self._grad_args = field.kernel_args("gradient")
        else:
            self._sum_args = field.kernel_args("acceleration")
            self._grad_args = gradient_field.kernel_args("gradient")
        # tidal acceleration sums to degree N + 1 (tables packed as GravityField's, to N + 2)
        degree = 0 if tides is None else tides.max_degree
        recursion = recursion_tables(degree + 2)
        self._tide_offsets = recursion[0]
        self._tide_args = (field.radius_m, degree + 1, *recursion)
        if tides is None:
            self.tide_grid = None
            self._tide_grid_args = (0.0, 1.0, 2, np.zeros((2, 6)))
        else:
            self.tide_grid = _Grid(env.t_start_s, env.t_end_s, tide_step_s, _TIDE_POINTS,
                                   self._tide_tables)
            self._tide_grid_args = self.tide_grid.args()

    def tide_coefficients(self, t_s) -> tuple[np.ndarray, np.ndarray]:
        """Tidal ΔC̄nm, ΔS̄nm (n, N+1, N+1) computed directly at epochs ``t_s`` (n,) [s].

        Inputs of :meth:`TideModel.coefficients`: GMST (IAU 2006, ``erfa.gmst06``) from the
        EOP's UT1, Sun and Moon rotated to the ITRF, pole coordinates of the EOP.
        """
        t = np.atleast_1d(np.asarray(t_s, dtype=float))
        times = self.env.times(t)
        eop = self.env.eop.at(times)
        gmst = erfa.gmst06(*jd_ut1(times, eop), *jd_tt(times))
        rot = self.env.rotation_direct(t)[0]
        bodies = self.env.bodies_direct(t)
        sun_ef = np.einsum("nji,nj->ni", rot, bodies[:, 0:3])
        moon_ef = np.einsum("nji,nj->ni", rot, bodies[:, 6:9])
        return self.tides.coefficients(self.env.tt_j2000_s(t), gmst, sun_ef, moon_ef,
                                       eop.xp_rad, eop.yp_rad)

    def tide_tables(self, dc: np.ndarray, ds: np.ndarray) -> np.ndarray:
        """Packed acceleration-sum tables (n, K·6) of tidal corrections (n, N+1, N+1)."""
        return np.array([acceleration_table(c, s, self.field.gm_m3_s2, self.field.radius_m,
                                            self._tide_offsets).ravel()
                         for c, s in zip(dc, ds)])

    def _tide_tables(self, t_s) -> np.ndarray:
        return self.tide_tables(*self.tide_coefficients(t_s))

    def tide_acceleration_itrf(self, t_s: float, pos_itrf_m: np.ndarray,
                               table: np.ndarray | None = None) -> np.ndarray:
        """Tidal acceleration [m/s²] (ITRF) at one epoch, from the interpolated tables (or
        from ``table`` (K·6,) if given); for tests of the interpolation."""
        if table is None:
            table = self.tide_grid(t_s)[0]
        out = np.empty(3)
        acceleration_sums(np.ascontiguousarray(pos_itrf_m, dtype=float), *self._tide_args,
                          table.reshape(-1, 6), out)
        return out

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        self.env.check(t_s)
        acc = np.empty(3)
        grad = np.empty((3, 3))
        _gravity_kernel(float(t_s), np.ascontiguousarray(pos_m, dtype=float),
                        self.env.rotation_grid.args(), self._full, self._sum_args,
                        self._grad_args, self.tide_grid is not None, self._tide_args,
                        self._tide_grid_args, acc, grad)
        return acc, grad, np.zeros((3, 3)), np.zeros((3, 0))


# ---------------------------------------------------------------- third bodies, relativity


@numba.njit(cache=True)
def _third_body_kernel(t, pos, body_grid, gm, acc, grad):  # pragma: no cover - numba
    """Sun (gm[0]) and Moon (gm[1]; 0 = off) point masses with the indirect term,
    M&G (2000) eq. 3.37, and the gradient ``GM (3 d dᵀ/|d|⁵ − I/|d|³)``, d = s − r."""
    bodies = np.empty(9)
    lagrange_equidistant(t, body_grid[0], body_grid[1], body_grid[2], body_grid[3], bodies)
    acc[:] = 0.0
    grad[:, :] = 0.0
    for b in range(2):
        if gm[b] == 0.0:
            continue
        s = bodies[6 * b:6 * b + 3]
        d = s - pos
        nd = np.sqrt(d[0] ** 2 + d[1] ** 2 + d[2] ** 2)
        ns = np.sqrt(s[0] ** 2 + s[1] ** 2 + s[2] ** 2)
        k3, ks3 = gm[b] / nd**3, gm[b] / ns**3
        for i in range(3):
            acc[i] += k3 * d[i] - ks3 * s[i]
            for j in range(3):
                grad[i, j] += 3.0 * k3 * d[i] * d[j] / (nd * nd) - (k3 if i == j else 0.0)


class ThirdBodies(Force):
    """Sun and Moon as point masses (DE421 via ``env``), M&G (2000) eq. 3.37.

    Parameters
    ----------
    env : ArcEnvironment
    sun, moon : bool
        Include the body.
    """

    def __init__(self, env: ArcEnvironment, sun: bool = True, moon: bool = True):
        self.env = env
        self.parameters = []
        self._gm = np.array([GM_SUN_M3_S2 if sun else 0.0, GM_MOON_M3_S2 if moon else 0.0])

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        self.env.check(t_s)
        acc = np.empty(3)
        grad = np.empty((3, 3))
        _third_body_kernel(float(t_s), np.ascontiguousarray(pos_m, dtype=float),
                           self.env.body_grid.args(), self._gm, acc, grad)
        return acc, grad, np.zeros((3, 3)), np.zeros((3, 0))


@numba.njit(cache=True)
def _cross(a, b):  # pragma: no cover - numba
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


@numba.njit(cache=True)
def _relativity_kernel(t, pos, vel, body_grid, lense_thirring, de_sitter):  # pragma: no cover
    """IERS Conventions 2010 eq. (10.12), β = γ = 1 (see :mod:`leopod.dynamics.relativity`)."""
    c2 = C_LIGHT_M_S * C_LIGHT_M_S
    gm = GM_EARTH_M3_S2
    r = np.sqrt(pos[0] ** 2 + pos[1] ** 2 + pos[2] ** 2)
    rv = pos[0] * vel[0] + pos[1] * vel[1] + pos[2] * vel[2]
    vv = vel[0] ** 2 + vel[1] ** 2 + vel[2] ** 2
    k = gm / (c2 * r**3)
    acc = k * ((4.0 * gm / r - vv) * pos + 4.0 * rv * vel)
    if lense_thirring:
        j = np.array([0.0, 0.0, EARTH_ANGULAR_MOMENTUM_M2_S])
        acc += 2.0 * k * (3.0 / r**2 * pos[2] * j[2] * _cross(pos, vel) + _cross(vel, j))
    if de_sitter:
        bodies = np.empty(9)
        lagrange_equidistant(t, body_grid[0], body_grid[1], body_grid[2], body_grid[3], bodies)
        big_r = -bodies[0:3]                                   # Earth w.r.t. the Sun
        big_v = -bodies[3:6]
        nr = np.sqrt(big_r[0] ** 2 + big_r[1] ** 2 + big_r[2] ** 2)
        omega = -GM_SUN_M3_S2 / (c2 * nr**3) * _cross(big_v, big_r)
        acc += 3.0 * _cross(omega, vel)
    return acc


class Relativity(Force):
    """Relativistic corrections of IERS Conventions 2010 eq. (10.12), partials neglected.

    Parameters
    ----------
    env : ArcEnvironment
    lense_thirring, de_sitter : bool
        Include these terms (Schwarzschild always).
    """

    def __init__(self, env: ArcEnvironment, lense_thirring: bool = True, de_sitter: bool = True):
        self.env = env
        self.lense_thirring, self.de_sitter = bool(lense_thirring), bool(de_sitter)
        self.parameters = []

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        self.env.check(t_s)
        acc = _relativity_kernel(float(t_s), np.ascontiguousarray(pos_m, dtype=float),
                                 np.ascontiguousarray(vel_m_s, dtype=float),
                                 self.env.body_grid.args(), self.lense_thirring, self.de_sitter)
        return acc, np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((3, 0))


# ---------------------------------------------------------------- non-gravitational forces


def interval_edges(t_start_s: float, t_end_s: float, interval_s: float | None) -> np.ndarray:
    """Boundaries of intervals of ``interval_s`` from ``t_start_s`` (the last ends at
    ``t_end_s``); one interval for ``None``."""
    if interval_s is None:
        return np.array([t_start_s, t_end_s], dtype=float)
    if interval_s <= 0:
        raise ValueError(f"interval_s must be positive, not {interval_s}")
    n = max(int(np.ceil((t_end_s - t_start_s) / interval_s - 1e-9)), 1)
    return np.minimum(t_start_s + interval_s * np.arange(n + 1), t_end_s)


class _Scaled(Force):
    """Force ``s_k a0(t, r, v)`` with a scale factor per interval (shared by drag and SRP).

    Parameters ``f"{prefix}_{k}"``; the interval k holding t is clipped to the first and
    last (the integrator may step just outside the arc); interior edges are breakpoints.
    """

    def __init__(self, env: ArcEnvironment, edges_s: np.ndarray, prefix: str, *,
                 apriori: float = 1.0, estimate: bool = True, sigma: float | None = None):
        self.env = env
        self.edges_s = np.asarray(edges_s, dtype=float)
        n = self.edges_s.size - 1
        self.parameters = [f"{prefix}_{k}" for k in range(n)]
        self.apriori = np.full(n, float(apriori))
        self.estimate = bool(estimate)
        self.sigma = np.full(n, np.inf if sigma is None else float(sigma))

    @property
    def breakpoints_s(self) -> np.ndarray:
        return self.edges_s[1:-1]

    def interval(self, t_s: float) -> int:
        k = int(np.searchsorted(self.edges_s, t_s, side="right")) - 1
        return min(max(k, 0), self.edges_s.size - 2)

    @abstractmethod
    def _unscaled(self, t_s, pos, vel, scale):
        """(s a0, ∂(s a0)/∂r, ∂(s a0)/∂v, a0 (3, 1)) at one state."""

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        self.env.check(t_s)
        k = self.interval(t_s)
        acc, da_dr, da_dv, a0 = self._unscaled(float(t_s), np.asarray(pos_m, dtype=float),
                                               np.asarray(vel_m_s, dtype=float), params[k])
        da_dp = np.zeros((3, len(self.parameters)))
        da_dp[:, k] = a0[:, 0]
        return acc, da_dr, da_dv, da_dp


class Drag(_Scaled):
    """Atmospheric drag on a cannonball, one scale factor per interval (M&G 2000, sec. 3.5).

    ``a = −½ s_k ρ (C_D A/m) |v_r| v_r``, ``v_r = v − ω × r`` with ω the Earth's rotation
    about the CIP (``ω_E R ẑ``, R the ITRF -> GCRF matrix); ρ and ∇ρ from ``density``
    (:class:`leopod.dynamics.drag.HarrisPriesterDensity` or ``MsisDensity``).

    Parameters
    ----------
    env : ArcEnvironment
    density : callable
        ``density(t_tt_j2000_s, pos_gcrf_m, rot_gcrf_to_itrf, sun_gcrf_m) -> (ρ, ∇ρ)``.
    cd_area_mass_m2_kg : float
        C_D A/m [m²/kg].
    edges_s : array_like, shape (n + 1,)
        Interval boundaries [s] of the scale factors ``drag_scale_k``.
    apriori, estimate, sigma
        A priori scale, whether it is estimated, a priori constraint (None: free).
    """

    def __init__(self, env, density, cd_area_mass_m2_kg: float, edges_s, **kwargs):
        super().__init__(env, edges_s, "drag_scale", **kwargs)
        self.density = density
        self.cd_area_mass_m2_kg = float(cd_area_mass_m2_kg)

    def _unscaled(self, t_s, pos, vel, scale):
        bodies = self.env.body_grid(t_s)[0]
        rot = self.env.rotation(t_s)[0]
        rho, grad_rho = self.density(self.env.tt_j2000_ref_s + t_s, pos, rot.T, bodies[0:3])
        acc, da_dr, da_dv, a0 = drag_cannonball(pos, vel, rho, grad_rho, self.cd_area_mass_m2_kg,
                                                scale, omega_rad_s=OMEGA_EARTH_RAD_S * rot[:, 2])
        return acc, da_dr, da_dv, a0


class SolarRadiation(_Scaled):
    """Solar radiation pressure on a cannonball with the conical Earth shadow, scale
    factor(s) ``srp_scale_k`` (M&G 2000, sec. 3.4; :func:`leopod.dynamics.srp.srp_cannonball`).

    Parameters
    ----------
    env : ArcEnvironment
    cr_area_mass_m2_kg : float
        C_R A/m [m²/kg].
    edges_s : array_like, shape (n + 1,)
        Interval boundaries [s] of the scale factors.
    shadow : bool
        Apply the conical shadow.
    r_earth_m : float
        Radius of the occulting Earth [m].
    apriori, estimate, sigma
        As :class:`Drag` (default: not estimated).
    """

    def __init__(self, env, cr_area_mass_m2_kg: float, edges_s, *, shadow: bool = True,
                 r_earth_m: float = R_EARTH_EQUATOR_M, **kwargs):
        kwargs.setdefault("estimate", False)
        super().__init__(env, edges_s, "srp_scale", **kwargs)
        self.cr_area_mass_m2_kg = float(cr_area_mass_m2_kg)
        self.shadow, self.r_earth_m = bool(shadow), float(r_earth_m)

    def _unscaled(self, t_s, pos, vel, scale):
        sun = self.env.body_grid(t_s)[0, 0:3]
        return srp_cannonball(pos, sun, self.cr_area_mass_m2_kg, scale,
                              r_earth_m=self.r_earth_m, shadow=self.shadow)


class Empirical(Force):
    """Constant and once-per-revolution accelerations per interval
    (:func:`leopod.dynamics.empirical.empirical_acceleration`); parameters
    ``emp_{term}_{direction}_{k}`` [m/s²].

    Parameters
    ----------
    model : EmpiricalModel
    apriori, estimate, sigma
        A priori value of every coefficient (0), whether they are estimated, and an a priori
        constraint [m/s²] (None: free).
    """

    def __init__(self, model: EmpiricalModel, *, apriori: float = 0.0, estimate: bool = True,
                 sigma: float | None = None):
        self.model = model
        self.parameters = model.names("emp")
        self.apriori = np.full(model.n_params, float(apriori))
        self.estimate = bool(estimate)
        self.sigma = np.full(model.n_params, np.inf if sigma is None else float(sigma))

    @property
    def breakpoints_s(self) -> np.ndarray:
        return self.model.boundaries_s[1:-1]

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        return empirical_acceleration(t_s, pos_m, vel_m_s, params, self.model)


# ---------------------------------------------------------------------------------- builder

_SECTIONS = {
    "environment": {"rotation_step_s", "ephemeris_step_s", "ephemeris"},
    "gravity": {"enabled", "field", "max_degree", "gradient_degree"},
    "tides": {"enabled", "solid", "ocean", "ocean_max_degree", "solid_pole", "ocean_pole",
              "step_s"},
    "third_body": {"enabled", "sun", "moon"},
    "relativity": {"enabled", "lense_thirring", "de_sitter"},
    "drag": {"enabled", "cd_area_mass_m2_kg", "drag_coefficient", "area_m2", "mass_kg",
             "density", "space_weather", "msis_version", "hp_exponent", "interval_s",
             "apriori", "estimate", "sigma"},
    "srp": {"enabled", "cr_area_mass_m2_kg", "reflectivity_coefficient", "area_m2", "mass_kg",
            "shadow", "r_earth_m", "interval_s", "apriori", "estimate", "sigma"},
    "empirical": {"enabled", "interval_s", "directions", "terms", "apriori", "estimate",
                  "sigma"},
}


def _section(config: Mapping, name: str) -> dict | None:
    """The settings of one force, or None if it is switched off."""
    value = config.get(name)
    if value is None or value is False:
        return None
    if value is True:
        return {}
    if not isinstance(value, Mapping):
        raise TypeError(f"force config '{name}' must be a mapping, True/False or None")
    unknown = sorted(set(value) - _SECTIONS[name])
    if unknown:
        raise ValueError(f"force config '{name}': unknown keys {unknown}")
    return None if not value.get("enabled", True) else dict(value)


@functools.lru_cache(maxsize=4)
def _read_icgem(path: str) -> xr.Dataset:
    return read_icgem(path)


@functools.lru_cache(maxsize=4)
def _ocean_tides(path: str, max_degree: int) -> OceanTides:
    return OceanTides.from_file(path, max_degree=max_degree)


@functools.lru_cache(maxsize=2)
def _space_weather(path: str) -> xr.Dataset:
    return read_space_weather(path)


def _area_mass(cfg: dict, key: str, coefficient_key: str, default: float) -> float:
    """C A/m [m²/kg] from ``key`` or from coefficient × area_m2 / mass_kg."""
    if key in cfg:
        return float(cfg[key])
    if "area_m2" not in cfg or "mass_kg" not in cfg:
        raise ValueError(f"give {key} or area_m2 and mass_kg")
    return float(cfg.get(coefficient_key, default)) * float(cfg["area_m2"]) / float(cfg["mass_kg"])


def _gravity(cfg: dict, tides_cfg: dict | None, env: ArcEnvironment) -> Force:
    if "field" not in cfg:
        raise ValueError("force config 'gravity' needs 'field' (ICGEM path or Dataset)")
    ds = cfg["field"]
    if not isinstance(ds, xr.Dataset):
        ds = _read_icgem(str(Path(ds)))
    epoch = decimal_year(env.t_ref)
    available = int(ds.attrs.get("max_degree", ds.sizes["n"] - 1))
    field = GravityField(ds, cfg.get("max_degree", min(120, available)), epoch_decimal_year=epoch)
    gradient_degree = cfg.get("gradient_degree")
    gradient_field = None
    if gradient_degree is not None and gradient_degree < field.max_degree:
        gradient_field = GravityField(ds, gradient_degree, epoch_decimal_year=epoch)
    tides = None
    if tides_cfg is not None:
        ocean = tides_cfg.get("ocean")
        if ocean is not None:
            ocean = _ocean_tides(str(Path(ocean)), int(tides_cfg.get("ocean_max_degree", 30)))
        try:
            tides = TideModel(field.tide_system, ocean=ocean, solid=tides_cfg.get("solid", True),
                              solid_pole=tides_cfg.get("solid_pole", True),
                              ocean_pole=tides_cfg.get("ocean_pole", True),
                              gm_earth_m3_s2=field.gm_m3_s2, radius_m=field.radius_m)
        except ValueError as err:
            raise ValueError(f"tides with the gravity field {field.modelname}: {err}") from None
        if not (tides.solid or tides.solid_pole or tides.ocean_pole or ocean is not None):
            tides = None
    return EarthGravity(field, env, tides, gradient_field=gradient_field,
                        tide_step_s=float((tides_cfg or {}).get("step_s", 300.0)))


def _drag(cfg: dict, env: ArcEnvironment) -> Drag:
    kind = cfg.get("density", "msis" if "space_weather" in cfg else "harris_priester")
    if kind == "msis":
        if "space_weather" not in cfg:
            raise ValueError("force config 'drag': density 'msis' needs 'space_weather'")
        density = MsisDensity(_space_weather(str(Path(cfg["space_weather"]))),
                              version=cfg.get("msis_version", 0))
    elif kind == "harris_priester":
        density = HarrisPriesterDensity(cfg.get("hp_exponent", 6.0))
    else:
        raise ValueError(f"force config 'drag': unknown density '{kind}' "
                         "(harris_priester or msis)")
    edges = interval_edges(env.t_start_s, env.t_end_s, cfg.get("interval_s"))
    return Drag(env, density, _area_mass(cfg, "cd_area_mass_m2_kg", "drag_coefficient",
                                         DEFAULT_DRAG_COEFFICIENT), edges,
                **_parameter_options(cfg, 1.0, True))


def _srp(cfg: dict, env: ArcEnvironment) -> SolarRadiation:
    edges = interval_edges(env.t_start_s, env.t_end_s, cfg.get("interval_s"))
    return SolarRadiation(env, _area_mass(cfg, "cr_area_mass_m2_kg", "reflectivity_coefficient",
                                          DEFAULT_REFLECTIVITY_COEFFICIENT), edges,
                          shadow=cfg.get("shadow", True),
                          r_earth_m=cfg.get("r_earth_m", R_EARTH_EQUATOR_M),
                          **_parameter_options(cfg, 1.0, False))


def _empirical(cfg: dict, env: ArcEnvironment) -> Empirical:
    edges = interval_edges(env.t_start_s, env.t_end_s, cfg.get("interval_s", 10800.0))
    model = EmpiricalModel(edges, directions=tuple(cfg.get("directions", ("T", "N"))),
                           terms=tuple(cfg.get("terms", ("const", "cos", "sin"))))
    return Empirical(model, **_parameter_options(cfg, 0.0, True))


def _parameter_options(cfg: dict, apriori: float, estimate: bool) -> dict:
    return {"apriori": cfg.get("apriori", apriori), "estimate": cfg.get("estimate", estimate),
            "sigma": cfg.get("sigma")}


def build_force_model(config: Mapping, t_ref, t_start_s: float, t_end_s: float, *,
                      eop: EarthOrientation | None = None,
                      environment: ArcEnvironment | None = None) -> ForceModel:
    """Force model of an arc from a plain configuration dict (module docstring).

    Parameters
    ----------
    config : mapping
        One section per force (``gravity``, ``tides``, ``third_body``, ``relativity``,
        ``drag``, ``srp``, ``empirical``) and optional ``environment`` grid settings.
    t_ref : datetime64
        Reference epoch (GPS-time label); force times are TT s since it.
    t_start_s, t_end_s : float
        The arc [s since ``t_ref``] (intervals of estimated parameters start at ``t_start_s``).
    eop : EarthOrientation, optional
        EOP (default: installed IERS data).
    environment : ArcEnvironment, optional
        Grids to reuse (must cover the arc); built from ``config["environment"]`` otherwise.

    Returns
    -------
    ForceModel
        Forces in the order gravity, third bodies, relativity, drag, SRP, empirical.
    """
    unknown = sorted(set(config) - set(_SECTIONS))
    if unknown:
        raise ValueError(f"force config: unknown sections {unknown} (known: {sorted(_SECTIONS)})")
    if environment is None:
        env_cfg = _section(config, "environment") or {}
        eph = env_cfg.get("ephemeris")
        environment = ArcEnvironment(
            t_ref, t_start_s, t_end_s, eop=eop,
            ephemeris=None if eph is None else Ephemeris(eph),
            rotation_step_s=env_cfg.get("rotation_step_s", 60.0),
            ephemeris_step_s=env_cfg.get("ephemeris_step_s", 600.0))
    env = environment
    forces: list[Force] = []
    gravity = _section(config, "gravity")
    forces.append(PointMassGravity() if gravity is None
                  else _gravity(gravity, _section(config, "tides"), env))
    third = _section(config, "third_body")
    if third is not None:
        forces.append(ThirdBodies(env, third.get("sun", True), third.get("moon", True)))
    rel = _section(config, "relativity")
    if rel is not None:
        forces.append(Relativity(env, rel.get("lense_thirring", True), rel.get("de_sitter", True)))
    for name, make in (("drag", _drag), ("srp", _srp), ("empirical", _empirical)):
        cfg = _section(config, name)
        if cfg is not None:
            forces.append(make(cfg, env))
    model = ForceModel(forces)
    logger.info("force model: %s; %d parameters", ", ".join(type(f).__name__ for f in forces),
                model.n_params)
    return model


def _per_parameter(force_model: ForceModel, attribute: str, default) -> np.ndarray:
    parts = []
    for force in force_model.forces:
        k = len(force.parameters)
        value = getattr(force, attribute, default)
        parts.append(np.broadcast_to(np.asarray(value), (k,)))
    return np.concatenate(parts) if parts else np.empty(0)


def apriori_parameters(force_model: ForceModel) -> np.ndarray:
    """A priori values (P,) of the force model's parameters (0 for forces without any)."""
    return _per_parameter(force_model, "apriori", 0.0).astype(float)


def estimated_parameters(force_model: ForceModel) -> np.ndarray:
    """Boolean mask (P,): which parameters are estimated (default True)."""
    return _per_parameter(force_model, "estimate", True).astype(bool)


def constraint_sigmas(force_model: ForceModel) -> np.ndarray:
    """A priori standard deviations (P,) of the parameters (inf: unconstrained)."""
    return _per_parameter(force_model, "sigma", np.inf).astype(float)
