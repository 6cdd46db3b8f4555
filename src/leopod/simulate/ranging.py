"""A simulated inter-satellite range of a formation pair, as a K-band ranging system gives it.

The instantaneous distance ``|r_B − r_A|`` of the two truth orbits at their common epochs plus
white noise (GRACE's K-band ranging: ~1 µm at 5 s after filtering; Kroes et al. 2005 use it to
validate GPS baselines at the mm level). No light-time, antenna-offset or bias terms: the series
stands for a range that those corrections have already turned into a centre-of-mass distance,
as the ``grc_kb_rng.csv`` file of the LEOGPS example is.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

__all__ = ["simulated_range"]


def simulated_range(truth_a: xr.Dataset, truth_b: xr.Dataset, sigma_m: float,
                    seed: int) -> xr.Dataset:
    """Range series of two truth orbits.

    Parameters
    ----------
    truth_a, truth_b : xarray.Dataset
        Truth orbits (``pos_itrf_m`` (time, xyz) [m]), e.g. the simulator's daily truth files.
    sigma_m : float
        Standard deviation of the white noise [m].
    seed : int
        Seed of the noise.

    Returns
    -------
    xarray.Dataset
        ``range_m`` (time) [m] at the epochs of both orbits, GPS time.
    """
    times = np.intersect1d(truth_a.time.values, truth_b.time.values)
    d = (truth_b.pos_itrf_m.sel(time=times).values - truth_a.pos_itrf_m.sel(time=times).values)
    rng = np.random.default_rng(seed)
    value = np.linalg.norm(d, axis=1) + sigma_m * rng.standard_normal(times.size)
    return xr.Dataset(
        {"range_m": ("time", value, {"units": "m", "long_name": "simulated inter-satellite "
                                     f"range (truth + {sigma_m:g} m white noise)"})},
        coords={"time": times}, attrs={"time_system": "GPS"})
