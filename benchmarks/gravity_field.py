"""Benchmark: spherical-harmonic gravity acceleration and gradient (leopod.dynamics.gravity_field).

Evaluates EGM2008 (from ../shared/models/gravity; synthetic coefficients of the same degree
when ../shared is absent) on a 30-h LEO track sampled at 10 s (10 800 Earth-fixed positions,
500 km, polar) and prints the wall time of: building the field, the batch acceleration, the
batch acceleration + gradient, and one position per call (the use inside an ODE right-hand
side), through the Python methods and through the jitted kernel called from jitted code.

    .venv/bin/python benchmarks/gravity_field.py [--degree N] [--repeat R]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numba
import numpy as np
import xarray as xr
from _timing import best_of

from leopod.dynamics.gravity_field import GravityField
from leopod.dynamics.spherical_harmonics import acceleration_sums, field_sums
from leopod.io.icgem import read_icgem

EGM2008 = Path(__file__).resolve().parents[2] / "shared/models/gravity/EGM2008_120.gfc"
N_EPOCHS = 10_800   # 30 h at 10 s
R_ORBIT_M = 6_878_136.3
INCLINATION_RAD = np.radians(89.0)
MEAN_MOTION_RAD_S = np.sqrt(3.986004415e14 / R_ORBIT_M ** 3)


def _model(degree: int) -> tuple[str, xr.Dataset]:
    if EGM2008.exists() and degree <= 120:
        return "EGM2008 (real)", read_icgem(EGM2008, max_degree=degree)
    rng = np.random.default_rng(0)
    n = np.arange(degree + 1)[:, None]
    m = np.arange(degree + 1)[None, :]
    sigma = 1e-5 / np.maximum(n, 1) ** 2
    c = np.where(m <= n, rng.normal(size=(degree + 1, degree + 1)) * sigma, 0.0)
    s = np.where((m <= n) & (m > 0), rng.normal(size=(degree + 1, degree + 1)) * sigma, 0.0)
    c[0, 0] = 1.0
    ds = xr.Dataset({"C": (("n", "m"), c), "S": (("n", "m"), s)},
                    attrs={"gm_m3_s2": 3.986004415e14, "radius_m": 6378136.3,
                           "max_degree": degree, "modelname": "synthetic"})
    return "synthetic (../shared absent or degree > 120)", ds


def _track() -> np.ndarray:
    """Positions (N_EPOCHS, 3) of a circular polar orbit in a frame rotating with the Earth."""
    t = np.arange(N_EPOCHS) * 10.0
    u = MEAN_MOTION_RAD_S * t
    lon = -7.292115e-5 * t
    x, y = np.cos(u), np.sin(u) * np.cos(INCLINATION_RAD)
    z = np.sin(u) * np.sin(INCLINATION_RAD)
    return R_ORBIT_M * np.stack([x * np.cos(lon) - y * np.sin(lon),
                                 x * np.sin(lon) + y * np.cos(lon), z], axis=1)


@numba.njit
def _jitted_loop(kernel, pos_m, args, out):
    for i in range(pos_m.shape[0]):
        kernel(pos_m[i], *args, out)



def main(degree: int, repeat: int) -> None:
    label, ds = _model(degree)
    pos = _track()
    start = time.perf_counter()
    field = GravityField(ds, degree)
    build_s = time.perf_counter() - start
    start = time.perf_counter()
    field.acceleration_and_gradient(pos[:1])
    field.acceleration(pos[:1])
    first_s = time.perf_counter() - start
    acc_s = best_of(lambda: field.acceleration(pos), repeat)
    grad_s = best_of(lambda: field.acceleration_and_gradient(pos), repeat)
    n_single = 2000
    one_acc_s = best_of(lambda: [field.acceleration(p) for p in pos[:n_single]], repeat)
    one_grad_s = best_of(lambda: [field.acceleration_and_gradient(p) for p in pos[:n_single]],
                       repeat)
    kernel_times = {}
    for kind, kernel, size in (("acceleration", acceleration_sums, 3),
                               ("gradient", field_sums, 9)):
        args, out = field.kernel_args(kind), np.empty(size)
        _jitted_loop(kernel, pos[:2], args, out)
        kernel_times[kind] = best_of(
            lambda kernel=kernel, args=args, out=out: _jitted_loop(kernel, pos, args, out),
            repeat)

    print(f"model: {label}, degree/order {degree}, {N_EPOCHS} positions, numba "
          f"{numba.__version__}, best of {repeat}")
    print(f"  build field (coefficient tables)        {build_s * 1e3:8.2f} ms")
    print(f"  first calls (JIT compile or cache load) {first_s * 1e3:8.2f} ms")
    print(f"  batch acceleration                      {acc_s:8.3f} s  "
          f"({acc_s / N_EPOCHS * 1e6:.1f} us/position)")
    print(f"  batch acceleration + gradient           {grad_s:8.3f} s  "
          f"({grad_s / N_EPOCHS * 1e6:.1f} us/position)")
    print(f"  one position per call, acceleration     {one_acc_s / n_single * 1e6:8.1f} us")
    print(f"  one position per call, acc + gradient   {one_grad_s / n_single * 1e6:8.1f} us")
    print(f"  jitted kernel, acceleration             "
          f"{kernel_times['acceleration'] / N_EPOCHS * 1e6:8.1f} us/position")
    print(f"  jitted kernel, acc + gradient           "
          f"{kernel_times['gradient'] / N_EPOCHS * 1e6:8.1f} us/position")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--degree", type=int, default=120)
    parser.add_argument("--repeat", type=int, default=3)
    cli = parser.parse_args()
    main(cli.degree, cli.repeat)
