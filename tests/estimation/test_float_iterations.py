"""The float POD's iterations after a small correction linearise without integrating.

Authority: the float POD that integrates the orbit with its variational equations at every
iteration (what it did before issue 18's change; here by setting the threshold
``_INTEGRATE_ABOVE_M`` to 0). Linearising at the last integration plus the corrections since
instead of integrating at the corrected estimates neglects the second-order term of those
corrections, ~|Δr|²/r (Montenbruck & Gill 2000, sec. 7.2; below 4e-10 m for the 5-cm
threshold), and the change of the partials over them (relative ~|Δr|/r): the two solutions
must agree at the reproducibility of an integration (~1e-6 m,
tests/estimation/test_orbit_correction.py) and reject the same observations.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from _simulated_arc import simulated_arc

from leopod.estimation import float_pod
from leopod.estimation.arc import run_arc


@pytest.fixture(scope="module")
def arc(tmp_path_factory):
    return simulated_arc(tmp_path_factory.mktemp("arc"))


def test_small_corrections_need_no_integration(arc, monkeypatch):
    monkeypatch.setattr(float_pod, "_INTEGRATE_ABOVE_M", 0.0)
    every = run_arc(*arc.args, limits=arc.limits)
    linear = arc.float
    assert every.result.converged and linear.result.converged
    # the same iterations (measured: 3); the first correction is metres, so the second
    # iteration integrates again, the third does not
    assert linear.result.iterations == every.result.iterations >= 3
    assert every.result.integrations == every.result.iterations
    assert linear.result.integrations == 2
    diff = {name: float(np.max(np.abs(linear.orbit[name].values - every.orbit[name].values)))
            for name in ("pos_gcrf_m", "vel_gcrf_m_s", "sigma_rtn_m")}
    # measured: position 5.6e-9 m, velocity 4.5e-12 m/s, sigmas 1.5e-11 m
    assert diff["pos_gcrf_m"] < 1e-6 and diff["vel_gcrf_m_s"] < 1e-9
    assert diff["sigma_rtn_m"] < 1e-8
    np.testing.assert_allclose(linear.ambiguities.value_m.values,
                               every.ambiguities.value_m.values, atol=1e-6)
    np.testing.assert_array_equal(linear.result.phase_rejected, every.result.phase_rejected)
    np.testing.assert_array_equal(linear.result.code_rejected, every.result.code_rejected)


def test_the_longer_step_of_a_high_orbit_gives_the_same_orbit(arc):
    """The default campaign integrates at 10 s (``pod.integrator_step_s``, 971 km); the
    authority is the same float POD at the default 5-s step, which resolves a degree-120
    field down to ~400 km (leopod.dynamics.integrator: 0.002 mm against a 2-s run). At
    971 km the field's short periods are weaker by (R/r)^n, so both orbits must agree far
    below a millimetre, for about half the force evaluations."""
    date, data, signals, arc_settings, pod, forces, pco = arc.args
    assert pod.integrator_step_s == 10.0
    five = run_arc(date, data, signals, arc_settings,
                   dataclasses.replace(pod, integrator_step_s=5.0), forces, pco,
                   limits=arc.limits)
    ten = arc.float
    # measured: 5.6e-9 m (1-5 h of the simulated day), 3 182 vs 6 056 evaluations
    diff = np.max(np.abs(ten.orbit.pos_gcrf_m.values - five.orbit.pos_gcrf_m.values))
    assert diff < 1e-6
    np.testing.assert_array_equal(ten.result.phase_rejected, five.result.phase_rejected)
    assert 0.4 < ten.result.force_evaluations / five.result.force_evaluations < 0.6
