"""Ocean tides in the geopotential: IERS Conventions (2010), sec. 6.3, model FES2004.

Eq. (6.15) of the Conventions, for each wave f of the model::

    ΔC̄nm − i ΔS̄nm = Σ_f Σ_{+,−} (C±_f,nm ∓ i S±_f,nm) e^{±i θ_f}

i.e. (real form, used here)::

    ΔC̄nm = Σ_f [(C⁺ + C⁻) cos θ_f + (S⁺ + S⁻) sin θ_f]
    ΔS̄nm = Σ_f [(S⁺ − S⁻) cos θ_f − (C⁺ − C⁻) sin θ_f]      (0 for m = 0)

with θ_f = Σ_i n_i β_i the Doodson argument of the wave (multipliers n_i from its Doodson
number, β = (τ, s, h, p, N', p_s) from :func:`leopod.dynamics.solid_tides.doodson_arguments`).
The amplitudes of the IERS file ``fes2004_Cnm-Snm.dat`` (read by :func:`leopod.io.fes.read_fes_cnm`)
already contain the load Love numbers (1 + k'_n) and the Doodson-Warburg phase corrections.

Simplifications, stated:

* only the waves of the file are used (18 waves: Om1, Om2, Sa, Ssa, Mm, Mf, Mtm, Msq, Q1, O1,
  P1, K1, 2N2, N2, M2, S2, K2, M4); the minor waves that the Conventions suggest to add by
  admittance (sec. 6.3.2) are not implemented;
* eq. (6.15) is applied as written, without nodal modulation factors (f, u) of the lunar waves
  (over 18.6 years these change e.g. the O1 amplitude by ±19 %, K1 by ±12 %, M2 by ±4 %);
* the 18.6-year lines Om1/Om2 are taken from the file as they are; the Conventions flag their
  phase (π/2 or −π/2) as under discussion (update of 14 October 2011).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.astro.arguments import doodson_arguments
from leopod.io.fes import read_fes_cnm

__all__ = ["DEFAULT_OCEAN_TIDE_MAX_DEGREE", "OceanTides"]

#: Default truncation degree of the ocean-tide corrections for LEO POD.
DEFAULT_OCEAN_TIDE_MAX_DEGREE = 30


class OceanTides:
    """Ocean-tide corrections to the geopotential from a FES2004 coefficient set.

    Parameters
    ----------
    coefficients : xarray.Dataset
        As returned by :func:`leopod.io.fes.read_fes_cnm`.
    max_degree : int
        Truncation degree N of the corrections (default 30).
    waves : sequence of str, optional
        Darwin names of the waves to use (default: all waves of the data set).

    Raises
    ------
    ValueError
        For a wave not in the data set, or a negative max_degree.
    """

    def __init__(self, coefficients: xr.Dataset,
                 max_degree: int = DEFAULT_OCEAN_TIDE_MAX_DEGREE,
                 waves: Sequence[str] | None = None):
        if max_degree < 0:
            raise ValueError(f"max_degree must be >= 0, not {max_degree}")
        names = list(coefficients.wave.values) if waves is None else list(waves)
        unknown = sorted(set(names) - set(coefficients.wave.values))
        if unknown:
            raise ValueError(f"waves {unknown} are not in the ocean tide model (available: "
                             f"{list(coefficients.wave.values)})")
        n_max = min(int(max_degree), int(coefficients.n.max()))
        ds = coefficients.sel(wave=names, n=slice(0, n_max), m=slice(0, n_max))
        self.max_degree = n_max
        self.waves = tuple(names)
        self.doodson_multipliers = ds.doodson_multipliers.values.astype(float)  # (W, 6)
        cp, sp = ds.C_plus.values, ds.S_plus.values
        cm, sm = ds.C_minus.values, ds.S_minus.values
        zonal = np.arange(n_max + 1)[None, None, :] == 0  # m = 0: no S̄n0
        size = (n_max + 1) ** 2
        # (W, (N+1)²) factors of cos θ_f and sin θ_f in ΔC̄ and ΔS̄ (module docstring)
        self._c_cos = (cp + cm).reshape(len(names), size)
        self._c_sin = (sp + sm).reshape(len(names), size)
        self._s_cos = np.where(zonal, 0.0, sp - sm).reshape(len(names), size)
        self._s_sin = np.where(zonal, 0.0, cm - cp).reshape(len(names), size)

    @classmethod
    def from_file(cls, path: str | Path, max_degree: int = DEFAULT_OCEAN_TIDE_MAX_DEGREE,
                  waves: Sequence[str] | None = None) -> OceanTides:
        """Read ``fes2004_Cnm-Snm.dat`` up to ``max_degree`` (see :class:`OceanTides`)."""
        return cls(read_fes_cnm(path, max_degree=max_degree), max_degree, waves)

    def arguments(self, t_tt_s_j2000, gmst_rad) -> np.ndarray:
        """Doodson arguments θ_f of the waves [rad], shape (n, W)."""
        return doodson_arguments(t_tt_s_j2000, gmst_rad) @ self.doodson_multipliers.T

    def coefficients(self, t_tt_s_j2000, gmst_rad) -> tuple[np.ndarray, np.ndarray]:
        """Corrections ΔC̄nm, ΔS̄nm at the given epochs, IERS Conventions (2010) eq. (6.15).

        Parameters
        ----------
        t_tt_s_j2000 : array_like, shape (n,)
            TT seconds since J2000.0.
        gmst_rad : array_like, shape (n,)
            Greenwich mean sidereal time θ_g [rad].

        Returns
        -------
        dC, dS : numpy.ndarray, shape (n, N+1, N+1)
            ΔC̄nm, ΔS̄nm [1], indexed [epoch, n, m] (0 for m > n).
        """
        theta = self.arguments(t_tt_s_j2000, gmst_rad)
        cos, sin = np.cos(theta), np.sin(theta)
        shape = (theta.shape[0], self.max_degree + 1, self.max_degree + 1)
        dc = (cos @ self._c_cos + sin @ self._c_sin).reshape(shape)
        ds = (cos @ self._s_cos + sin @ self._s_sin).reshape(shape)
        return dc, ds
