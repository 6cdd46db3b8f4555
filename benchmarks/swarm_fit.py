"""Dynamic orbit fit to the Swarm-A reference orbit of 2023-01-01, with and without each force.

Data: ESA's reduced-dynamic Swarm-A orbit ``SW_OPER_SP3ACOM_2__20221231T235942_20230101T235942_
0201.sp3`` (SP3-d, GPS time, frame IGS20, positions and velocities every 10 s, 8640 epochs
from 2023-01-01 00:00:00 GPST). Fit (leopod.dynamics.orbit_fit.fit_orbit): initial state, one
drag scale factor per 3 h and once-per-revolution + constant along-track and cross-track
empirical accelerations per interval (3 h, the specification; also 90 min, about one
revolution, where smaller model errors become visible), observations the SP3 positions
(ITRF -> GCRF with IAU 2006/2000A and IERS C04 EOP), sigma 1 cm.

Force model: EGM2008 to degree 120 (tide-free), solid Earth tides (IERS 2010 steps 1-2),
FES2004 ocean tides to degree 30, solid and ocean pole tides, Sun and Moon (DE421),
relativity (IERS 2010 eq. 10.12), drag (cannonball C_D = 2.3, A = 1 m², m = 470 kg,
NRLMSISE-00 with CelesTrak F10.7/ap), SRP (cannonball C_R = 1.3, conical shadow). Each row of
the table switches one model off (or replaces it): "effect" is the 3D RMS change of the
all-forces orbit that this causes (same initial state and parameters, no refit: the size of
the force's signal), then the model is fitted again: the RMS of the residuals (observed −
fitted) in R, T, N and 3D shows what the empirical parameters cannot absorb.

    .venv/bin/python benchmarks/swarm_fit.py [--hours 24] [--sampling-s 10]
        [--intervals-s 10800 5400] [--jobs 2]
"""

from __future__ import annotations

import argparse
import copy
import logging
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from leopod.dynamics.force_config import ForceModelSettings, build_force_model
from leopod.dynamics.forces import apriori_parameters
from leopod.dynamics.integrator import integrate
from leopod.dynamics.orbit_fit import fit_orbit
from leopod.io.sp3 import read_sp3

SHARED = Path(__file__).resolve().parents[2] / "shared"
MODELS = SHARED / "models"
SP3 = (SHARED / "data" / "swarm-a_2023-001"
       / "SW_OPER_SP3ACOM_2__20221231T235942_20230101T235942_0201.sp3")

CONFIG = {
    "gravity": {"field": MODELS / "gravity" / "EGM2008_120.gfc", "max_degree": 120},
    "tides": {"ocean": MODELS / "ocean_tides" / "fes2004_Cnm-Snm.dat", "solid": True,
              "solid_pole": True, "ocean_pole": True},
    "third_body": {"sun": True, "moon": True},
    "relativity": {"lense_thirring": True, "de_sitter": True},
    "drag": {"area_m2": 1.0, "mass_kg": 470.0, "drag_coefficient": 2.3, "density": "msis",
             "space_weather": MODELS / "space_weather" / "SW-All.csv", "interval_s": 10800.0},
    "srp": {"area_m2": 1.0, "mass_kg": 470.0, "reflectivity_coefficient": 1.3},
    "empirical": {"interval_s": 10800.0, "directions": ["T", "N"],
                  "terms": ["const", "cos", "sin"]},
}

#: Table rows: label and changes to CONFIG ("section" = None switches a force off,
#: "section.key" sets one setting).
ROWS = [
    ("all forces", {}),
    ("without solid Earth tides", {"tides.solid": False}),
    ("without ocean tides (FES2004)", {"tides.ocean": None}),
    ("without pole tides (solid + ocean)", {"tides.solid_pole": False,
                                            "tides.ocean_pole": False}),
    ("without any tides", {"tides": None}),
    ("without Sun and Moon", {"third_body": None}),
    ("without relativity", {"relativity": None}),
    ("without drag", {"drag": None}),
    ("drag: Harris-Priester instead of MSIS", {"drag.density": "harris_priester"}),
    ("without SRP", {"srp": None}),
    ("without empirical accelerations", {"empirical": None}),
    ("gravity field to degree 90 (not 120)", {"gravity.max_degree": 90}),
    ("gravity field to degree 60 (not 120)", {"gravity.max_degree": 60}),
]


def variant(changes: dict, interval_s: float) -> dict:
    """CONFIG with the empirical interval and the changes of one row applied."""
    config = copy.deepcopy(CONFIG)
    config["empirical"]["interval_s"] = interval_s
    for key, value in changes.items():
        section, _, setting = key.partition(".")
        if setting:
            config[section][setting] = value
        else:
            config[section] = value
    return config


def load(hours: float, sampling_s: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """SP3 epochs (GPS), ITRF positions [m] and velocities [m/s] of the arc."""
    ds = read_sp3(SP3)
    step = round(sampling_s / ds.attrs["interval_s"])
    n = round(hours * 3600.0 / ds.attrs["interval_s"])
    sel = slice(0, n, step)
    return ds.time.values[sel], ds.pos_m.values[sel, 0], ds.vel_m_s.values[sel, 0]


def orbit_effect(config: dict, reference: dict) -> float:
    """3D RMS [m] of the change of the all-forces orbit when integrated with ``config``
    (same initial state, same values of the parameters both models have; no refit)."""
    t_s = reference["t_s"]
    model = build_force_model(ForceModelSettings.from_config(config), reference["t_ref"],
                              t_s[0], t_s[-1])
    params = apriori_parameters(model)
    for i, name in enumerate(model.parameters):
        params[i] = reference["params"].get(name, params[i])
    traj = integrate(model, t_s[0], reference["state0"], params, t_s, with_partials=False)
    diff = traj.states[:, :3] - reference["pos_gcrf"]
    return float(np.sqrt(np.mean(np.sum(diff**2, axis=1))))


def fit_row(label: str, config: dict, data: tuple, reference: dict | None = None) -> dict:
    """Fit one configuration: RMS [m], iterations, wall time, drag scales, and (with a
    reference solution) the size of the configuration's change on the orbit before refit."""
    times, pos, vel = data
    t0 = time.perf_counter()
    result = fit_orbit(times, pos, ForceModelSettings.from_config(config), vel_m_s=vel)
    row = {"label": label, "rms": result.rms_rtn_m, "rms_3d": result.rms_3d_m,
           "iterations": result.iterations, "converged": result.converged,
           "time_s": time.perf_counter() - t0, "n_obs": result.t_s.size, "sigma0": result.sigma0,
           "drag": [(name, *result.estimate(name)) for name in result.parameter_names
                    if name.startswith("drag_scale")]}
    if reference is None:
        row["reference"] = {"t_ref": result.t_ref, "t_s": result.t_s,
                            "state0": result.state0_gcrf,
                            "params": dict(zip(result.force_model.parameters,
                                               result.force_parameters)),
                            "pos_gcrf": result.trajectory.states[:, :3]}
    else:
        row["effect_3d"] = orbit_effect(config, reference)
    return row


def print_table(rows: list[dict], interval_s: float, hours: float, sampling_s: float) -> None:
    base = rows[0]["rms_3d"]
    print(f"\nSwarm-A 2023-01-01, {hours:g} h, positions every {sampling_s:g} s "
          f"({rows[0]['n_obs']} epochs); drag scale per 3 h, empirical T/N const+cos+sin per "
          f"{interval_s / 60:g} min")
    print("effect: 3D RMS change of the all-forces orbit by the change of the row (no refit);"
          " R T N 3D: RMS of the fit residuals after refitting with it")
    print(f"{'configuration':40s} {'effect':>8s} {'R [cm]':>7s} {'T [cm]':>7s} {'N [cm]':>7s} "
          f"{'3D [cm]':>8s} {'Δ3D [cm]':>9s} {'iter':>5s} {'time [s]':>9s}")
    for r in rows:
        r_cm = 100 * r["rms"]
        delta = "" if r is rows[0] else f"{100 * (r['rms_3d'] - base):+9.2f}"
        effect = f"{100 * r['effect_3d']:8.2f}" if "effect_3d" in r else ""
        flag = "" if r["converged"] else "  (not converged)"
        print(f"{r['label']:40s} {effect:>8s} {r_cm[0]:7.2f} {r_cm[1]:7.2f} {r_cm[2]:7.2f} "
              f"{100 * r['rms_3d']:8.2f} {delta:>9s} {r['iterations']:5d} "
              f"{r['time_s']:9.1f}{flag}")
    drag = ", ".join(f"{v:.2f}±{s:.2f}" for _, v, s in rows[0]["drag"])
    print(f"all forces: drag scale factors {drag}; sigma0 {rows[0]['sigma0']:.2f} "
          f"(sigma 1 cm)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hours", type=float, default=24.0, help="arc length [h]")
    parser.add_argument("--sampling-s", type=float, default=10.0, help="observation spacing")
    parser.add_argument("--intervals-s", type=float, nargs="+", default=[10800.0, 5400.0],
                        help="empirical-acceleration intervals [s], one table each")
    parser.add_argument("--jobs", type=int, default=1, help="parallel fits (processes)")
    args = parser.parse_args()
    if not SP3.exists():
        raise SystemExit(f"needs the real data in {SHARED}")
    logging.basicConfig(level=logging.WARNING)
    start = time.perf_counter()
    data = load(args.hours, args.sampling_s)
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        for interval_s in args.intervals_s:
            (label, changes), *others = ROWS
            first = fit_row(label, variant(changes, interval_s), data)
            futures = [pool.submit(fit_row, label, variant(changes, interval_s), data,
                                   first["reference"]) for label, changes in others]
            print_table([first] + [f.result() for f in futures], interval_s, args.hours,
                        args.sampling_s)
    print(f"\ntotal wall time {time.perf_counter() - start:.0f} s ({args.jobs} process(es))")


if __name__ == "__main__":
    main()
