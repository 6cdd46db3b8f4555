"""Benchmark: reading times of the large reference files, of a POD arc's inputs, and the
orbit comparison.

Prints the wall time (best of ``--repeat``) of

* reading the IGS05 ANTEX igs05_1627.atx (323 antennas; requirement < 1.5 s),
* reading the ILRS SLRF2020 SINEX (227 station solutions; requirement < 1.0 s),
* comparing a 30-h 10-s orbit with a 30-s reference and its statistics (requirement < 0.5 s
  after warm-up),

against the requirements that the tests used to assert (a test suite on a shared machine is no
place for wall-time limits), and (issue 18) the time of
:meth:`leopod.estimation.arc.ArcData.read` for the GRACE-A day 2007-080 (CODE SP3 and 30-s
clocks, IGS05 ANTEX) and the simulated default campaign's day 2019-002 (a 30-h arc over three
days of SP3 and integer-clock files, no ANTEX), once from the text files (as every POD job
parsed them before the gnss_products rule) and once from the netCDF files that rule writes
(written here by its script into a temporary folder): the products alone, and the whole arc when
the ingest and quality outputs of the day exist under results/<campaign>/ (``snakemake
results/grace-a-2007/quality/grace-a/2007-080.nc --configfile config/grace-a-2007.yaml``; for
the simulated arc the quality files of 2019-001..003 with config/config.yaml). The real files
come from ../shared/data and the simulated ones from resources/hy2b-sim/simulate/gnss/
(``snakemake resources/hy2b-sim/simulate/gnss/2019-00{1,2,3}_int.clk --configfile
config/config.yaml``); without them those lines say so.

    .venv/bin/python benchmarks/readers.py [--repeat N]
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import tempfile
from pathlib import Path

import numpy as np
import xarray as xr
from _timing import best_of

from leopod.constants import GM_EARTH_M3_S2
from leopod.estimation.arc import ArcData
from leopod.frames.earth_rotation import gcrf_to_itrf
from leopod.io.antex import read_antex
from leopod.io.sinex import read_sinex_stations
from leopod.validation.compare import compare_orbits
from leopod.validation.orbit_statistics import orbit_statistics

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared/data"
ANTEX = SHARED / "antex/igs05_1627.atx"
SLRF2020 = SHARED / "slr/SLRF2020_POS+VEL_2023.10.02.snx"
GRACE = SHARED / "grace-a_2007-080"
SIMULATED = REPO / "resources/hy2b-sim/simulate/gnss"
#: The products folder of each satellite's campaign (config/grace-a-2007.yaml, config.yaml).
RESULTS = {"grace-a": REPO / "results/grace-a-2007", "hy2b-sim": REPO / "results/hy2b-sim"}


def _gnss_products_main():
    """``main`` of scripts/gnss_products.py (the rule that writes the netCDF products)."""
    spec = importlib.util.spec_from_file_location("gnss_products",
                                                  REPO / "scripts/gnss_products.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.main


def _arc_files(sat: str, days: list[str], text: dict, folder: Path) -> tuple[dict, dict, bool]:
    """ArcData.read mappings of an arc (text products, netCDF products) and whether they
    include the day's ingest and quality outputs. ``text``: {day: (sp3, clock, antex)}."""
    write = _gnss_products_main()
    nc = {"orbit": [], "clock": []}
    for day in days:
        sp3, clk, atx = text[day]
        out = {k: folder / f"{day}_{k}.nc" for k in ("orbit", "clock", "antenna")}
        write(day, sp3, clk, atx, out["orbit"], out["clock"], out["antenna"], systems=["G"])
        nc["orbit"].append(out["orbit"])
        nc["clock"].append(out["clock"])
        if atx and day == days[len(days) // 2]:
            nc["antenna"] = out["antenna"]
    raw = {"orbit": [text[d][0] for d in days], "clock": [text[d][1] for d in days]}
    atx = text[days[len(days) // 2]][2]
    if atx:
        raw["antenna"] = atx
    results = RESULTS[sat]
    daily = {"obs": [results / "ingest" / sat / f"{d}_obs.nc" for d in days],
             "leo": [results / "ingest" / sat / f"{d}_leo.nc" for d in days],
             "quality": [results / "quality" / sat / f"{d}.nc" for d in days]}
    whole = all(p.exists() for paths in daily.values() for p in paths)
    if not whole:
        daily = {k: [] for k in daily}
    return {**daily, **raw}, {**daily, **nc}, whole


def _arc_read_rows(label: str, sat: str, days: list[str], text: dict, repeat: int) -> list:
    """Rows of ArcData.read from text and from netCDF products (products only, and the
    whole arc if its ingest/quality outputs exist)."""
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        raw, nc, whole = _arc_files(sat, days, text, Path(tmp))
        products_only = {"obs": [], "leo": [], "quality": []}
        for what, files in (("text", raw), ("netCDF", nc)):
            rows.append((f"ArcData.read {label}, products from {what}",
                         best_of(lambda f=files: ArcData.read({**f, **products_only}), repeat),
                         None))
        if whole:
            for what, files in (("text", raw), ("netCDF", nc)):
                rows.append((f"ArcData.read {label}, whole arc, {what}",
                             best_of(lambda f=files: ArcData.read(f), repeat), None))
        else:
            print(f"{label}: ingest/quality outputs under {RESULTS[sat]} missing: whole-arc "
                  "reading not measured")
    return rows



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
    if GRACE.exists():
        text = {"2007-080": (GRACE / "cod14193.sp3.gz", GRACE / "cod14193.clk.gz",
                             GRACE / "igs05_1402.atx.gz")}
        rows += _arc_read_rows("GRACE-A 2007-080", "grace-a", ["2007-080"], text, args.repeat)
    else:
        print(f"{GRACE} not found: GRACE-A arc reading not measured")
    days = ["2019-001", "2019-002", "2019-003"]
    text = {d: (SIMULATED / f"{d}.sp3", SIMULATED / f"{d}_int.clk", None) for d in days}
    if all(p.exists() for d in days for p in text[d][:2]):
        rows += _arc_read_rows("simulated 2019-002 (30 h)", "hy2b-sim", days, text,
                               args.repeat)
    else:
        print(f"{SIMULATED}: simulated products of {', '.join(days)} missing: simulated arc "
              "reading not measured")
    orbit = _circular_orbit()
    ref = orbit.isel(time=slice(0, None, 3))
    compare_orbits(orbit.isel(time=slice(0, 50)), ref)                    # warm-up
    rows.append(("compare_orbits + statistics, 30 h at 10 s",
                 best_of(lambda: orbit_statistics(compare_orbits(orbit, ref)), args.repeat), 0.5))
    print(f"{'step':66s} {'best [s]':>9s} {'limit [s]':>9s}")
    for name, seconds, limit in rows:
        if limit is None:
            print(f"{name:66s} {seconds:9.3f} {'-':>9s}")
            continue
        flag = "" if seconds < limit else "  OVER THE LIMIT"
        print(f"{name:66s} {seconds:9.3f} {limit:9.1f}{flag}")


if __name__ == "__main__":
    main()
