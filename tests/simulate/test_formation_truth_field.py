"""The common random field of a formation's truth (leopod.simulate.truth_forces, Formations).

Authorities: the simulator's own definition x_B = ρ x_A + sqrt(1 − ρ²) x_B,own (so ρ = 1
gives the leader's values exactly and ρ = 0 the satellite's own, bit-identical to a truth
without a formation); sample statistics of normal draws for the differential sigma
σ sqrt(2 (1 − ρ)) and for the independence of unrelated satellites.
"""

import numpy as np

from leopod.simulate.truth_forces import truth_force_config

DAY_S = 86400.0
LEADER, FOLLOWER, OTHER = 101, 202, 303


def test_full_correlation_gives_the_leader_s_accelerations():
    """Two satellites at the same place and time in a fully common field feel the same
    unmodelled accelerations and drag scales."""
    lead = truth_force_config(DAY_S, seed=LEADER)
    foll = truth_force_config(DAY_S, seed=FOLLOWER, common_seed=LEADER, correlation=1.0)
    np.testing.assert_array_equal(foll.stochastic_acc_rtn_m_s2, lead.stochastic_acc_rtn_m_s2)
    np.testing.assert_array_equal(foll.drag_scale, lead.drag_scale)


def test_zero_correlation_is_bit_identical_to_the_own_truth():
    own = truth_force_config(DAY_S, seed=FOLLOWER)
    mixed = truth_force_config(DAY_S, seed=FOLLOWER, common_seed=LEADER, correlation=0.0)
    np.testing.assert_array_equal(mixed.stochastic_acc_rtn_m_s2, own.stochastic_acc_rtn_m_s2)
    np.testing.assert_array_equal(mixed.drag_scale, own.drag_scale)
    assert mixed.values == own.values


def test_differential_part_and_unrelated_satellites():
    span = 60 * DAY_S
    rho = 0.999
    lead = truth_force_config(span, seed=LEADER)
    foll = truth_force_config(span, seed=FOLLOWER, common_seed=LEADER, correlation=rho)
    other = truth_force_config(span, seed=OTHER)
    a, b, c = (f.stochastic_acc_rtn_m_s2 for f in (lead, foll, other))
    n = a.shape[0]
    sigma = a.std(axis=0)
    # each satellite alone keeps σ (relative standard error of a sample std 1/sqrt(2n))
    np.testing.assert_allclose(b.std(axis=0) / sigma, 1.0, atol=5.0 / np.sqrt(2 * n))
    # the differential part: σ sqrt(2 (1 − ρ)) = 4.5 % of σ
    np.testing.assert_allclose((b - a).std(axis=0) / (sigma * np.sqrt(2 * (1 - rho))), 1.0,
                               atol=5.0 / np.sqrt(2 * n))
    # unrelated satellites: sample correlations within 5/sqrt(n) of zero; the formation: ρ
    for k in range(3):
        assert abs(np.corrcoef(a[:, k], c[:, k])[0, 1]) < 5.0 / np.sqrt(n)
        assert np.corrcoef(a[:, k], b[:, k])[0, 1] > 0.998
    # drag-scale noise: the same mix (the periodic part is common anyway)
    d = foll.drag_scale - lead.drag_scale
    assert d.std() < 0.05 * np.sqrt(2 * (1 - rho)) * (1 + 5.0 / np.sqrt(2 * d.size))
