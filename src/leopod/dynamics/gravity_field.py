"""Earth gravity field: potential, acceleration and its gradient from spherical harmonics.

:class:`GravityField` holds the coefficients of a model (fully normalised ``C̄nm``, ``S̄nm``
of an ICGEM file) and sums them with the recursions and compiled kernels of
:mod:`leopod.dynamics.spherical_harmonics` (formulas there), in the Earth-fixed frame.

given as a decimal year with :meth:`GravityField.at_epoch` (formula in
:mod:`leopod.io.icgem`). The tide system (``tide_free``, ``zero_tide``, ...) is recorded from the
file; converting C̄20 between systems is left to the solid-tide model.

:class:`EarthGravity` is its force in the GCRF for the orbit integrator: the static field plus
the tidal ΔC̄nm, ΔS̄nm of :class:`leopod.dynamics.tides.TideModel` (solid Earth steps 1-2, ocean
FES2004, solid and ocean pole tides; IERS Conventions 2010 ch. 6), evaluated in the ITRF and
rotated: ``a = R ∇U(Rᵀ r)``, ``∂a/∂r = R G Rᵀ`` (G = ∇∇U; the tidal part of G, < 1e-7 of it,
is neglected), R and the tidal tables interpolated on the grids of
:class:`leopod.dynamics.environment.ArcEnvironment`.
"""

from __future__ import annotations

import logging
from datetime import date

import erfa
import numba
import numpy as np
import xarray as xr

from leopod.dynamics.environment import ArcEnvironment, _Grid
from leopod.dynamics.forces import Force
from leopod.dynamics.spherical_harmonics import (
    _acc_grad_fields,
    _acc_grad_many,
    _field_table,
    _sums_many,
    acceleration_sums,
    acceleration_table,
    field_sums,
    recursion_tables,
)
from leopod.dynamics.tides import TideModel
from leopod.numerics.interpolate import lagrange_equidistant
from leopod.time.eop import jd_ut1
from leopod.time.scales import jd_tt

__all__ = ["EarthGravity", "GravityField", "decimal_year"]

logger = logging.getLogger(__name__)

_TIDE_POINTS = 6              # Lagrange points of the tidal coefficient tables (degree 5)


def decimal_year(day: date | np.datetime64 | str) -> float:
    """Decimal year of an instant: ``year + (t − 1 January 0 h)/(length of that year)``.

    This is the convention used for the reference epoch ``t0`` of ICGEM time-variable models
    (so that t0 = 2005-01-01 gives 2005.0); the time scale (UTC, GPS, TT) is irrelevant at the
    precision of these terms (1 min = 2e-6 year).

    Parameters
    ----------
    day : date, numpy.datetime64 or ISO string
        The instant.

    Returns
    -------
    float
        Decimal year [year].
    """
    t = np.datetime64(day, "ns")
    year = t.astype("datetime64[Y]")
    start = year.astype("datetime64[ns]")
    length = (year + 1).astype("datetime64[ns]") - start
    return float(year.astype(int) + 1970) + float((t - start) / length)


# ---------------------------------------------------------------------------------- class


class GravityField:
    """Spherical-harmonic gravity field of the Earth, evaluated in the Earth-fixed frame.

    Parameters
    ----------
    dataset : xarray.Dataset
        ICGEM model from :func:`leopod.io.icgem.read_icgem` (fully normalised ``C``, ``S``
        (n, m), attributes ``gm_m3_s2``, ``radius_m``, ``tide_system``, optional time-variable
        terms).
    max_degree : int or None, optional
        Degree and order N of the expansion (default 120); None: the degree of ``dataset``.
    central_term : bool, optional
        Keep C̄00 (default). False gives only the non-spherical part of the field.
    epoch_decimal_year : float, optional
        Epoch [decimal year, see :func:`decimal_year`] at which the time-variable terms of
        the model are evaluated (:meth:`at_epoch`). Ignored by static models; a time-variable
        model without an epoch uses its static part (``gfct`` records, i.e. without trend and
        periodic terms), with a logged warning.

    Attributes
    ----------
    gm_m3_s2, radius_m : float
        GM [m³/s²] and reference radius R [m] of the model (used with its coefficients).
    max_degree : int
    tide_system : str
        As stated by the file (``tide_free``, ``zero_tide``, ``unknown``, ...).
    modelname : str
    epoch_decimal_year : float or None
    c, s : ndarray, shape (N + 1, N + 1)
        Fully normalised coefficients in use (C̄00 = 0 when ``central_term`` is False).
    """

    def __init__(self, dataset: xr.Dataset, max_degree: int | None = 120, *,
                 central_term: bool = True, epoch_decimal_year: float | None = None):
        available = int(dataset.attrs.get("max_degree", dataset.sizes["n"] - 1))
        degree = available if max_degree is None else int(max_degree)
        if not 0 <= degree <= available:
            raise ValueError(f"max_degree {degree} outside 0..{available} (the degree of "
                             f"{dataset.attrs.get('modelname', 'the model')})")
        self._dataset = dataset.isel(n=slice(0, degree + 1), m=slice(0, degree + 1))
        self.max_degree = degree
        self.gm_m3_s2 = float(dataset.attrs["gm_m3_s2"])
        self.radius_m = float(dataset.attrs["radius_m"])
        self.tide_system = str(dataset.attrs.get("tide_system", "unknown"))
        self.modelname = str(dataset.attrs.get("modelname", ""))
        self.central_term = central_term
        self.epoch_decimal_year = epoch_decimal_year
        if self._time_variable and epoch_decimal_year is None:
            logger.warning("%s has time-variable terms but no epoch was given: using its "
                           "static part (gfct, t0 = %s) without trend and periodic terms",
                           self.modelname, dataset.attrs.get("t0"))
        if epoch_decimal_year is None:
            c, s = (self._dataset[v].values.copy() for v in ("C", "S"))
        else:
            c, s = self.at_epoch(epoch_decimal_year)
        if not central_term:
            c[0, 0] = 0.0
        c.flags.writeable = s.flags.writeable = False
        self.c, self.s = c, s
        self._build_tables()

    @property
    def _time_variable(self) -> bool:
        return bool(self._dataset.attrs.get("time_variable_terms", ""))

    def at_epoch(self, epoch_decimal_year: float) -> tuple[np.ndarray, np.ndarray]:
        """Coefficients of the model at an epoch (including C̄00, whatever ``central_term``).

        ICGEM icgem1.0 time-variable model (Barthelmes & Foerste 2011; :mod:`leopod.io.icgem`),
        with ``Δt = t − t0`` in years (t0 as a decimal year by :func:`decimal_year`)::

            G(t) = gfct + trnd Δt + Σ_p [acos_p cos(2π Δt/p) + asin_p sin(2π Δt/p)]

        Parameters
        ----------
        epoch_decimal_year : float
            Epoch t [decimal year].

        Returns
        -------
        c, s : ndarray, shape (N + 1, N + 1)
            Fully normalised coefficients at t (the static ones for a static model).
        """
        ds = self._dataset
        c, s = ds["C"].values.copy(), ds["S"].values.copy()
        if not self._time_variable:
            return c, s
        dt_year = epoch_decimal_year - decimal_year(ds.attrs["t0"])
        for name, out in (("C", c), ("S", s)):
            if f"trnd_{name}" in ds:
                out += ds[f"trnd_{name}"].values * dt_year
            if f"acos_{name}" in ds:
                arg = 2 * np.pi * dt_year / ds["period"].values
                out += np.einsum("p,pnm->nm", np.cos(arg), ds[f"acos_{name}"].values)
                out += np.einsum("p,pnm->nm", np.sin(arg), ds[f"asin_{name}"].values)
        return c, s

    def _build_tables(self) -> None:
        """Precompute recursion factors and the coefficients of the ten sums (to degree N+2)."""
        top = self.max_degree + 2
        self._offsets, self._rec_a, self._rec_b, self._diag = recursion_tables(top)
        fields = _acc_grad_fields(self.c, self.s, self.gm_m3_s2, self.radius_m)
        recursion = (self._offsets, self._rec_a, self._rec_b, self._diag)
        self._kernel_args = {
            kind: (self.radius_m, self.max_degree + extra, *recursion,
                   _field_table(fields[first:last], self._offsets))
            for kind, extra, first, last in (("potential", 0, 0, 1), ("acceleration", 1, 1, 4),
                                             ("gradient", 2, 1, 10))}

    def kernel_args(self, kind: str = "acceleration") -> tuple:
        """Arguments ``(radius_m, degree, offsets, rec_a, rec_b, diag, table)`` of
        :func:`leopod.dynamics.spherical_harmonics.field_sums` (or ``acceleration_sums``) for
        use inside other jitted code.

        ``kind`` "potential" gives 1 sum (U), "acceleration" 3 (a_x, a_y, a_z) and
        "gradient" 9 (a_x, a_y, a_z, then ∂a/∂r: xx, xy, xz, yy, yz, zz).
        """
        return self._kernel_args[kind]

    def _sums(self, pos_m, kind: str, nf: int) -> tuple[np.ndarray, bool]:
        pos = np.asarray(pos_m, dtype=float)
        single = pos.ndim == 1
        pos2 = np.ascontiguousarray(pos.reshape(-1, 3))
        out = np.empty((pos2.shape[0], nf))
        if not _sums_many(pos2, *self.kernel_args(kind), out):
            raise ValueError("the gravity field is undefined at the geocentre (position 0)")
        return out, single

    def potential(self, pos_m: np.ndarray) -> np.ndarray:
        """Gravitational potential U (positive, U = GM/r for the central term).

        Parameters
        ----------
        pos_m : ndarray, shape (n, 3) or (3,)
            Earth-fixed positions [m].

        Returns
        -------
        ndarray, shape (n,) or ()
            Potential [m²/s²].
        """
        out, single = self._sums(pos_m, "potential", 1)
        return out[0, 0] if single else out[:, 0]

    def acceleration(self, pos_m: np.ndarray) -> np.ndarray:
        """Gravitational acceleration ``a = ∇U`` (Earth-fixed axes).

        Parameters
        ----------
        pos_m : ndarray, shape (n, 3) or (3,)
            Earth-fixed positions [m].

        Returns
        -------
        ndarray, shape (n, 3) or (3,)
            Acceleration [m/s²].
        """
        out, single = self._sums(pos_m, "acceleration", 3)
        return out[0] if single else out

    def acceleration_and_gradient(self, pos_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Acceleration and its gradient ``∂a_i/∂r_j = ∂²U/∂r_i∂r_j`` (symmetric, trace 0).

        Parameters
        ----------
        pos_m : ndarray, shape (n, 3) or (3,)
            Earth-fixed positions [m].

        Returns
        -------
        acc : ndarray, shape (n, 3) or (3,)
            Acceleration [m/s²].
        grad : ndarray, shape (n, 3, 3) or (3, 3)
            Gradient [1/s²].
        """
        pos = np.asarray(pos_m, dtype=float)
        pos2 = np.ascontiguousarray(pos.reshape(-1, 3))
        acc = np.empty((pos2.shape[0], 3))
        grad = np.empty((pos2.shape[0], 3, 3))
        if not _acc_grad_many(pos2, *self.kernel_args("gradient"), acc, grad):
            raise ValueError("the gravity field is undefined at the geocentre (position 0)")
        return (acc[0], grad[0]) if pos.ndim == 1 else (acc, grad)

    def __repr__(self) -> str:
        return (f"GravityField({self.modelname!r}, N={self.max_degree}, tide_system="
                f"{self.tide_system!r}, central_term={self.central_term}, "
                f"epoch_decimal_year={self.epoch_decimal_year})")


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
        Tidal corrections; its ``tide_system`` must be the field's (see
        :func:`leopod.dynamics.force_config.build_force_model`).
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

    def kernel_data(self) -> tuple:
        """The arguments of :func:`_gravity_kernel` after ``t, pos`` (compiled force model)."""
        return (self.env.rotation_grid.args(), self._full, self._sum_args, self._grad_args,
                self.tide_grid is not None, self._tide_args, self._tide_grid_args)

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        self.env.check(t_s)
        acc = np.empty(3)
        grad = np.empty((3, 3))
        _gravity_kernel(float(t_s), np.ascontiguousarray(pos_m, dtype=float),
                        *self.kernel_data(), acc, grad)
        return acc, grad, np.zeros((3, 3)), np.zeros((3, 0))

