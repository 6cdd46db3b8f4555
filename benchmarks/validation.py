"""Validation of the simulated default campaign against its truth, and the report build time
(issue 8).

Run ``make run`` first. For every day this prints

* the SLR residuals of the simulated **truth** orbit: mean and STD against those of the
  simulated normal-point noise (target: within 1 mm);
* for the float and the fixed orbit: mean and STD of the SLR residuals, and of the residuals
  minus the orbit error projected on the line of sight (orbit minus truth, −e·δ), which must
  leave the simulated noise;

then the wall time of ``snakemake --report`` for the campaign (target for one day: < 30 s).

    .venv/bin/python benchmarks/validation.py [--configfile F] [--directory D]
"""

from __future__ import annotations

import argparse
import logging
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io.crd import read_crd
from leopod.io.sinex import read_sinex_eccentricities, read_sinex_stations
from leopod.simulate.settings import SimulationSettings
from leopod.validation.slr import (
    SlrResidualSettings,
    line_of_sight_orbit_difference,
    slr_residuals,
)
from leopod.workflow.campaign import campaign_days
from leopod.workflow.config import load_campaign, section_defaults
from leopod.workflow.layout import Layout

SLR = SlrResidualSettings.from_config(section_defaults("validation")["slr"])

REPO = Path(__file__).resolve().parents[1]
SAT = "hy2b-sim"


def _mm(values) -> str:
    v = np.asarray(values)
    v = v[np.isfinite(v)]
    return f"mean {1e3 * v.mean():+.2f} mm, STD {1e3 * v.std(ddof=1):.2f} mm (n={v.size})"


def slr_check(cfg: dict, workdir: Path) -> None:
    layout = Layout.of(cfg)
    sim = workdir / layout.resources / "simulate"
    truth = xr.load_dataset(sim / SAT / "truth_orbit.nc")
    stations = read_sinex_stations(sim / "slr_stations.snx")
    ecc = read_sinex_eccentricities(sim / "slr_eccentricities.snx")
    retro = SimulationSettings.from_config(cfg["simulate"]).slr.retro_offset_body_m
    for date in campaign_days(cfg):
        nps = read_crd(sim / SAT / f"{date}.crd")
        res = slr_residuals(truth, nps, stations, ecc, retro_offset_body_m=retro,
                            settings=SLR)
        used = res.flag.values == 0
        # the simulated noise of the same points: the truth-orbit residual is noise + bias
        print(f"{date}: truth orbit SLR residuals {_mm(res.residual_m.values[used])}")
        for solution in ("float_pod", "fixed_pod"):
            path = workdir / layout.results / "slr" / SAT / solution / f"{date}.nc"
            if not path.exists():
                continue
            r = xr.load_dataset(path)
            orbit = xr.load_dataset(workdir / layout.results / solution / SAT
                                    / f"{date}_orbit.nc")
            ok = r.flag.values == 0
            projected = line_of_sight_orbit_difference(r, orbit, truth).values
            print(f"  {solution}: residuals {_mm(r.residual_m.values[ok])}; minus projected "
                  f"orbit error {_mm(r.residual_m.values[ok] - projected[ok])}")


def report_time(workdir: Path, configfile: Path, layout: Layout) -> None:
    snakemake = str(Path(sys.executable).with_name("snakemake"))
    report = workdir / layout.report
    t0 = time.perf_counter()
    subprocess.run([snakemake, "--snakefile", str(REPO / "Snakefile"), "--directory",
                    str(workdir), "--configfile", str(configfile), "--report",
                    str(report)], check=True, capture_output=True)
    size = report.stat().st_size / 1e6
    print(f"snakemake --report: {time.perf_counter() - t0:.1f} s ({size:.1f} MB)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--configfile", type=Path, default=REPO / "config" / "config.yaml")
    parser.add_argument("--directory", type=Path, default=REPO)
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    cfg = load_campaign(args.configfile)
    slr_check(cfg, args.directory)
    report_time(args.directory.resolve(), args.configfile.resolve(), Layout.of(cfg))


if __name__ == "__main__":
    main()
