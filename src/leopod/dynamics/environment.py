"""Earth rotation, Sun and Moon on time grids over one orbit arc, shared by the forces.

Time ``t_s`` = TT seconds since the reference epoch ``t_ref`` of the arc, a GPS-time
datetime64 label; since TT − GPST is constant, ``t_s`` is also GPS seconds since ``t_ref``.

Slowly varying inputs are precomputed on time grids by :class:`ArcEnvironment` and interpolated
with Lagrange polynomials on equidistant nodes (numba): the ITRF → GCRF matrix (IAU 2006/2000A
with EOP, :func:`leopod.frames.earth_rotation.gcrf_from_itrf_matrices`; 60-s nodes, 8 points:
matrix elements agree with direct evaluation to 1e-13, the resolution of the direct
computation itself, i.e. 1-ns epochs and ``erfa.era00``), the geocentric Sun and Moon (600-s
nodes, 8 points: < 2 mm and < 0.1 mm) and, in :class:`leopod.dynamics.gravity_field.EarthGravity`,
the tidal corrections (300-s nodes, 6 points: 2e-11 relative): being linear in ΔC̄, ΔS̄, the
coefficient tables of the acceleration sums are interpolated directly.
"""

from __future__ import annotations

import numpy as np

from leopod.astro.ephemeris import Ephemeris
from leopod.constants import GPST_MINUS_TAI_S, TT_MINUS_TAI_S
from leopod.frames.earth_rotation import gcrf_from_itrf_matrices
from leopod.numerics.interpolate import lagrange_equidistant_many
from leopod.time.calendar import J2000_TT
from leopod.time.eop import EarthOrientation, default_earth_orientation

__all__ = ["ArcEnvironment"]

_TT_MINUS_GPST_NS = round((TT_MINUS_TAI_S - GPST_MINUS_TAI_S) * 1e9)
_ROTATION_POINTS = 8          # Lagrange points of the ITRF->GCRF matrix (degree 7)
_EPHEMERIS_POINTS = 8         # ... of the Sun and Moon positions
_SUN_VELOCITY_STEP_S = 60.0   # half step of the central difference giving the Sun's velocity


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
