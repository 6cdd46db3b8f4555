"""Tests of leopod.ambiguity.pairs.

Authorities: brute force (double loop over all pairs with the stated conditions) and the
8-minute rule of Peng et al. (2021) (sec. IV-B) at its boundary.
"""

from __future__ import annotations

import numpy as np
import pytest

from leopod.ambiguity.pairs import MIN_COMMON_S, sd_pairs

T0 = np.datetime64("2021-01-01T00:00", "ns")


def _s(seconds):
    return T0 + np.asarray(np.round(np.asarray(seconds) * 1e9), dtype="timedelta64[ns]")


def test_pairs_match_brute_force():
    rng = np.random.default_rng(5)
    n = 60
    sv = rng.choice(["G01", "G02", "G03", "G07", "C20", "C21"], n)
    start_s = rng.uniform(0, 20_000, n)
    end_s = start_s + rng.uniform(0, 3_000, n)
    result = sd_pairs(sv, _s(start_s), _s(end_s))
    expected = []
    for a in range(n):               # brute force: every pair, every condition spelled out
        for b in range(a + 1, n):
            common = min(end_s[a], end_s[b]) - max(start_s[a], start_s[b])
            if sv[a] != sv[b] and sv[a][0] == sv[b][0] and common >= MIN_COMMON_S - 1e-6:
                expected.append((a, b))
    assert list(zip(result.i.tolist(), result.j.tolist())) == expected
    assert len(expected) > 20
    np.testing.assert_array_equal(result.common_start,
                                  np.maximum(_s(start_s)[result.i], _s(start_s)[result.j]))
    np.testing.assert_array_equal(result.common_end,
                                  np.minimum(_s(end_s)[result.i], _s(end_s)[result.j]))


def test_eight_minute_boundary_and_exclusions():
    # Peng et al. (2021): common time of fewer than 8 minutes is ignored; 480 s exactly is kept
    sv = ["G01", "G02", "G03", "G01", "C19"]
    start = _s([0.0, 600.0, 600.1, 700.0, 0.0])
    end = _s([1080.0, 2000.0, 2000.0, 2000.0, 2000.0])
    p = sd_pairs(sv, start, end)
    pairs = set(zip(p.i.tolist(), p.j.tolist()))
    assert (0, 1) in pairs            # common 480.0 s
    assert (0, 2) not in pairs        # common 479.9 s
    assert (1, 3) in pairs and (2, 3) in pairs
    assert (0, 3) not in pairs        # same satellite
    assert not any(4 in pair for pair in pairs)   # BDS with GPS: no pair
    assert sd_pairs(sv, start, end, min_common_s=0.0).i.size > p.i.size


def test_invalid_input():
    with pytest.raises(ValueError, match="end before"):
        sd_pairs(["G01", "G02"], _s([0.0, 0.0]), _s([10.0, -1.0]))
    with pytest.raises(ValueError, match="equal length"):
        sd_pairs(["G01"], _s([0.0, 0.0]), _s([10.0, 1.0]))
