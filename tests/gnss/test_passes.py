"""Cycle-slip detection on synthetic LEO-like tracking with known slips (analytic truth).

The slip pairs are chosen to exercise each test: (1, 0) and (0, 1) change both MW and GF;
(1, 1) leaves the wide lane unchanged (MW blind, GF sees λ1 − λ2 = −5.4 cm); (9, 7) changes
the wide lane by 2 cycles but GF by only 3.3 mm (GF blind, MW sees it).
"""

import numpy as np
import pytest

from leopod import signals
from leopod.constants import C_LIGHT_M_S
from leopod.gnss.passes import (
    FLAG_GAP,
    FLAG_GF,
    FLAG_LLI,
    FLAG_MW,
    FLAG_NEW,
    FLAG_OUTLIER,
    detect_passes,
)

F1, F2 = signals.frequency_hz("G", "1"), signals.frequency_hz("G", "2")
LAM1, LAM2 = C_LIGHT_M_S / F1, C_LIGHT_M_S / F2


def _track(n=360, dt=10.0, seed=3, slips=(), gap=None, outlier=None):
    rng = np.random.default_rng(seed)
    t = np.arange(n) * dt
    rho = 2.3e7 + 2000.0 * t - 0.8 * t**2 / 2
    iono = 5.0 + 2.0 * np.sin(t / 900.0)                 # smooth LEO-like ionosphere [m]
    g = (F1 / F2) ** 2
    n1 = np.full(n, 1000.0)
    n2 = np.full(n, 800.0)
    for k, d1, d2 in slips:
        n1[k:] += d1
        n2[k:] += d2
    l1 = rho - iono + LAM1 * n1 + rng.normal(0, 0.002, n)
    l2 = rho - g * iono + LAM2 * n2 + rng.normal(0, 0.002, n)
    p1 = rho + iono + rng.normal(0, 0.10, n)
    p2 = rho + g * iono + rng.normal(0, 0.10, n)
    if outlier is not None:
        p1[outlier] += 8.0
    cols = [x[:, None] for x in (l1, l2, p1, p2)]
    if gap is not None:
        for c in cols:
            c[gap[0]:gap[1]] = np.nan
    zeros = np.zeros((n, 1), dtype=int)
    return t, cols, zeros


@pytest.mark.parametrize("d1,d2,expected", [(1, 0, FLAG_MW | FLAG_GF), (0, 1, FLAG_MW | FLAG_GF),
                                            (1, 1, FLAG_GF), (9, 7, FLAG_MW)])
def test_each_slip_found_by_the_right_test(d1, d2, expected):
    t, (l1, l2, p1, p2), lli = _track(slips=[(200, d1, d2)])
    res = detect_passes(t, l1, l2, p1, p2, lli, lli, F1, F2)
    assert res.n_passes == 2
    assert res.flags[200, 0] & (FLAG_MW | FLAG_GF) == expected
    assert (res.pass_id[:200, 0] == 0).all() and (res.pass_id[200:, 0] == 1).all()
    assert res.n_slips == 1


def test_no_false_slips_on_clean_data():
    t, (l1, l2, p1, p2), lli = _track(n=1000, seed=11)
    res = detect_passes(t, l1, l2, p1, p2, lli, lli, F1, F2)
    assert res.n_passes == 1 and res.n_slips == 0
    assert res.flags[0, 0] == FLAG_NEW


def test_gap_lli_and_outlier():
    t, (l1, l2, p1, p2), lli = _track(gap=(100, 110), outlier=250)
    lli1 = lli.copy()
    lli1[300, 0] = 1
    res = detect_passes(t, l1, l2, p1, p2, lli1, lli, F1, F2, max_gap_s=60)
    assert res.flags[110, 0] & FLAG_GAP
    assert res.flags[300, 0] & FLAG_LLI
    assert res.flags[250, 0] == FLAG_OUTLIER and res.pass_id[250, 0] == -1
    assert res.n_passes == 3 and res.n_slips == 1   # the gap is not a slip, the LLI is
