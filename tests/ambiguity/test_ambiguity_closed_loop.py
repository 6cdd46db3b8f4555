"""Closed loop of the whole ambiguity-resolution chain on synthetic data.

Authority: the generating model (tests/ambiguity/_ambiguity_scenario.py: integers + receiver
and satellite biases + noise of known statistics) and the simulator's bias products written
to and read back from files (CNES WL records, Bias-SINEX OSBs). Every fixed WL and NL integer
must equal the true one, the pseudo-observations must equal the noise-free single
differences of the float parameters, and with the wrong sign of the CNES WL value the chain
must fail to fix.
"""

from __future__ import annotations

import numpy as np
import pytest
from _ambiguity_scenario import EPOCH, F1, F2, scenario

from leopod.ambiguity import (
    constraint_matrix,
    constraint_rows,
    dong_bock_decision,
    fixed_sd_if_m,
    fixing_rate,
    graph_rank,
    rounding_decision,
    sat_if_phase_bias_osb,
    sat_wl_bias_cnes,
    sat_wl_bias_osb,
    sd_narrow_lane,
    sd_pairs,
    sd_wide_lane,
)
from leopod.ambiguity.decision import NL_MAX_DEV_CYC, WL_MAX_DEV_CYC
from leopod.io.bias_sinex import read_bias_sinex
from leopod.io.bias_sinex_write import write_bias_sinex
from leopod.io.wlbias import read_wl_bias
from leopod.io.wlbias_write import write_wl_bias


@pytest.fixture(scope="module")
def world(tmp_path_factory):
    s = scenario(seed=31, hours=10.0)
    path = tmp_path_factory.mktemp("products")
    write_wl_bias(s.products.wl, path / "wl.txt")
    write_bias_sinex(s.products.osb, path / "osb.bia")
    return s, read_wl_bias(path / "wl.txt"), read_bias_sinex(path / "osb.bia")


def _wide_lane(s, wl_sat):
    amb = s.amb
    pairs = sd_pairs(amb.sv.values, amb.start.values, amb.end.values)
    sd = sd_wide_lane(s.hmw, s.pass_id, pairs.i, pairs.j, wl_sat)
    return pairs, sd, rounding_decision(sd.value_cyc, sd.sigma_cyc, max_dev_cyc=WL_MAX_DEV_CYC)


def test_chain_recovers_true_integers_and_constraints(world):
    s, wl_file, osb_file = world
    amb = s.amb
    epoch = EPOCH + np.timedelta64(5, "h")
    pairs, sd_wl, wl = _wide_lane(s, sat_wl_bias_cnes(wl_file, epoch))
    i, j = pairs.i, pairs.j
    assert i.size > 200
    assert wl.fixed.mean() > 0.95
    np.testing.assert_array_equal(wl.integer[wl.fixed], (s.n_wl[i] - s.n_wl[j])[wl.fixed])
    # the OSB product gives the same SD WL values as the CNES one
    sd_osb = sd_wide_lane(s.hmw, s.pass_id, i, j, sat_wl_bias_osb(osb_file, s.svs, epoch))
    np.testing.assert_allclose(sd_osb.value_cyc, sd_wl.value_cyc, rtol=0, atol=2e-5)

    # narrow lane with the satellite IF phase bias of the OSB file (ordinary clocks)
    sat_bias = sat_if_phase_bias_osb(osb_file, s.svs, epoch).sel(sv=amb.sv.values).values
    fi, fj = i[wl.fixed], j[wl.fixed]
    nl = sd_narrow_lane(amb.value_m.values, amb.covariance_m2.values, fi, fj,
                        wl.integer[wl.fixed], F1, F2, sat_bias_m=sat_bias)
    rule = rounding_decision(nl.value_cyc, nl.sigma_cyc, max_dev_cyc=NL_MAX_DEV_CYC)
    prob = dong_bock_decision(nl.value_cyc, nl.sigma_cyc)
    truth_nl = s.n1[fi] - s.n1[fj]
    for decision in (rule, prob):
        assert decision.fixed.mean() > 0.9
        np.testing.assert_array_equal(decision.integer[decision.fixed],
                                      truth_nl[decision.fixed])

    # fixed SD IF values of an independent set -> pseudo-observations
    ok = rule.fixed
    value = fixed_sd_if_m(wl.integer[wl.fixed][ok], rule.integer[ok], F1, F2,
                          sat_bias_sd_m=(sat_bias[fi] - sat_bias[fj])[ok])
    rows = constraint_rows(fi[ok], fj[ok], value, nl.sigma_cyc[ok])
    np.testing.assert_allclose(rows.value_m, s.b_true[rows.index_i] - s.b_true[rows.index_j],
                               rtol=0, atol=1e-5)   # OSB file: 6 decimals of ns
    a = constraint_matrix(rows, amb.sizes["ambiguity"])
    assert np.linalg.matrix_rank(a) == rows.index_i.size
    # Jiang et al. (2023) fixing rates: independent fixed / all independent
    wl_rate = fixing_rate(i, j, wl.fixed)
    nl_fixed = np.zeros(i.size, dtype=bool)
    nl_fixed[np.nonzero(wl.fixed)[0][ok]] = True
    nl_rate = fixing_rate(i, j, nl_fixed)
    assert 0.95 < wl_rate <= 1.0 and 0.9 < nl_rate <= wl_rate
    assert rows.index_i.size == round(nl_rate * graph_rank(i, j))


def test_wrong_cnes_sign_breaks_wide_lane_fixing(world):
    # the file holds −w^s; using it with the other sign leaves 2 w^s in the SD values
    s, wl_file, _ = world
    wrong = -sat_wl_bias_cnes(wl_file, EPOCH)
    pairs, _, wl = _wide_lane(s, wrong)
    correct = wl.fixed & (wl.integer == s.n_wl[pairs.i] - s.n_wl[pairs.j])
    assert correct.mean() < 0.5


def test_ils_nl_option_fixes_true_integers(world):
    """Integer least squares of the NL set (Teunissen 1995) on the closed loop: every fixed
    NL equals the simulated integer and a maximal independent set is nearly all fixed."""
    from leopod.ambiguity.alternatives import ils_nl_decision
    from leopod.ambiguity.narrow_lane import sd_covariance_m2
    from leopod.gnss.combinations import narrow_lane_wavelength_m

    s, _, osb_file = world
    amb = s.amb
    epoch = EPOCH + np.timedelta64(5, "h")
    pairs, _, wl = _wide_lane(s, sat_wl_bias_osb(osb_file, s.svs, epoch))
    i, j = pairs.i, pairs.j
    sat_bias = sat_if_phase_bias_osb(osb_file, s.svs, epoch).sel(sv=amb.sv.values).values
    nl = sd_narrow_lane(amb.value_m.values, amb.covariance_m2.values, i, j,
                        np.where(wl.fixed, wl.integer, 0), F1, F2, sat_bias_m=sat_bias)
    cov = sd_covariance_m2(amb.covariance_m2.values, i, j) / narrow_lane_wavelength_m(F1, F2) ** 2
    dec = ils_nl_decision(nl.value_cyc, cov, i, j, wl.fixed, min_ratio=3.0,
                          min_success_rate=0.999)
    truth = s.n1[i] - s.n1[j]
    np.testing.assert_array_equal(dec.integer[dec.fixed], truth[dec.fixed])
    assert fixing_rate(i, j, dec.fixed) > 0.9
