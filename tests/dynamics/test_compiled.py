"""Tests of the compiled right-hand side (leopod.dynamics.compiled), the density along a
reference orbit (leopod.dynamics.drag.DensityAlongOrbit) and pulses without restart in the
Gauss–Jackson integrator.

Authorities: the per-force implementation (for the plate forces too, whose Python path calls
the same kernels through each force's own adapter) (:meth:`ForceModel.evaluate`, each force's own
kernel and Python glue, tested against its references in test_force_model.py) for the
compiled sums; the density models evaluated directly (NRLMSISE-00 through pymsis, modified
Harris–Priester) for the tabulated density; the restarted integration (a new start-up at
each pulse, the previous method) for the pulses applied through the first sum.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import leopod.dynamics.integrator as integrator
from leopod.constants import GM_EARTH_M3_S2
from leopod.dynamics.compiled import CompiledForceModel
from leopod.dynamics.drag import Drag
from leopod.dynamics.force_config import ForceModelSettings, build_force_model
from leopod.dynamics.forces import ForceModel, PointMassGravity, apriori_parameters
from leopod.dynamics.integrator import apply_pulses, integrate
from leopod.dynamics.model_files import resolve_model_paths
from leopod.dynamics.srp import MacroModel
from leopod.frames.leo_attitude import LeoAttitude
from leopod.frames.rtn import rtn_basis

T_REF = np.datetime64("2023-03-01T00:00:00", "ns")
#: The nominal law turned by a constant yaw, pitch and roll (the plates see every axis).
YAWED = LeoAttitude.of({"attitude_offset": {"yaw_deg": 30.0, "pitch_deg": -5.0,
                                            "roll_deg": 3.0}})
ARC_S = 3 * 3600.0
RADIUS_M = 6878e3


def _circular(t_s: np.ndarray) -> np.ndarray:
    """GCRF positions [m] of a circular two-body orbit (inclination 87°) at t_s [s]."""
    n = np.sqrt(GM_EARTH_M3_S2 / RADIUS_M**3)
    u = n * np.asarray(t_s, dtype=float)
    inc = np.radians(87.0)
    return RADIUS_M * np.column_stack([np.cos(u), np.sin(u) * np.cos(inc),
                                       np.sin(u) * np.sin(inc)])


def _state(t_s: float) -> np.ndarray:
    pos = _circular([t_s])[0]
    vel = (_circular([t_s + 0.5])[0] - _circular([t_s - 0.5])[0])
    return np.concatenate([pos, vel])


#: A box with a Sun-tracking array (both faces) and distinct infrared coefficients.
BOX_WING = MacroModel(
    normal_body=[[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1],
                 [0, 0, 1], [0, 0, -1]],
    area_m2=[1.0, 1.1, 2.0, 2.1, 3.0, 3.1, 9.0, 9.0],
    specular=[0.2, 0.2, 0.3, 0.3, 0.1, 0.1, 0.05, 0.0],
    diffuse=[0.1, 0.1, 0.2, 0.2, 0.3, 0.3, 0.05, 0.1],
    specular_ir=[0.1, 0.1, 0.1, 0.1, 0.0, 0.0, 0.02, 0.0],
    diffuse_ir=[0.2, 0.2, 0.1, 0.1, 0.2, 0.2, 0.1, 0.1],
    drag_coefficient=[2.2, 2.2, 2.3, 2.3, 2.4, 2.4, 2.5, 2.5], mass_kg=500.0,
    panel=[0, 0, 0, 0, 0, 0, 1, -1])


def _forces(density: str, degree: int = 40, plates: bool = False,
            empirical_interval_s: float = 3600.0) -> ForceModelSettings:
    drag = {"area_m2": 1.0, "mass_kg": 500.0, "density": density, "interval_s": 3600.0,
            "plates": plates}
    if density == "msis":
        drag["space_weather"] = "satkit:SW-All.csv"
    return ForceModelSettings.from_config(resolve_model_paths({
        "gravity": {"field": "satkit:ITU_GRACE16.gfc", "max_degree": degree},
        "tides": {"solid": True, "solid_pole": True, "ocean_pole": True},
        "third_body": {"sun": True, "moon": True},
        "relativity": {"lense_thirring": True, "de_sitter": True},
        "drag": drag,
        "srp": {"area_m2": 2.0, "mass_kg": 500.0, "interval_s": 5400.0, "estimate": True,
                "plates": plates},
        "earth_radiation": {"area_m2": 2.0, "mass_kg": 500.0, "interval_s": 5400.0,
                            "estimate": True, "plates": plates},
        "empirical": {"interval_s": empirical_interval_s, "directions": ["R", "T", "N"],
                      "terms": ["const", "cos", "sin"]},
    }), macro_model=BOX_WING if plates else None)


def _model(density: str, degree: int = 40, plates: bool = False,
           empirical_interval_s: float = 3600.0) -> tuple[ForceModel, np.ndarray]:
    model = build_force_model(_forces(density, degree, plates, empirical_interval_s), T_REF,
                              0.0, ARC_S, attitude=YAWED if plates else None)
    model.follow(_circular)
    params = apriori_parameters(model)
    rng = np.random.default_rng(7)
    emp = np.array(["emp" in name for name in model.parameters])
    params[emp] = rng.normal(0.0, 3e-8, emp.sum())
    params[~emp] = rng.uniform(0.8, 1.2, (~emp).sum())
    return model, params


@pytest.mark.parametrize(("density", "plates"), [("msis", False), ("harris_priester", False),
                                                ("harris_priester", True)])
def test_compiled_sum_equals_the_per_force_model(density, plates):
    """Accelerations and all partials of the compiled sum equal ForceModel.evaluate to 1e-12
    (relative to the largest element of each), off the reference orbit by up to 2 km: with
    cannonball forces and with drag, SRP and Earth radiation on a box-wing flown with an
    offset attitude law (issue 18's agreement for the plate forces)."""
    model, params = _model(density, plates=plates)
    compiled = CompiledForceModel.of(model)
    assert compiled is not None
    rng = np.random.default_rng(11)
    acted = np.zeros(model.n_params)
    for t in np.concatenate([[0.0, ARC_S, 3600.0], rng.uniform(0.0, ARC_S, 20)]):
        state = _state(t)
        state[:3] += rng.uniform(-2000.0, 2000.0, 3)
        state[3:] += rng.uniform(-2.0, 2.0, 3)
        expected = model.evaluate(t, state[:3], state[3:], params)
        got = compiled.evaluate(t, state[:3], state[3:], params)
        for name, e, g in zip(("acc", "da_dr", "da_dv", "da_dp"), expected, got):
            scale = np.abs(e).max()
            assert np.abs(g - e).max() <= 1e-12 * scale, (name, t)
        assert np.count_nonzero(got[3]) > 0
        acted += np.abs(got[3]).max(axis=0)
    for prefix in ("drag_scale", "srp_scale", "erp_scale"):     # each force acted (SRP: lit)
        assert max(a for a, n in zip(acted, model.parameters) if n.startswith(prefix)) > 0.0


def test_plate_forces_differ_from_the_cannonball():
    """The plate forces are not the cannonball ones in disguise: the unscaled drag, SRP and
    Earth radiation of the box-wing differ from the cannonball's by more than 10 % (areas
    and coefficients differ), and drag stays along −v_r (no lift, M&G 2000 sec. 3.5.1)."""
    ball, _ = _model("harris_priester")
    box, _ = _model("harris_priester", plates=True)

    def unscaled(model, t, state):
        _, _, _, da_dp = CompiledForceModel.of(model).evaluate(t, state[:3], state[3:],
                                                                apriori_parameters(model))
        return {p: da_dp[:, [i for i, n in enumerate(model.parameters)
                             if n.startswith(p)]].sum(axis=1)
                for p in ("drag_scale", "srp_scale", "erp_scale")}
    lit = (t for t in np.arange(0.0, ARC_S, 300.0)
           if np.any(unscaled(ball, t, _state(t))["srp_scale"]))
    t = next(lit)
    state = _state(t)
    got = {"ball": unscaled(ball, t, state), "box": unscaled(box, t, state)}
    for p in got["ball"]:
        a, b = got["ball"][p], got["box"][p]
        assert np.linalg.norm(a - b) > 0.1 * np.linalg.norm(a), p
    drag = got["box"]["drag_scale"]
    rot = box.forces[0].env.rotation(t)[0]
    vrel = state[3:] - np.cross(7.292115e-5 * rot[:, 2], state[:3])
    assert np.linalg.norm(np.cross(drag, vrel)) < 1e-9 * np.linalg.norm(drag) * np.linalg.norm(
        vrel)
    assert drag @ vrel < 0.0


def test_no_compiled_form_without_kernels_or_reference_orbit():
    """Point-mass gravity (no kernel) and drag without a reference orbit fall back to Python."""
    assert CompiledForceModel.of(ForceModel([PointMassGravity()])) is None
    model = build_force_model(_forces("harris_priester"), T_REF, 0.0, ARC_S)
    assert CompiledForceModel.of(model) is None
    model.follow(_circular)
    assert CompiledForceModel.of(model) is not None
    plated = build_force_model(_forces("harris_priester", plates=True), T_REF, 0.0, ARC_S)
    assert CompiledForceModel.of(plated) is None       # no attitude table yet
    plated.follow(_circular)
    assert CompiledForceModel.of(plated) is not None


def test_plates_need_a_macro_model():
    """plates: true without satellites.<sat>.macro_model is a clear error naming both."""
    settings = _forces("harris_priester", plates=True)
    settings = dataclasses.replace(settings, macro_model=None)
    with pytest.raises(ValueError, match="drag.*macro_model"):
        build_force_model(settings, T_REF, 0.0, ARC_S)


@pytest.fixture
def python_path(monkeypatch):
    """Integrate through the per-force Python path (no compiled form)."""
    monkeypatch.setattr(integrator.CompiledForceModel, "of", classmethod(lambda cls, m: None))


def test_compiled_integration_equals_the_python_path(monkeypatch):
    """Same forces, same Gauss–Jackson formulas (restarts at the breakpoints on both paths):
    same orbit and partials to round-off."""
    model, params = _model("harris_priester", degree=20)
    t_out = np.linspace(0.0, ARC_S, 61)
    monkeypatch.setattr(integrator, "_PULSE_ON_NODE", -1.0)    # every breakpoint restarts
    fast = integrate(model, 0.0, _state(0.0), params, t_out)
    monkeypatch.setattr(integrator.CompiledForceModel, "of", classmethod(lambda cls, m: None))
    slow = integrate(model, 0.0, _state(0.0), params, t_out)
    assert fast.n_evaluations == slow.n_evaluations
    assert np.abs(fast.states[:, :3] - slow.states[:, :3]).max() < 1e-9
    assert np.abs(fast.stm - slow.stm).max() < 1e-9 * np.abs(slow.stm).max()
    assert np.abs(fast.sensitivity - slow.sensitivity).max() < 1e-9 * np.abs(
        slow.sensitivity).max()


def test_pulses_without_restart(monkeypatch):
    """Pulses applied without a start-up agree with restarts at the pulses (measured 1.4e-7 m
    over 3 h with 1e-4 m/s pulses, as without pulses: the difference of the two start-up
    schemes; 2.7e-5 m without the back-value correction), with fewer evaluations; the
    trajectory is right-continuous with the jump M Δv at each pulse, also backwards."""
    model, params = _model("harris_priester", degree=20)
    pulses = np.arange(900.0, ARC_S, 900.0)
    dv = np.random.default_rng(3).normal(0.0, 1e-4, (pulses.size, 3))
    t_out = np.linspace(0.0, ARC_S, 181)
    fast = apply_pulses(model, 0.0, _state(0.0), params, t_out, pulses, dv)
    monkeypatch.setattr(integrator, "_PULSE_ON_NODE", -1.0)    # every pulse restarts
    slow = apply_pulses(model, 0.0, _state(0.0), params, t_out, pulses, dv)
    assert fast.n_evaluations < slow.n_evaluations
    assert np.abs(fast.states[:, :3] - slow.states[:, :3]).max() < 1e-6
    assert np.abs(fast.stm - slow.stm).max() < 1e-8 * np.abs(slow.stm).max()
    monkeypatch.undo()
    eps = 1e-3
    for t0, t_i in ((0.0, pulses[3]), (ARC_S, pulses[-2])):   # forwards and backwards
        traj = apply_pulses(model, t0, fast.at([t0]).states[0], params,
                            [t_i - eps, t_i, t_i + eps], pulses, dv)
        before, at, after = traj.states
        expected = rtn_basis(at[:3], at[3:]) @ dv[np.searchsorted(pulses, t_i)]
        # the smooth change over eps cancels in the second difference (~ da/dt eps² ≈ 1e-8)
        assert np.abs((at[3:] - before[3:]) - (after[3:] - at[3:]) - expected).max() < 1e-7
        # positions continuous: second difference a eps² ≈ 9e-6 m (a position jump from a
        # misplaced pulse would be ~ Δv h ≈ 5e-4 m)
        assert np.abs((at[:3] - before[:3]) - (after[:3] - at[:3])).max() < 2e-5


@pytest.mark.parametrize("t0", [0.0, ARC_S])
def test_breakpoints_without_restart(monkeypatch, t0):
    """An orbit without partials crosses piecewise-constant accelerations without a start-up
    (the node corrected with the forces of the side it is reached from, the back values moved
    by the jump), forwards and backwards, in the simulator's truth case of 10-min stochastic
    accelerations (here 1e-7 m/s²). Against the same integration at 1-s steps with restarts
    at every breakpoint (converged: 2-s steps differ from it by 5e-6 m) the 5-s orbit is as
    close as with restarts at 5 s (measured forwards 3.4e-5 vs 4.4e-5 m, backwards 2.2e-4
    vs 1.9e-4 m: the jumps' own error at 5 s), with ~35 fewer evaluations per breakpoint.
    With partials the arc still restarts (the parameter partials were 3e-6 relative less
    accurate without restarts)."""
    model, params = _model("harris_priester", degree=20, empirical_interval_s=600.0)
    emp = np.array(["emp" in name for name in model.parameters])
    params[emp] = np.random.default_rng(11).normal(0.0, 1e-7, emp.sum())
    t_out = np.linspace(0.0, ARC_S, 361)
    fast = integrate(model, t0, _state(t0), params, t_out, with_partials=False)
    with_partials = integrate(model, t0, _state(t0), params, t_out)
    monkeypatch.setattr(integrator, "_PULSE_ON_NODE", -1.0)    # every breakpoint restarts
    slow = integrate(model, t0, _state(t0), params, t_out, with_partials=False)
    reference = integrate(model, t0, _state(t0), params, t_out, step_s=1.0,
                          with_partials=False)
    error = {name: np.abs(traj.states[:, :3] - reference.states[:, :3]).max()
             for name, traj in (("without restart", fast), ("restarts", slow))}
    print("\n5-s orbit vs 1-s restarts: " + ", ".join(f"{k} {v:.2e} m" for k, v in error.items())
          + f"; {fast.n_evaluations} vs {slow.n_evaluations} evaluations")
    assert error["without restart"] < 1.25 * error["restarts"]
    assert slow.n_evaluations - fast.n_evaluations > 30 * 17      # 17 breakpoints inside
    assert with_partials.n_evaluations == slow.n_evaluations


@pytest.mark.parametrize("density", ["msis", "harris_priester"])
def test_density_along_an_orbit(density):
    """The tabulated density equals the model on the reference orbit (nodes: exactly; between
    the 60-s nodes within 1e-5, measured 2e-6 for NRLMSISE-00) and 100 m off it within 1e-4
    (first order in the deviation; NRLMSISE-00's gradient is vertical only)."""
    model = build_force_model(_forces(density), T_REF, 0.0, ARC_S)
    model.follow(_circular)
    drag = next(f for f in model.forces if isinstance(f, Drag))
    env = drag.env
    t_first, step, _, _ = drag.along_orbit.args()
    rng = np.random.default_rng(5)
    for t, off in [(t_first + 10 * step, 0.0), (1234.5, 0.0), (7000.3, 100.0)]:
        pos = _circular([t])[0] + off * rng.normal(size=3) / np.sqrt(3)
        rot = env.rotation(t)[0].T
        direct, _ = drag.density(env.tt_j2000_ref_s + t, pos, rot, env.sun_m(t)[0])
        tabulated, _ = drag.along_orbit(t, pos)
        tol = 1e-14 if t == t_first + 10 * step else 1e-5 if off == 0 else 1e-4
        assert abs(tabulated / direct - 1.0) < tol, (t, off)
