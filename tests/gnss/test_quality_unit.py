"""Sliding-window STD against a direct computation (numpy.std, ddof=1)."""

import numpy as np

from leopod.gnss.quality import sliding_std


def test_sliding_std_matches_direct_computation():
    rng = np.random.default_rng(0)
    t = np.arange(0, 600, 10.0)
    x = rng.normal(0, 0.1, t.size)
    x[[5, 6, 30]] = np.nan
    got = sliding_std(t, x, 120.0, 5)
    for k in range(t.size):
        if np.isnan(x[k]):
            assert np.isnan(got[k])
            continue
        w = x[(np.abs(t - t[k]) <= 60) & np.isfinite(x)]
        want = np.std(w, ddof=1) if w.size >= 5 else np.nan
        np.testing.assert_allclose(got[k], want, rtol=1e-9, equal_nan=True)
