"""Benchmark: a 30-h LEO arc with the full force model, STM and ~40 sensitivities.

Force model (leopod.dynamics.force_config): EGM2008 to degree 120 with its full gradient, solid
Earth tides (IERS 2010 steps 1-2), FES2004 ocean tides to degree 30, solid and ocean pole
tides, Sun and Moon (DE421), relativity (IERS 2010 eq. 10.12), drag (cannonball,
NRLMSISE-00 with CelesTrak space weather, one scale factor per 3 h), SRP (cannonball, conical
shadow, one scale factor) and once-per-revolution + constant T/N empirical accelerations per
6 h: 10 + 1 + 30 = 41 parameters. The orbit is Swarm-A from 2023-01-01 00:00 GPST (state of
its ESA SP3 orbit). Outputs every 30 s. Prints:

* the time to build the force model (grids of Earth rotation, Sun/Moon, tides);
* the time to integrate the 30-h arc with the state transition matrix and sensitivities
  (target < 5 s), the number of force evaluations and the cost per evaluation;
* the cost of each force per call (measured on states of the arc) and the integrator's
  own overhead; the same arc with Harris–Priester drag instead of MSIS, and with a
  degree-30 gradient for the partials.

Needs ../shared (EGM2008, FES2004, space weather, Swarm SP3).

    .venv/bin/python benchmarks/dynamics_full.py [--repeat N]
"""

from __future__ import annotations

import argparse
import copy
import time
from pathlib import Path

import numpy as np
from _timing import best_of

from leopod.dynamics.force_config import ForceModelSettings, build_force_model
from leopod.dynamics.forces import apriori_parameters
from leopod.dynamics.integrator import integrate
from leopod.frames.earth_rotation import itrf_to_gcrf
from leopod.io.sp3 import read_sp3

SHARED = Path(__file__).resolve().parents[2] / "shared"
MODELS = SHARED / "models"
SP3 = (SHARED / "data" / "swarm-a_2023-001"
       / "SW_OPER_SP3ACOM_2__20221231T235942_20230101T235942_0201.sp3")
ARC_S = 30 * 3600.0
OUTPUT_STEP_S = 30.0
TARGET_S = 5.0

CONFIG = {
    "gravity": {"field": MODELS / "gravity" / "EGM2008_120.gfc", "max_degree": 120},
    "tides": {"ocean": MODELS / "ocean_tides" / "fes2004_Cnm-Snm.dat"},
    "third_body": True,
    "relativity": True,
    "drag": {"area_m2": 1.0, "mass_kg": 470.0, "density": "msis",
             "space_weather": MODELS / "space_weather" / "SW-All.csv", "interval_s": 10800.0},
    "srp": {"area_m2": 1.0, "mass_kg": 470.0, "estimate": True},
    "empirical": {"interval_s": 21600.0},
}


def initial_state() -> tuple[np.datetime64, np.ndarray]:
    """Swarm-A GCRF state at the first epoch of its SP3 orbit."""
    ds = read_sp3(SP3)
    times = ds.time.values[:1]
    pos, vel = itrf_to_gcrf(times, ds.pos_m.values[:1, 0], ds.vel_m_s.values[:1, 0])
    return times[0], np.concatenate([pos[0], vel[0]])


def run(config: dict, t_ref, state0, repeat: int) -> dict:
    """Build the model, integrate the arc ``repeat`` times; timings [s]."""
    t0 = time.perf_counter()
    model = build_force_model(ForceModelSettings.from_config(config), t_ref, 0.0, ARC_S)
    build_s = time.perf_counter() - t0
    params = apriori_parameters(model)
    t_out = np.arange(0.0, ARC_S + 1.0, OUTPUT_STEP_S)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        traj = integrate(model, 0.0, state0, params, t_out)
        times.append(time.perf_counter() - t0)
    return {"model": model, "params": params, "traj": traj, "build_s": build_s,
            "integrate_s": min(times), "first_s": times[0]}


def _cost_us(fun, traj, params, idx, repeat: int = 3) -> float:
    """Least mean cost per call [µs] of ``fun(t, r, v, p)`` over the states ``idx``."""
    def calls():
        for i in idx:
            fun(traj.t_s[i], traj.states[i, :3], traj.states[i, 3:], params)

    return best_of(calls, repeat) / idx.size * 1e6


def force_costs(model, params, traj, n_calls: int = 3000) -> dict[str, float]:
    """Cost per call [µs] of each force and of the whole model on states of the arc."""
    idx = np.linspace(0, traj.t_s.size - 1, n_calls).astype(int)
    costs = {}
    offset = 0
    for force in model.forces:
        k = len(force.parameters)
        costs[type(force).__name__] = _cost_us(force.evaluate, traj,
                                               params[offset:offset + k], idx)
        offset += k
    costs["ForceModel (total)"] = _cost_us(model.evaluate, traj, params, idx)
    return costs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=2, help="integrations per case (min)")
    args = parser.parse_args()
    if not SP3.exists():
        raise SystemExit(f"needs the real data in {SHARED}")
    t_ref, state0 = initial_state()
    cases = {"full (MSIS drag, degree-120 gradient)": CONFIG}
    hp = copy.deepcopy(CONFIG)
    hp["drag"] = {**CONFIG["drag"], "density": "harris_priester"}
    cases["Harris-Priester drag"] = hp
    low = copy.deepcopy(CONFIG)
    low["gravity"] = {**CONFIG["gravity"], "gradient_degree": 30}
    cases["MSIS drag, degree-30 gradient for the partials"] = low
    print(f"30-h arc of Swarm-A from {t_ref} GPST, outputs every {OUTPUT_STEP_S:.0f} s, "
          f"STM + sensitivities")
    for name, config in cases.items():
        r = run(config, t_ref, state0, args.repeat)
        traj, model = r["traj"], r["model"]
        n_eval = traj.n_evaluations
        verdict = "OK" if r["integrate_s"] < TARGET_S else "ABOVE TARGET"
        print(f"\n== {name}: {model.n_params} parameters")
        print(f"  build force model   {r['build_s']:7.2f} s")
        print(f"  integrate 30 h      {r['integrate_s']:7.2f} s  (first run {r['first_s']:.2f} s; "
              f"target < {TARGET_S:.0f} s: {verdict})")
        print(f"  force evaluations   {n_eval:7d}    {r['integrate_s'] / n_eval * 1e6:6.1f} µs "
              "per evaluation incl. integrator")
        costs = force_costs(model, r["params"], traj)
        for force, us in costs.items():
            print(f"    {force:28s} {us:7.1f} µs/call")
        overhead = r["integrate_s"] / n_eval * 1e6 - costs["ForceModel (total)"]
        print(f"    {'integrator overhead':28s} {overhead:7.1f} µs/evaluation")


if __name__ == "__main__":
    main()
