"""Simulated inter-satellite range (leopod.simulate.ranging): analytic truth."""

import numpy as np
import xarray as xr

from leopod.simulate.ranging import simulated_range


def _orbit(t, pos):
    return xr.Dataset({"pos_itrf_m": (("time", "xyz"), pos)}, coords={"time": t})


def test_range_is_the_distance_plus_white_noise():
    t = np.datetime64("2022-07-14", "ns") + np.arange(2000) * np.timedelta64(10, "s")
    rng = np.random.default_rng(0)
    a = rng.normal(scale=7e6, size=(t.size, 3))
    b = a + np.array([300.0, -5000.0, 450.0]) + rng.normal(scale=10.0, size=(t.size, 3))
    exact = simulated_range(_orbit(t, a), _orbit(t[::2], b[::2]), 0.0, seed=1)
    assert np.array_equal(exact.time.values, t[::2])                    # common epochs
    assert np.allclose(exact.range_m.values, np.linalg.norm(b[::2] - a[::2], axis=1),
                       rtol=0, atol=1e-9)
    noisy = simulated_range(_orbit(t, a), _orbit(t, b), 1e-6, seed=1)
    err = noisy.range_m.values - np.linalg.norm(b - a, axis=1)
    assert abs(err.std() - 1e-6) < 0.1e-6 and abs(err.mean()) < 1e-7
