"""The force model as one compiled right-hand side: all forces and the variational equations.

:class:`leopod.dynamics.forces.ForceModel` sums Python force objects, each calling its own
jitted kernel: ~100 µs of Python glue per evaluation on top of the kernels. Here the forces
of :func:`leopod.dynamics.force_config.build_force_model` (Earth gravity with tides, Sun and
Moon, relativity, drag, solar radiation pressure, Earth radiation pressure, empirical
accelerations, manoeuvres; drag and radiation on a cannonball or on plates) are evaluated by one
numba function, :func:`force_sum`, from the data of the force objects (their
``kernel_data()``): the same kernels, the same interpolated Earth rotation, Sun and Moon, the
same sums in the same order, so accelerations and partials equal those of
:meth:`ForceModel.evaluate` to round-off (tests/dynamics/test_compiled.py). The Gauss–Jackson
integrator calls it from compiled code (:func:`leopod.dynamics.gauss_jackson.gauss_jackson_compiled`).

Drag needs its density along a reference orbit (:meth:`leopod.dynamics.drag.Drag.follow`):
the density models are Python (pymsis), so they are tabulated per arc instead of called per
evaluation; plate forces likewise need the attitude along it
(:class:`leopod.dynamics.plates.Plates`). A force model holding any other force (e.g. the
point-mass field of the tests, :class:`leopod.dynamics.forces.ConstantAcceleration`), or drag
or plates without a reference orbit, has
no compiled form (:meth:`CompiledForceModel.of` returns None) and is integrated through the
Python path.
"""

from __future__ import annotations

import numba
import numpy as np

from leopod.constants import OMEGA_EARTH_RAD_S
from leopod.dynamics.drag import Drag, _density_at, _drag_kernel, _facing_area
from leopod.dynamics.earth_radiation import EarthRadiation, erp_kernel
from leopod.dynamics.empirical import Empirical, _local_partials
from leopod.dynamics.forces import ForceModel
from leopod.dynamics.gravity_field import EarthGravity, _gravity_kernel
from leopod.dynamics.manoeuvre import Manoeuvres
from leopod.dynamics.plates import plate_normals_at
from leopod.dynamics.relativity import Relativity, _relativity_kernel
from leopod.dynamics.srp import SolarRadiation, _cannonball, _plates, absent_plates
from leopod.dynamics.third_body import ThirdBodies, _third_body_kernel
from leopod.numerics.interpolate import lagrange_equidistant

__all__ = ["CompiledForceModel", "fill_acceleration", "force_sum"]

_OPTIONAL = (ThirdBodies, Relativity, Drag, SolarRadiation, EarthRadiation, Empirical,
             Manoeuvres)


@numba.njit(cache=True)
def _interval(edges, t):  # pragma: no cover - numba
    """Index of the interval of ``edges`` holding t, clipped to the first and last."""
    k = np.searchsorted(edges, t, side="right") - 1
    return min(max(k, 0), edges.size - 2)


@numba.njit(cache=True)
def _add(acc, da_dr, da_dv, a, dr, dv, scale):  # pragma: no cover - numba
    for i in range(3):
        acc[i] += scale * a[i]
        for j in range(3):
            da_dr[i, j] += scale * dr[i, j]
            da_dv[i, j] += scale * dv[i, j]


@numba.njit(cache=True)
def force_sum(t, pos, vel, params, data, acc, da_dr, da_dv, da_dp,
              with_dp=True):  # pragma: no cover - numba
    """Total acceleration and partials of a :class:`CompiledForceModel` (its ``data``).

    Arguments and results (filled in place) as :meth:`leopod.dynamics.forces.ForceModel.evaluate`:
    ``acc`` (3,), ``da_dr`` and ``da_dv`` (3, 3), ``da_dp`` (3, P). Without ``with_dp``
    ``da_dp`` is scratch (not cleared, only the current intervals' columns written): an
    integration without partials does not use it, and clearing (3, P) at every evaluation
    cost ~20 µs for the P = 13 445 parameters of a 30-day simulated truth.
    """
    gravity, third, relativity, drag, srp, erp, empirical, manoeuvre = data
    zero3 = np.zeros((3, 3))
    acc[:] = 0.0
    da_dr[:, :] = 0.0
    da_dv[:, :] = 0.0
    if with_dp:
        da_dp[:, :] = 0.0
    a = np.empty(3)
    g = np.empty((3, 3))
    _gravity_kernel(t, pos, gravity[0], gravity[1], gravity[2], gravity[3], gravity[4],
                    gravity[5], gravity[6], a, g)
    _add(acc, da_dr, da_dv, a, g, zero3, 1.0)
    if third[0]:
        _third_body_kernel(t, pos, third[1], third[2], a, g)
        _add(acc, da_dr, da_dv, a, g, zero3, 1.0)
    if relativity[0]:
        a = _relativity_kernel(t, pos, vel, relativity[1], relativity[2], relativity[3])
        _add(acc, da_dr, da_dv, a, zero3, zero3, 1.0)
    if drag[0]:
        offset, edges, coef, table = drag[1], drag[2], drag[3], drag[4]
        k = _interval(edges, t)
        rot = np.empty(9)
        grid = gravity[0]
        lagrange_equidistant(t, grid[0], grid[1], grid[2], grid[3], rot)
        omega = np.array([OMEGA_EARTH_RAD_S * rot[2], OMEGA_EARTH_RAD_S * rot[5],
                          OMEGA_EARTH_RAD_S * rot[8]])          # ω_E R ẑ
        vrel = vel - np.array([omega[1] * pos[2] - omega[2] * pos[1],
                               omega[2] * pos[0] - omega[0] * pos[2],
                               omega[0] * pos[1] - omega[1] * pos[0]])
        skew = np.array([[0.0, -omega[2], omega[1]], [omega[2], 0.0, -omega[0]],
                         [-omega[1], omega[0], 0.0]])
        rho, grad_rho = _density_at(t, pos, table)
        if drag[5]:             # plates: facing area along the flow, 1/m
            plates = drag[6]
            bodies = np.empty(9)
            lagrange_equidistant(t, third[1][0], third[1][1], third[1][2], third[1][3], bodies)
            normals = plate_normals_at(t, pos, bodies[0:3].copy(), plates)
            w = _facing_area(normals, vrel, plates[10], plates[1])
            a0, dr0, dv0 = _drag_kernel(vrel, rho, grad_rho, w, False, 1.0 / plates[9], skew)
        else:
            a0, dr0, dv0 = _drag_kernel(vrel, rho, grad_rho, np.zeros(3), True, coef, skew)
        _add(acc, da_dr, da_dv, a0, dr0, dv0, params[offset + k])
        da_dp[:, offset + k] = a0
    if srp[0]:
        offset, edges, coef, r_earth, shadow = srp[1], srp[2], srp[3], srp[4], srp[5]
        k = _interval(edges, t)
        bodies = np.empty(9)
        grid = third[1]
        lagrange_equidistant(t, grid[0], grid[1], grid[2], grid[3], bodies)
        sun = bodies[0:3].copy()
        if srp[6]:
            plates = srp[7]
            normals = plate_normals_at(t, pos, sun, plates)
            a0, g0 = _plates(pos, sun, normals, plates[1], plates[2], plates[3], plates[9],
                             r_earth, shadow)
        else:
            a0, g0 = _cannonball(pos, sun, coef, r_earth, shadow)
        _add(acc, da_dr, da_dv, a0, g0, zero3, params[offset + k])
        da_dp[:, offset + k] = a0
    if erp[0]:
        offset, edges = erp[1], erp[2]
        k = _interval(edges, t)
        a0 = erp_kernel(t, pos, vel, gravity[0], third[1], erp[3])
        _add(acc, da_dr, da_dv, a0, zero3, zero3, params[offset + k])
        da_dp[:, offset + k] = a0
    if empirical[0]:
        offset, bounds, dir_idx, term_idx = empirical[1], empirical[2], empirical[3], empirical[4]
        n_per = dir_idx.size * term_idx.size
        first = offset + _interval(bounds, t) * n_per
        local = _local_partials(pos, vel, dir_idx, term_idx)
        for i in range(3):
            s = 0.0
            for j in range(n_per):
                s += local[i, j] * params[first + j]
                da_dp[i, first + j] = local[i, j]
            acc[i] += s
    if manoeuvre[0]:
        offset, starts, ends = manoeuvre[1], manoeuvre[2], manoeuvre[3]
        k = np.searchsorted(starts, t, side="right") - 1
        if k >= 0 and t < ends[k]:
            first = offset + 3 * k
            local = _local_partials(pos, vel, np.arange(3), np.zeros(1, np.int64))
            for i in range(3):
                for j in range(3):
                    acc[i] += local[i, j] * params[first + j]
                    da_dp[i, first + j] = local[i, j]


@numba.njit(cache=True)
def fill_acceleration(acc, da_dr, da_dv, da_dp, y, out):  # pragma: no cover - numba
    """``out = [a | A y_r + B y_v (+ ∂a/∂p in the S columns)]`` for y (6, C), out (3, C)
    (the augmented system of :mod:`leopod.dynamics.integrator`)."""
    n_col = y.shape[1]
    for i in range(3):
        out[i, 0] = acc[i]
        for j in range(1, n_col):
            s = 0.0
            for k in range(3):
                s += da_dr[i, k] * y[k, j] + da_dv[i, k] * y[3 + k, j]
            out[i, j] = s
        if n_col > 1:
            for j in range(da_dp.shape[1]):
                out[i, 7 + j] += da_dp[i, j]


@numba.njit(cache=True)
def augmented_rhs(t, y, out, params, data, work):  # pragma: no cover - numba
    """``F(t, Y)`` (3, C) of the augmented matrix Y (6, C) into ``out``; ``work`` is the
    tuple of scratch arrays ``(acc (3,), da_dr (3, 3), da_dv (3, 3), da_dp (3, P))``."""
    acc, da_dr, da_dv, da_dp = work
    force_sum(t, y[:3, 0].copy(), y[3:, 0].copy(), params, data, acc, da_dr, da_dv, da_dp,
              y.shape[1] > 1)
    fill_acceleration(acc, da_dr, da_dv, da_dp, y, out)


def _absent(force_type: type, body_grid: tuple) -> tuple:
    """Data of a force that is not in the model, with the numba types of a present one."""
    edges = np.zeros(2)
    return {ThirdBodies: (False, body_grid, np.zeros(2)),
            Relativity: (False, body_grid, False, False),
            Drag: (False, 0, edges, 0.0, (0.0, 1.0, 2, np.zeros((2, 7))), False,
                   absent_plates()),
            SolarRadiation: (False, 0, edges, 0.0, 0.0, False, False, absent_plates()),
            EarthRadiation: (False, 0, edges, (0.0, 0.0, 2, 0.0, np.zeros(6), False,
                                               absent_plates())),
            Empirical: (False, 0, edges, np.zeros(1, np.int64), np.zeros(1, np.int64)),
            Manoeuvres: (False, 0, edges, edges),
            }[force_type]


class CompiledForceModel:
    """The data of a :class:`ForceModel` for :func:`force_sum` (module docstring).

    Attributes
    ----------
    force_model : ForceModel
    data : tuple
        ``(gravity, third_body, relativity, drag, srp, erp, empirical, manoeuvre)`` kernel
        data.
    env : ArcEnvironment
        The grids the forces interpolate (their span limits the integration).
    """

    def __init__(self, force_model: ForceModel, data: tuple, env):
        self.force_model, self.data, self.env = force_model, data, env

    @classmethod
    def of(cls, force_model: ForceModel) -> CompiledForceModel | None:
        """The compiled form of ``force_model``, or None if it has none (module docstring)."""
        forces = force_model.forces
        kinds = [type(f) for f in forces]
        if (not forces or kinds[0] is not EarthGravity or len(set(kinds)) != len(kinds)
                or any(k not in _OPTIONAL for k in kinds[1:])):
            return None
        gravity = forces[0]
        env = gravity.env
        if any(getattr(f, "env", env) is not env for f in forces):
            return None
        if not all(getattr(f, "ready", True) for f in forces):
            return None
        body_grid = env.body_grid.args()
        slots = {k: _absent(k, body_grid) for k in _OPTIONAL}
        for force, sl in zip(forces[1:], force_model._slices[1:]):
            offset = () if not force.parameters else (sl.start,)
            slots[type(force)] = (True, *offset, *force.kernel_data())
        data = (gravity.kernel_data(), *(slots[k] for k in _OPTIONAL))
        return cls(force_model, data, env)

    def evaluate(self, t_s: float, pos_m: np.ndarray, vel_m_s: np.ndarray,
                 params: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """As :meth:`ForceModel.evaluate`, through :func:`force_sum`."""
        self.env.check(t_s)
        acc, da_dr, da_dv = np.empty(3), np.empty((3, 3)), np.empty((3, 3))
        da_dp = np.empty((3, self.force_model.n_params))
        force_sum(float(t_s), np.ascontiguousarray(pos_m, dtype=float),
                  np.ascontiguousarray(vel_m_s, dtype=float),
                  np.ascontiguousarray(params, dtype=float), self.data, acc, da_dr, da_dv,
                  da_dp)
        return acc, da_dr, da_dv, da_dp


def warm_up() -> None:
    """Compile (and cache) the compiled force model and integrator: a 20-min arc of a small
    model with every force, partials and pulses, and the pulse partials of the POD. ``make
    setup`` runs it once, so that the first POD job does not spend its time compiling."""
    from leopod.dynamics.force_config import ForceModelSettings, build_force_model
    from leopod.dynamics.forces import apriori_parameters, circular_orbit
    from leopod.dynamics.integrator import apply_pulses, pulse_partials
    from leopod.dynamics.model_files import resolve_model_paths

    settings = ForceModelSettings.from_config(resolve_model_paths({
        "gravity": {"field": "satkit:ITU_GRACE16.gfc", "max_degree": 8},
        "tides": {"solid": True}, "third_body": {}, "relativity": {},
        "drag": {"area_m2": 1.0, "mass_kg": 500.0, "density": "harris_priester"},
        "srp": {"area_m2": 1.0, "mass_kg": 500.0}, "empirical": {"interval_s": 600.0}}))
    model = build_force_model(settings, np.datetime64("2020-01-01T00:00", "ns"), 0.0, 1200.0)
    state = np.array([6.9e6, 0.0, 0.0, 0.0, 1.0e3, 7.5e3])
    model.follow(circular_orbit(0.0, state))
    traj = apply_pulses(model, 0.0, state, apriori_parameters(model), [0.0, 1200.0], [600.0],
                        [[1e-6, 0.0, 0.0]])
    pulse_partials(traj, [600.0], position_only=True)


if __name__ == "__main__":
    warm_up()
