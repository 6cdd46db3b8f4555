"""The linearly corrected orbit of leopod.estimation.orbit_correction.

Authority: the re-integration itself: the orbit integrated at the corrected parameters
(initial state, drag/SRP scale factors, empirical accelerations, pseudo-stochastic pulses),
which the corrected orbit must equal to the neglected second-order term (~|Δr|²/r) or, for
small corrections, to the reproducibility of the integration (~1e-6 m: two integrations from
slightly different states differ by their rounding and truncation at that level).
"""

from __future__ import annotations

import numpy as np
import pytest

from leopod.dynamics.force_config import ForceModelSettings, build_force_model
from leopod.dynamics.forces import (
    PseudoStochasticPulses,
    apriori_parameters,
    estimated_parameters,
)
from leopod.dynamics.integrator import apply_pulses
from leopod.dynamics.model_files import resolve_model_paths
from leopod.estimation.float_pod import pulse_epochs
from leopod.estimation.orbit_correction import CorrectedOrbit, epoch_covariance

T_REF = np.datetime64("2023-01-01T00:00:00", "ns")
ARC_S = 6 * 3600.0
CONFIG = {"gravity": {"field": "satkit:ITU_GRACE16.gfc", "max_degree": 20},
          "third_body": True,
          "drag": {"area_m2": 1.0, "mass_kg": 470.0, "interval_s": 10800.0},
          "srp": {"area_m2": 1.0, "mass_kg": 470.0, "estimate": True},
          "empirical": {"interval_s": 10800.0}}
STATE0 = np.array([6131381.0, -3041979.0, 96752.65, 258.5907, 255.4880, -7623.774])
RADIUS_M = float(np.linalg.norm(STATE0[:3]))


@pytest.fixture(scope="module")
def arc():
    """Force model, pulses every 30 min, and the orbit integrated at a-priori parameters
    with random pulses (the linearisation point)."""
    model = build_force_model(ForceModelSettings.from_config(resolve_model_paths(CONFIG)),
                              T_REF, 0.0, ARC_S)
    pulses = PseudoStochasticPulses(pulse_epochs(0.0, ARC_S, 1800.0))
    rng = np.random.default_rng(5)
    dv = rng.normal(0.0, 1e-5, (pulses.epochs_s.size, 3))
    params = apriori_parameters(model)
    base = apply_pulses(model, 0.0, STATE0, params, np.arange(0.0, ARC_S + 1.0, 30.0), pulses,
                        dv)
    return model, pulses, dv, params, base


def _correction(model, pulses, scale: float, rng) -> np.ndarray:
    """Δx: state (m, m/s), estimated force parameters (scale factors 1e-2, accelerations
    1e-9 m/s²) and pulses (1e-5 m/s), all times ``scale``."""
    est = estimated_parameters(model)
    names = [n for n, e in zip(model.parameters, est, strict=True) if e]
    force = [1e-2 if n.startswith(("drag", "srp")) else 1e-9 for n in names]
    return scale * np.concatenate([rng.normal(0.0, 1.0, 3), rng.normal(0.0, 1e-3, 3),
                                   force * rng.normal(0.0, 1.0, len(force)),
                                   rng.normal(0.0, 1e-5, 3 * pulses.epochs_s.size)])


def _compare(arc, dx):
    """Largest position and velocity differences to the re-integration, and |Δr|."""
    model, pulses, dv, params, base = arc
    est = estimated_parameters(model)
    n_e = int(est.sum())
    corrected = CorrectedOrbit(base, pulses, est, dx)
    t = np.arange(0.0, ARC_S, 7.0)                   # off the integration grid
    states, partials = corrected.at(t)
    p = params.copy()
    p[est] += dx[6:6 + n_e]
    again = apply_pulses(model, 0.0, STATE0 + dx[:6], p, t, pulses,
                         dv + dx[6 + n_e:].reshape(dv.shape), with_partials=False)
    shift = np.max(np.linalg.norm(states[:, :3] - base.at(t).states[:, :3], axis=1))
    assert partials.shape == (t.size, 6, dx.size)
    return (np.max(np.abs(states[:, :3] - again.states[:, :3])),
            np.max(np.abs(states[:, 3:] - again.states[:, 3:])), shift)


def test_small_correction_equals_the_reintegration(arc):
    # a correction of every kind of parameter moving the orbit by mm to cm (here 4 mm; the
    # fixed POD's float-to-fixed correction is ~1 cm, the float POD's last one below 1 mm):
    # equal to the reproducibility of the integration (measured 1.7e-7 m, 1.7e-10 m/s;
    # |Δr|²/r is 2e-12 m)
    dx = _correction(arc[0], arc[1], 1e-4, np.random.default_rng(1))
    dpos, dvel, shift = _compare(arc, dx)
    assert 1e-3 < shift < 3e-2
    assert dpos < 2e-6 and dvel < 1e-8


def test_large_correction_error_is_second_order(arc):
    # tens of metres: the neglected term is of the order of |Δr|²/r (measured 0.21 mm and
    # 2.3e-7 m/s for 55 m, |Δr|²/r = 0.45 mm)
    dx = _correction(arc[0], arc[1], 1.0, np.random.default_rng(2))
    dpos, dvel, shift = _compare(arc, dx)
    assert shift > 30.0
    assert dpos < 2.0 * shift**2 / RADIUS_M
    assert dvel < 2.0 * shift**2 / RADIUS_M * 1e-2       # ~ n |Δr|²/r, n ≈ 1e-3 /s


def test_correction_must_match_the_parameters(arc):
    model, pulses, _, _, base = arc
    with pytest.raises(ValueError, match="correction must have shape"):
        CorrectedOrbit(base, pulses, estimated_parameters(model), np.zeros(7))


def test_epoch_covariance_equals_the_full_product(arc):
    # analytic: G_e Q G_eᵀ per epoch, summed over the leading non-zero columns of blocks of
    # epochs, equals the full product (the dropped columns are exact zeros: the pulses after
    # an epoch) up to rounding; a wrong block boundary or column count would not
    model, pulses, _, _, base = arc
    est = estimated_parameters(model)
    k = 6 + int(est.sum()) + 3 * pulses.epochs_s.size
    _, g = CorrectedOrbit(base, pulses, est, np.zeros(k)).at(np.linspace(0.0, ARC_S, 997))
    g = g[:, :3]
    rng = np.random.default_rng(5)
    a = rng.standard_normal((g.shape[2], g.shape[2]))
    q = a @ a.T
    full = np.einsum("mik,kl,mjl->mij", g, q, g)
    assert np.mean(g == 0.0) > 0.2                 # there are trailing zero columns to skip
    np.testing.assert_allclose(epoch_covariance(g, q), full, rtol=1e-12,
                               atol=1e-12 * np.abs(full).max())
