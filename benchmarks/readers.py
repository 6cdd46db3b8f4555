"""Benchmark: reading times of the large reference files and the orbit comparison.

Prints the wall time (best of ``--repeat``) of

* reading the IGS05 ANTEX igs05_1627.atx (323 antennas; requirement < 1.5 s),
* reading the ILRS SLRF2020 SINEX (227 station solutions; requirement < 1.0 s),
* comparing a 30-h 10-s orbit with a 30-s reference and its statistics (requirement < 0.5 s
  after warm-up),

against the requirements that the tests used to assert (a test suite on a shared machine is
no place for wall-time limits). The real files come from ../shared/data; without them those
lines say so.

    .venv/bin/python benchmarks/readers.py [--repeat N]
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np
import xarray as xr
from _timing import best_of

from leopod.constants import GM_EARTH_M3_S2
from leopod.frames.earth_rotation import gcrf_to_itrf
from leopod.io.antex import read_antex
from leopod.io.sinex import read_sinex_stations
from leopod.validation.compare import compare_orbits
from leopod.validation.orbit_statistics import orbit_statistics

SHARED = Path(__file__).resolve().parents[2] / "shared/data"
ANTEX = SHARED / "antex/igs05_1627.atx"
SLRF2020 = SHARED / "slr/SLRF2020_POS+VEL_2023.10.02.snx"



def _circular_orbit(hours: float = 30.0, step_s: float = 10.0) -> xr.Dataset:
    """500-km circular polar orbit in the POD orbit schema (GCRF and ITRF)."""
    a = 6_878_137.0
    n = math.sqrt(GM_EARTH_M3_S2 / a**3)
    t_s = np.arange(0.0, hours * 3600.0 + 1e-6, step_s)
    times = np.datetime64("2023-01-01T21:00:00", "ns") + (t_s * 1e9).astype("timedelta64[ns]")
    u, inc = n * t_s, math.radians(87.4)
    pos = a * np.stack([np.cos(u), np.sin(u) * math.cos(inc), np.sin(u) * math.sin(inc)], 1)
    vel = a * n * np.stack([-np.sin(u), np.cos(u) * math.cos(inc), np.cos(u) * math.sin(inc)], 1)
    pos_itrf, vel_itrf = gcrf_to_itrf(times, pos, vel)
    dims = ("time", "xyz")
    return xr.Dataset({"pos_gcrf_m": (dims, pos), "vel_gcrf_m_s": (dims, vel),
                       "pos_itrf_m": (dims, pos_itrf), "vel_itrf_m_s": (dims, vel_itrf)},
                      coords={"time": times, "xyz": ["x", "y", "z"]},
                      attrs={"time_system": "GPS"})


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    rows = []
    if ANTEX.exists():
        rows.append(("read_antex igs05_1627.atx",
                     best_of(lambda: read_antex(ANTEX), args.repeat), 1.5))
    else:
        print(f"{ANTEX} not found: ANTEX reading not measured")
    if SLRF2020.exists():
        rows.append(("read_sinex_stations SLRF2020",
                     best_of(lambda: read_sinex_stations(SLRF2020), args.repeat), 1.0))
    else:
        print(f"{SLRF2020} not found: SINEX reading not measured")
    orbit = _circular_orbit()
    ref = orbit.isel(time=slice(0, None, 3))
    compare_orbits(orbit.isel(time=slice(0, 50)), ref)                    # warm-up
    rows.append(("compare_orbits + statistics, 30 h at 10 s",
                 best_of(lambda: orbit_statistics(compare_orbits(orbit, ref)), args.repeat), 0.5))
    print(f"{'step':45s} {'best [s]':>9s} {'limit [s]':>9s}")
    for name, seconds, limit in rows:
        flag = "" if seconds < limit else "  OVER THE LIMIT"
        print(f"{name:45s} {seconds:9.3f} {limit:9.1f}{flag}")


if __name__ == "__main__":
    main()
