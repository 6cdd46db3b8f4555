"""Tests of the WL ±1-cycle candidate check (Peng et al. 2021, sec. III-B, after Leick et al.
2015): a WL one cycle off shifts the NL by f2/(f1 − f2) cycles (3.529 for GPS L1/L2, so by
0.529 in its fractional part); the check must pick the WL whose NL is an integer, and only
when exactly one of the two nearest WL integers gives a fixable NL."""

from __future__ import annotations

import numpy as np

from leopod.ambiguity.alternatives import wl_candidate_check
from leopod.ambiguity.decision import rounding_decision
from leopod.signals import frequency_hz

F1, F2 = frequency_hz("G", "L1C"), frequency_hz("G", "L2W")
K = F2 / (F1 - F2)


def _nl_rule(v, s):
    return rounding_decision(v, s, max_dev_cyc=0.12)     # Peng et al. (2021), Table II


def test_candidate_check_picks_the_wl_that_makes_the_nl_integer():
    true_wl = np.array([4, -3, 7])
    true_nl = np.array([12, 5, -8])
    wl_float = np.array([4.55, -3.45, 7.5])      # nearest integer wrong for 0 (and 2: tie)
    wl = rounding_decision(wl_float, np.full(3, 0.05), max_dev_cyc=0.24)
    assert not wl.fixed.any()
    nl_float = true_nl + K * true_wl - K * 0 + np.array([0.02, -0.03, 0.01])  # WL unfixed: 0
    nl = _nl_rule(nl_float, np.full(3, 0.03))
    wl_new, nl_value, nl_new = wl_candidate_check(wl_float, wl, nl_float, nl, np.full(3, 0.03),
                                                  K, _nl_rule)
    assert wl_new.fixed.all() and nl_new.fixed.all()
    np.testing.assert_array_equal(wl_new.integer, true_wl)
    np.testing.assert_array_equal(nl_new.integer, true_nl)
    np.testing.assert_allclose(nl_value, true_nl + [0.02, -0.03, 0.01])


def test_candidate_check_refuses_when_no_or_both_candidates_pass():
    wl_float = np.array([2.5, 2.5])
    wl = rounding_decision(wl_float, np.full(2, 0.05), max_dev_cyc=0.24)
    # NL with WL 0: for candidates 2 and 3 the NL fractional parts are ±0.26: neither passes;
    # with a huge NL sigma-free rule of 0.5 both pass
    nl_float = np.array([0.26 + 2 * K, 0.26 + 2 * K])
    nl = _nl_rule(nl_float, np.full(2, 0.03))
    for rule in (_nl_rule, lambda v, s: rounding_decision(v, s, max_dev_cyc=0.5)):
        wl_new, _, nl_new = wl_candidate_check(wl_float, wl, nl_float, nl, np.full(2, 0.03), K,
                                               rule)
        assert not wl_new.fixed.any() and not nl_new.fixed.any()
