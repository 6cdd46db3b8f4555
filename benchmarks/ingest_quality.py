"""Benchmark: one day of 10-s onboard GNSS data from RINEX to the quality netCDF.

Runs the library calls of the ingest and quality steps (reading, canonical observations,
GNSS products at the observation epochs, code-only a-priori orbit, antenna-frame angles,
quality indicators, netCDF output) on the real GRACE-A day 2007-03-21 from ../shared/data and
prints the wall time of each stage and the peak memory. Without ../shared it uses a simulated
day at 10 s instead and says so.

    .venv/bin/python benchmarks/ingest_quality.py [--repeat N]
"""

from __future__ import annotations

import argparse
import resource
import tempfile
import time
from pathlib import Path

from leopod.frames.attitude import antenna_angles, nominal_body_axes
from leopod.gnss.products import GnssProducts
from leopod.gnss.quality import QualitySettings, assess_quality
from leopod.ingest import apriori_from_spp, canonical_observations, gnss_at_epochs
from leopod.io.antex import read_antex
from leopod.io.clock import read_rinex_clock
from leopod.io.netcdf import write_netcdf
from leopod.io.rinex_obs import read_rinex_obs
from leopod.io.sp3 import read_sp3
from leopod.signals import signal_settings
from leopod.workflow.config import section_defaults

SIGNALS = signal_settings({"G": {"phase": ["L1C", "L2W"], "code": ["C1C", "C1W", "C2W"],
                                 "pod_code": ["C1W", "C2W"]}})
GRACE = Path(__file__).resolve().parents[2] / "shared/data/grace-a_2007-080"


def _inputs(tmp: Path):
    if (GRACE / "graa0800.07o.gz").exists():
        return ("GRACE-A 2007-080 (real, 10 s)", GRACE / "graa0800.07o.gz", GRACE / "cod14193.sp3.gz",
                GRACE / "cod14193.clk.gz", GRACE / "igs05_1402.atx.gz",
                {"L1": [-0.0004, -0.0004, -0.4514], "L2": [-0.0004, -0.0004, -0.4757]})
    from leopod.simulate.campaign import (
        simulate_gnss_products,
        simulate_leo_day,
        simulate_truth,
        simulate_world_truth,
    )
    from leopod.simulate.settings import SimulationSettings
    from leopod.workflow.config import with_defaults

    day, sat = "2019-001", "sim"
    s = SimulationSettings.from_config(with_defaults("simulate", {"interval_s": 10.0}))
    pco = {"L1": [0.0, 0.0, -0.35], "L2": [0.0, 0.0, -0.37]}
    truth = simulate_truth(s, sat, day, day)
    biases = simulate_world_truth(s, [sat], day, day, biases_path=tmp / "b.nc",
                                  stations_path=tmp / "s.snx")
    simulate_gnss_products(day, s, day, day, biases, orbit=tmp / "g.sp3", clock=tmp / "g.clk",
                           integer_clock=tmp / "g_int.clk", wl_bias=tmp / "g.wsb",
                           osb=tmp / "g.bia")
    simulate_leo_day(day, sat, s, day, day, truth, biases, pco, rinex3=tmp / "o.rnx",
                     rinex2=tmp / "o.obs", truth_sp3=tmp / "t.sp3", truth_nc=tmp / "t.nc",
                     crd=tmp / "o.crd")
    return ("simulated day (../shared absent, 10 s)", tmp / "o.rnx", tmp / "g.sp3", tmp / "g.clk",
            None, pco)


def run_once(tmp: Path) -> dict[str, float]:
    label, obs_p, sp3_p, clk_p, atx_p, pco = _inputs(tmp)
    times = {}
    t = time.perf_counter()

    def lap(name):
        nonlocal t
        now = time.perf_counter()
        times[name] = now - t
        t = now

    raw = read_rinex_obs(obs_p)
    obs = canonical_observations(raw, SIGNALS)
    lap("read RINEX + canonical")
    products = GnssProducts.from_datasets(read_sp3(sp3_p), read_rinex_clock(clk_p),
                                          obs.time.values[0].astype("datetime64[D]"),
                                          max_extrapolation_s=900.0)
    antex = read_antex(atx_p) if atx_p else None
    lap("read SP3 + clock + ANTEX")
    gnss = gnss_at_epochs(products, obs.time.values)
    lap("GNSS orbits at epochs")
    leo = apriori_from_spp(obs, products, SIGNALS, pco, antex)
    lap("code-only a-priori orbit")
    write_netcdf(obs, tmp / "obs.nc", step="bench")
    write_netcdf(gnss, tmp / "gnss.nc", step="bench")
    write_netcdf(leo, tmp / "leo.nc", step="bench")
    lap("write ingest netCDF")
    rot = nominal_body_axes(leo.pos_m.values, leo.vel_m_s.values)
    el, az = antenna_angles(rot, gnss.pos_m.sel(sv=obs.sv).values - leo.pos_m.values[:, None, :])
    q = assess_quality(obs, el, az, "G", ["L1C", "L2W"], ["C1C", "C1W", "C2W"], ["C1W", "C2W"],
                       QualitySettings.from_config(section_defaults("quality")))
    lap("quality indicators")
    write_netcdf(q, tmp / "quality.nc", step="bench")
    lap("write quality netCDF")
    times["_label"] = label
    times["_epochs"] = obs.sizes["time"]
    return times


def _total(run: dict) -> float:
    return sum(v for k, v in run.items() if not k.startswith("_"))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs; the fastest is reported")
    args = parser.parse_args()
    runs = []
    for _ in range(args.repeat):
        with tempfile.TemporaryDirectory() as tmp:
            runs.append(run_once(Path(tmp)))
    best = min(runs, key=_total)
    print(f"input: {best['_label']}, {best['_epochs']} epochs; best of {args.repeat} runs")
    total = 0.0
    for name, sec in best.items():
        if name.startswith("_"):
            continue
        total += sec
        print(f"  {name:28s} {sec:7.2f} s")
    print(f"  {'total':28s} {total:7.2f} s   (target < 20 s)")
    print(f"  all runs, total [s]: {', '.join(f'{_total(r):.2f}' for r in runs)}")
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"  peak resident memory       {peak_mb:7.0f} MB")


if __name__ == "__main__":
    main()
