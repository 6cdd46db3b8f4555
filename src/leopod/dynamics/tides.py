"""Tidal corrections to the geopotential, IERS Conventions (2010) chapter 6.

The corrections ΔC̄nm, ΔS̄nm (fully normalised) are added to the static field's coefficients:

* solid Earth tides, steps 1-2 and the permanent tide (sec. 6.2):
  :mod:`leopod.dynamics.solid_tides`;
* ocean tides, FES2004 (sec. 6.3): :mod:`leopod.dynamics.ocean_tides`;
* solid Earth and ocean pole tides (sec. 6.4, 6.5): :mod:`leopod.dynamics.pole_tides`.

:class:`TideModel` sums them for many epochs at once. Its inputs are the epochs (TT seconds
since J2000.0), GMST, the Earth-fixed (ITRF) positions of the Sun and the Moon and the pole
coordinates; the caller (the force model) computes these from the ephemeris and the EOP. The
corrections change slowly (the fastest terms are semi-diurnal), so an integrator can evaluate
them on a grid (e.g. every 5-10 min) and interpolate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from leopod.astro.arguments import doodson_arguments, fundamental_arguments
from leopod.constants import GM_EARTH_M3_S2, R_EARTH_EQUATOR_M
from leopod.dynamics.ocean_tides import DEFAULT_OCEAN_TIDE_MAX_DEGREE, OceanTides
from leopod.dynamics.pole_tides import (
    ocean_pole_tide,
    secular_pole_rad,
    solid_pole_tide,
    wobble_rad,
)
from leopod.dynamics.solid_tides import (
    SOLID_TIDE_MAX_DEGREE,
    TIDE_SYSTEMS,
    permanent_tide_c20,
    solid_earth_tides,
    solid_tide_step1,
    solid_tide_step2,
)

__all__ = [
    "DEFAULT_OCEAN_TIDE_MAX_DEGREE",
    "SOLID_TIDE_MAX_DEGREE",
    "TIDE_SYSTEMS",
    "OceanTides",
    "TideModel",
    "doodson_arguments",
    "fundamental_arguments",
    "ocean_pole_tide",
    "permanent_tide_c20",
    "secular_pole_rad",
    "solid_earth_tides",
    "solid_pole_tide",
    "solid_tide_step1",
    "solid_tide_step2",
    "wobble_rad",
]


@dataclass(frozen=True)
class TideModel:
    """Which tidal corrections to apply, for a static field of a given tide system.

    Parameters
    ----------
    tide_system : {"tide_free", "zero_tide"}
        Tide system of the static field (ICGEM header); "zero_tide" removes the permanent
        tide from the solid-tide ΔC̄20 (IERS 2010 eq. 6.13).
    ocean : OceanTides or None
        Ocean-tide model (None: no ocean tides).
    solid : bool
        Solid Earth tides, steps 1 and 2.
    solid_pole, ocean_pole : bool
        Solid Earth pole tide (eq. 6.22) and ocean pole tide (eq. 6.24, degree 2).
    gm_earth_m3_s2, radius_m : float
        GM_E [m³/s²] and R_e [m] of the static field (used in solid-tide step 1).
    """

    tide_system: str
    ocean: OceanTides | None = None
    solid: bool = True
    solid_pole: bool = True
    ocean_pole: bool = True
    gm_earth_m3_s2: float = GM_EARTH_M3_S2
    radius_m: float = R_EARTH_EQUATOR_M

    def __post_init__(self):
        if self.tide_system not in TIDE_SYSTEMS:
            raise ValueError(f"tide system '{self.tide_system}' is not supported; expected "
                             f"one of {TIDE_SYSTEMS}")

    @property
    def max_degree(self) -> int:
        """Highest degree of the corrections (4 for solid tides, N of the ocean model)."""
        degrees = [2]
        if self.solid:
            degrees.append(SOLID_TIDE_MAX_DEGREE)
        if self.ocean is not None:
            degrees.append(self.ocean.max_degree)
        return max(degrees)

    def coefficients(self, t_tt_s_j2000, gmst_rad, sun_itrf_m, moon_itrf_m, xp_rad,
                     yp_rad) -> tuple[np.ndarray, np.ndarray]:
        """Sum of the selected corrections at n epochs.

        Parameters
        ----------
        t_tt_s_j2000 : array_like, shape (n,)
            TT seconds since J2000.0.
        gmst_rad : array_like, shape (n,)
            Greenwich mean sidereal time [rad].
        sun_itrf_m, moon_itrf_m : array_like, shape (n, 3)
            Earth-fixed geocentric positions of the Sun and the Moon [m].
        xp_rad, yp_rad : array_like, shape (n,)
            Pole coordinates [rad].

        Returns
        -------
        dC, dS : numpy.ndarray, shape (n, N+1, N+1)
            ΔC̄nm, ΔS̄nm [1] with N = :attr:`max_degree`, indexed [epoch, n, m].
        """
        t = np.atleast_1d(np.asarray(t_tt_s_j2000, dtype=float))
        size = self.max_degree + 1
        dc, ds = np.zeros((t.size, size, size)), np.zeros((t.size, size, size))
        if self.solid:
            sc, ss = solid_earth_tides(t, gmst_rad, sun_itrf_m, moon_itrf_m,
                                       tide_system=self.tide_system,
                                       gm_earth_m3_s2=self.gm_earth_m3_s2,
                                       radius_m=self.radius_m)
            dc[:, :SOLID_TIDE_MAX_DEGREE + 1, :SOLID_TIDE_MAX_DEGREE + 1] += sc
            ds[:, :SOLID_TIDE_MAX_DEGREE + 1, :SOLID_TIDE_MAX_DEGREE + 1] += ss
        if self.ocean is not None:
            oc, os_ = self.ocean.coefficients(t, gmst_rad)
            n_ocean = self.ocean.max_degree + 1
            dc[:, :n_ocean, :n_ocean] += oc
            ds[:, :n_ocean, :n_ocean] += os_
        for enabled, model in ((self.solid_pole, solid_pole_tide),
                               (self.ocean_pole, ocean_pole_tide)):
            if enabled:
                c21, s21 = model(xp_rad, yp_rad, t)
                dc[:, 2, 1] += c21
                ds[:, 2, 1] += s21
        return dc, ds
