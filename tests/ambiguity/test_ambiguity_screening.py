"""Rejection of fixes that raise the phase residuals (issue 7).

Authority: analytic construction — a wrong narrow-lane integer shifts the ionosphere-free
ambiguity of a pass by λ_NL ≈ 0.107 m (GPS L1/L2), which the pass's residuals then carry
partly; the test residuals are built with known RMS per pass.
"""

import numpy as np
import xarray as xr

from leopod.ambiguity.screening import degraded_passes, drop_constraints


def _residuals(rms_by_pass: dict[int, float], n: int = 50) -> xr.Dataset:
    rng = np.random.default_rng(1)
    res = np.full((n, len(rms_by_pass)), np.nan)
    pid = np.full(res.shape, -1, dtype=np.int32)
    for col, (p, rms) in enumerate(rms_by_pass.items()):
        z = rng.normal(size=n)
        res[:, col] = rms * z / np.sqrt(np.mean(z**2))
        pid[:, col] = p
    return xr.Dataset({"phase_residual_m": (("time", "sv"), res),
                       "pass_index": (("time", "sv"), pid)})


def test_degraded_pass_found_and_its_constraints_dropped():
    before = _residuals({0: 0.005, 1: 0.006, 2: 0.004, 3: 0.005})
    # pass 2 picked up a wrong fix (RMS x 5); pass 1 changed by 0.3 mm only
    after = _residuals({0: 0.005, 1: 0.0063, 2: 0.02, 3: 0.0051})
    bad = degraded_passes(before, after)
    np.testing.assert_array_equal(bad, [2])
    constraints = (np.array([0, 1, 2]), np.array([1, 2, 3]), np.array([0.1, 0.2, 0.3]),
                   np.full(3, 1e-3))
    kept = drop_constraints(constraints, bad)
    np.testing.assert_array_equal(kept[0], [0])
    np.testing.assert_array_equal(kept[2], [0.1])


def test_quiet_passes_and_short_passes_are_not_judged():
    before = _residuals({0: 0.0005, 1: 0.005})
    after = _residuals({0: 0.0012, 1: 0.005})        # x 2.4 but only +0.7 mm: below the floor
    assert degraded_passes(before, after).size == 0
    short_before, short_after = _residuals({0: 0.005}, n=5), _residuals({0: 0.05}, n=5)
    assert degraded_passes(short_before, short_after).size == 0
    assert degraded_passes(short_before, short_after, min_obs=5).tolist() == [0]
