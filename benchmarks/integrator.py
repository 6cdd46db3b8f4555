"""Benchmark: a 30-h LEO arc with state, STM and 40 sensitivities (leopod.dynamics.integrator).

Forces: point mass + J2 (with a J2 scale parameter) + piecewise-constant RTN empirical
accelerations in 13 intervals (39 parameters): 40 parameters, outputs every 30 s. Prints, for
the default Gauss–Jackson settings and for the alternatives (PECE, scipy DOP853):

* wall time, force-model evaluations (RHS calls), the time spent in the force model and the
  integrator's own overhead per evaluation;
* the 30-h position error against a run with half the step (and DOP853 against GJ);
* the force-model budget per call for the project's target of 5 s per arc.

With ../shared present it also integrates EGM2008 to degree 120 (the field that sets the
default step; Earth-fixed field rotated at the nominal Earth rate) and compares step sizes.

    .venv/bin/python benchmarks/integrator.py [--repeat N] [--no-field]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numba
import numpy as np

from leopod.constants import GM_EARTH_M3_S2, OMEGA_EARTH_RAD_S, R_EARTH_EQUATOR_M
from leopod.dynamics.forces import ConstantAcceleration, Force, ForceModel, PointMassGravity
from leopod.dynamics.integrator import integrate

HOUR_S = 3600.0
ARC_S = 30 * HOUR_S
TARGET_S = 5.0
J2 = 1.0826e-3                      # ≈ Earth's J2 (EGM2008), for the benchmark force
SHARED = Path(__file__).resolve().parents[2] / "shared"


@numba.njit(cache=True)
def _j2_part(pos):
    """J2 part of the acceleration (complex-capable for complex-step derivatives)."""
    r2 = pos[0] * pos[0] + pos[1] * pos[1] + pos[2] * pos[2]
    k = 1.5 * J2 * R_EARTH_EQUATOR_M**2 / r2
    zz = 5.0 * pos[2] * pos[2] / r2
    f = -GM_EARTH_M3_S2 / (r2 * np.sqrt(r2)) * k
    return np.array([f * pos[0] * (1 - zz), f * pos[1] * (1 - zz), f * pos[2] * (3 - zz)])


@numba.njit(cache=True)
def _j2_acc_grad(pos):
    acc = _j2_part(pos + 0j).real
    grad = np.empty((3, 3))
    for j in range(3):
        p = pos + 0j
        p[j] += 1e-3j
        grad[:, j] = _j2_part(p).imag / 1e-3
    return acc, grad


class J2Scaled(Force):
    """J2 acceleration times a scale parameter ``j2_scale`` (benchmark force)."""

    def __init__(self):
        self.parameters = ["j2_scale"]

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        acc, grad = _j2_acc_grad(pos_m)
        return params[0] * acc, params[0] * grad, np.zeros((3, 3)), acc[:, None]


class RotatingField(Force):
    """Earth-fixed spherical-harmonic field rotated at the nominal Earth rate (no EOP)."""

    def __init__(self, field, gradient: bool):
        self.field, self.gradient = field, gradient
        self.parameters = []

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        c, s = np.cos(OMEGA_EARTH_RAD_S * t_s), np.sin(OMEGA_EARTH_RAD_S * t_s)
        rot = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
        if self.gradient:
            acc, grad = self.field.acceleration_and_gradient(rot @ pos_m)
            grad = rot.T @ grad @ rot
        else:
            acc, grad = self.field.acceleration(rot @ pos_m), np.zeros((3, 3))
        return rot.T @ acc, grad, np.zeros((3, 3)), np.zeros((3, 0))


class TimedForceModel(ForceModel):
    """ForceModel that accumulates the wall time spent in the forces."""

    seconds = 0.0

    def evaluate(self, t_s, pos_m, vel_m_s, params):
        t = time.perf_counter()
        out = super().evaluate(t_s, pos_m, vel_m_s, params)
        self.seconds += time.perf_counter() - t
        return out


def initial_state() -> np.ndarray:
    """Near-circular sun-synchronous-like LEO: a = 6878 km, e ≈ 0.001, i = 97.4°."""
    a, e, inc = 6_878_000.0, 0.001, np.radians(97.4)
    rp = a * (1 - e)
    vp = np.sqrt(GM_EARTH_M3_S2 * (1 + e) / rp)
    return np.array([rp, 0.0, 0.0, 0.0, vp * np.cos(inc), vp * np.sin(inc)])


def run(model: TimedForceModel, params, t_out, repeat: int, **kw):
    best = None
    for _ in range(repeat):
        model.seconds = 0.0
        t = time.perf_counter()
        traj = integrate(model, 0.0, initial_state(), params, t_out, **kw)
        wall = time.perf_counter() - t
        if best is None or wall < best[1]:
            best = (traj, wall, model.seconds)
    return best


def report(label, traj, wall, force_s, ref=None):
    n = traj.n_evaluations
    line = (f"{label:<34s} {wall:6.2f} s  {n:7d} evals  force {force_s:5.2f} s  "
            f"integrator {1e6 * (wall - force_s) / n:5.1f} µs/eval")
    if ref is not None:
        err = np.linalg.norm(traj.states[:, :3] - ref.states[:, :3], axis=1).max()
        line += f"  Δpos {1e3 * err:.4f} mm"
    print(line)


def main(repeat: int, field: bool) -> None:
    t_out = np.arange(0.0, ARC_S + 1, 30.0)
    model = TimedForceModel([PointMassGravity(), J2Scaled(),
                             ConstantAcceleration(np.linspace(0.0, ARC_S, 14))])
    params = np.concatenate([[1.0], np.tile([5e-9, -2e-8, 1e-8], 13)])
    print(f"30-h arc, {t_out.size} outputs (30 s), P = {model.n_params} parameters, "
          f"point mass + J2 + 13 empirical intervals")
    integrate(model, 0.0, initial_state(), params, t_out[:3])          # numba compilation
    tight, *_ = run(model, params, t_out, 1, step_s=2.5)
    default = run(model, params, t_out, repeat)
    report("Gauss-Jackson q=10 PEC 5 s (default)", *default, ref=tight)
    report("Gauss-Jackson q=10 PECE 5 s", *run(model, params, t_out, repeat, pece=True),
           ref=tight)
    report("Gauss-Jackson q=10 PEC 30 s", *run(model, params, t_out, repeat, step_s=30.0),
           ref=tight)
    report("DOP853 rtol 1e-13 (scipy)", *run(model, params, t_out, repeat, method="dop853"),
           ref=tight)
    traj, wall, force_s = default
    overhead = wall - force_s
    print(f"→ default: {traj.n_evaluations} force evaluations per 30-h arc; integrator "
          f"overhead {overhead:.2f} s; budget for a {TARGET_S:.0f}-s arc: "
          f"{1e6 * (TARGET_S - overhead) / traj.n_evaluations:.0f} µs per force-model call "
          f"(acceleration + partials for {model.n_params} parameters)")
    gfc = SHARED / "models/gravity/EGM2008_120.gfc"
    if field and gfc.exists():
        degree_120(gfc, repeat)


def degree_120(gfc: Path, repeat: int) -> None:
    from leopod.dynamics.gravity_field import GravityField
    from leopod.io.icgem import read_icgem

    field = GravityField(read_icgem(gfc), 120)
    t_out = np.arange(0.0, ARC_S + 1, 30.0)
    print("\nEGM2008 degree 120 (rotating frame), state only, acceleration only:")
    model = TimedForceModel([RotatingField(field, gradient=False)])
    ref, *_ = run(model, [], t_out, 1, step_s=2.0, with_partials=False)
    for step in (5.0, 7.5, 10.0, 15.0):
        report(f"Gauss-Jackson PEC {step:g} s", *run(model, [], t_out, 1, step_s=step,
                                                        with_partials=False), ref=ref)
    report("DOP853 rtol 1e-13 (scipy)", *run(model, [], t_out, 1, method="dop853",
                                              with_partials=False), ref=ref)
    print("EGM2008 degree 120 with its gradient, state + STM (default settings):")
    model = TimedForceModel([RotatingField(field, gradient=True)])
    report("Gauss-Jackson q=10 PEC 5 s (default)", *run(model, [], t_out, repeat))


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="best of N runs")
    parser.add_argument("--no-field", action="store_true", help="skip the degree-120 field")
    args = parser.parse_args()
    main(args.repeat, not args.no_field)
