"""Tests of the time-correlation-aware WL sigma (leopod.ambiguity.correlation, issue 19 part 5).

Authorities:
- Bayley & Hammersley (1946): variance of the mean of a correlated series σ² c,
  c = (1/n²) Σ_ij r(t_i − t_j); for AR(1) on a gap-free grid c has the closed form
  (1/n)[1 + 2 Σ_k (1 − k/n) ρ^k];
- Zięba (2010): E[s²] = σ² n (1 − c)/(n − 1), so s² (n − 1) c/(n (1 − c)) is unbiased for
  var(x̄) — checked by Monte Carlo against the analytic variance;
- Satterthwaite (1946): ν = tr(AR)²/tr(ARAR), = n − 1 for white noise;
- Dong & Bock (1989) eq. A-12 (BDS SCB-AR paper eq. 9): with the right sigma a wrong fix
  needs |e| in ∪(i − d*, i + d*), of probability 1 − P0(d*) = α at the acceptance bound, so
  wrong fixes per tested ambiguity are at most α — measured on simulated passes with
  time-correlated noise (leopod.simulate.hmw_noise), where STD/sqrt(n) fails it.
"""

from __future__ import annotations

import numpy as np
import pytest

from leopod.ambiguity.correlation import (
    CorrelationModel,
    fit_correlation,
    mean_sigma,
    semivariogram,
    student_t_factor,
)
from leopod.ambiguity.decision import DONG_BOCK_ALPHA, dong_bock_decision
from leopod.ambiguity.wide_lane import sd_wide_lane
from leopod.simulate.hmw_noise import gauss_markov_series, sd_arc

STEP_S = 30.0


def _ar1_c(n, rho, share):
    k = np.arange(1, n)
    return (1.0 + 2.0 * np.sum((1.0 - k / n) * share * rho**k)) / n


def test_mean_variance_matches_bayley_hammersley_closed_form():
    model = CorrelationModel(white_var=0.02, markov_var=0.03, tau_s=300.0)
    n = 40
    t = np.arange(n) * STEP_S
    x = np.random.default_rng(0).normal(size=n)
    res = mean_sigma(t, x, model)
    c = _ar1_c(n, np.exp(-STEP_S / 300.0), 0.03 / 0.05)
    assert res.n_eff == pytest.approx(1.0 / c, rel=1e-12)
    s2 = np.var(x, ddof=1)
    assert res.sigma == pytest.approx(np.sqrt(s2 * (n - 1) * c / (n * (1 - c))), rel=1e-12)


def test_white_noise_gives_classical_values():
    model = CorrelationModel(white_var=0.04, markov_var=1e-30, tau_s=300.0)
    x = np.random.default_rng(1).normal(size=25)
    res = mean_sigma(np.arange(25) * STEP_S, x, model)
    assert res.n_eff == pytest.approx(25.0)
    assert res.dof == pytest.approx(24.0)                         # Satterthwaite: n − 1
    assert res.sigma == pytest.approx(np.std(x, ddof=1) / 5.0)


def test_zieba_estimator_is_unbiased_by_monte_carlo():
    rng = np.random.default_rng(2)
    white, markov, tau, n = 0.1, 0.2, 300.0, 30
    model = CorrelationModel(white**2, markov**2, tau)
    t = np.arange(n) * STEP_S
    est = [mean_sigma(t, gauss_markov_series(rng, n, white, markov, tau, STEP_S), model).sigma**2
           for _ in range(4000)]
    truth = (white**2 + markov**2) * _ar1_c(n, np.exp(-STEP_S / tau), markov**2 /
                                            (white**2 + markov**2))
    # mean of 4000 estimates: its own sampling error is a few per cent
    assert np.mean(est) == pytest.approx(truth, rel=0.06)
    naive = np.mean([np.var(gauss_markov_series(rng, n, white, markov, tau, STEP_S), ddof=1) / n
                     for _ in range(2000)])
    assert naive < 0.5 * truth                                   # why STD/sqrt(n) fails


def test_semivariogram_fit_recovers_the_process():
    rng = np.random.default_rng(3)
    white, markov, tau = 0.15, 0.25, 300.0
    xs = [gauss_markov_series(rng, int(n), white, markov, tau, STEP_S)
          for n in rng.integers(16, 81, 400)]
    ts = [np.arange(x.size) * STEP_S for x in xs]
    model = fit_correlation(*semivariogram(ts, xs, STEP_S), STEP_S)
    assert model.tau_s == pytest.approx(tau, rel=0.25)
    assert np.sqrt(model.white_var) == pytest.approx(white, rel=0.15)
    assert np.sqrt(model.markov_var) == pytest.approx(markov, rel=0.15)


def test_student_t_factor():
    assert student_t_factor(np.inf, 1e-3) == 1.0
    assert student_t_factor(10.0, 1e-3) == pytest.approx(4.5869 / 3.2905, rel=1e-3)  # t tables


def _false_fix_rates(arcs: int, per_arc: int, seed: int):
    rng = np.random.default_rng(seed)
    counts = np.zeros((3, 3), dtype=np.int64)        # rows: old, new, new + t; (n, fixed, wrong)
    for _ in range(arcs):
        tau = float(rng.choice([60.0, 150.0, 300.0, 600.0]))
        share = rng.uniform(0.2, 0.8)
        level = rng.uniform(0.1, 0.5, per_arc)
        arc = sd_arc(rng, rng.integers(16, 81, per_arc), level * np.sqrt(1 - share),
                     level * np.sqrt(share), tau, STEP_S)
        old = sd_wide_lane(arc.hmw_cyc, arc.pass_id, arc.id_i, arc.id_j, sigma_method="white")
        new = sd_wide_lane(arc.hmw_cyc, arc.pass_id, arc.id_i, arc.id_j,
                           sigma_method="autocorrelation")
        sigmas = (old.sigma_cyc, new.sigma_cyc,
                  new.sigma_cyc * student_t_factor(new.dof, DONG_BOCK_ALPHA))
        for row, sigma in enumerate(sigmas):
            d = dong_bock_decision(new.value_cyc, sigma, alpha=DONG_BOCK_ALPHA)
            wrong = d.fixed & (d.integer != arc.true_cyc)
            counts[row] += [d.fixed.size, d.fixed.sum(), wrong.sum()]
    return counts


def test_dong_bock_alpha_holds_with_the_new_sigma_only():
    """12 000 simulated SD passes (noise model: benchmarks/wl_statistics.py)."""
    counts = _false_fix_rates(arcs=40, per_arc=300, seed=11)
    wrong_per_tested = counts[:, 2] / counts[:, 0]
    assert wrong_per_tested[0] > 3 * DONG_BOCK_ALPHA          # old sigma: α is not what it says
    assert wrong_per_tested[2] <= DONG_BOCK_ALPHA             # the default: new sigma + t
    assert counts[2, 2] / counts[2, 1] <= DONG_BOCK_ALPHA     # also per fixed ambiguity
    assert counts[2, 1] / counts[2, 0] > 0.8                  # and still fixing most


def test_auto_wl_sigma_follows_the_decision():
    # the Dong–Bock α holds only with the sigma of a time-correlated mean (the test above);
    # the rounding bounds of Peng et al. (2021) are bounds on STD/sqrt(n)
    import dataclasses

    from leopod.ambiguity.resolve import ArSettings, wl_sigma_method
    from leopod.workflow.config import section_defaults

    ar = ArSettings.from_config(section_defaults("ambiguity"))
    assert ar.wl_sigma == "auto"
    assert wl_sigma_method(dataclasses.replace(ar, decision="dong_bock")) == "autocorrelation"
    assert wl_sigma_method(dataclasses.replace(ar, decision="rounding")) == "white"
    assert wl_sigma_method(dataclasses.replace(ar, decision="dong_bock",
                                               wl_sigma="white")) == "white"
