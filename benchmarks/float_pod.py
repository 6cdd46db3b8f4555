"""Benchmark and figures of the float POD on the real GRACE-A day 2007-03-21 (issue 5).

Prepares the ingest and quality outputs with the workflow if they are missing
(``snakemake results/grace-a-2007/quality/grace-a/2007-080.nc --configfile
config/grace-a-2007.yaml``),
then runs the float POD step's library call (:func:`leopod.estimation.arc.run_arc`) with the
campaign settings of config/grace-a-2007.yaml at 30-s sampling over the 24 h of data and
prints its wall time, peak memory, post-fit residual RMS, passes, rejections, and the orbit
integrations and force evaluations of the initial fit and of the POD. With
``--overlap`` it also solves the sub-arcs 00-14 h and 10-24 h and prints their RTN
differences over the 4-h overlap (and over its central 2 h, away from the arc ends).

    .venv/bin/python benchmarks/float_pod.py [--overlap] [--set key=value ...] [--save F]
                                             [--antenna ANTEX TYPE]

``--set`` overrides a key of the ``pod`` section (YAML value), e.g. ``--set
pulse_interval_s=360``.
"""

from __future__ import annotations

import argparse
import logging
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import xarray as xr
import yaml
from _counting import IntegrationCounter

from leopod.estimation.arc import ArcData, run_arc
from leopod.frames.leo_attitude import LeoAttitude
from leopod.gnss.leo_antenna import leo_antenna
from leopod.io.antex import read_antex
from leopod.io.clock import read_rinex_clock
from leopod.io.sp3 import read_sp3
from leopod.validation.compare import difference_rtn, rms_rtn
from leopod.workflow.config import validated
from leopod.workflow.settings import pod_settings

REPO = Path(__file__).resolve().parents[1]
DATA = REPO.parent / "shared" / "data" / "grace-a_2007-080"
CONFIG = REPO / "config" / "grace-a-2007.yaml"
RESULTS = REPO / "results" / "grace-a-2007"   # the campaign of CONFIG
DATE = "2007-080"


def _prepare() -> None:
    target = RESULTS / "quality" / "grace-a" / f"{DATE}.nc"
    if not target.exists():
        # the target first: --configfile takes several values
        subprocess.run([str(REPO / ".venv" / "bin" / "snakemake"), str(target.relative_to(REPO)),
                        "--cores", "2", "--configfile", str(CONFIG)],
                       cwd=REPO, check=True)


def _inputs(results: Path = RESULTS) -> ArcData:
    """The arc's inputs: ingest and quality outputs of a workflow run in ``results``, the
    CODE products of the day."""
    def load(step, suffix):
        return [xr.load_dataset(results / step / "grace-a" / f"{DATE}{suffix}.nc")]
    return ArcData(obs=load("ingest", "_obs"), quality=load("quality", ""),
                   leo=load("ingest", "_leo"), orbit=read_sp3(DATA / "cod14193.sp3.gz"),
                   clock=read_rinex_clock(DATA / "cod14193.clk.gz"),
                   antex=read_antex(DATA / "igs05_1402.atx.gz"))


def _summary(label: str, arc, seconds: float | None = None) -> None:
    r = arc.result
    line = (f"{label}: phase RMS {1e3 * np.sqrt(np.nanmean(r.phase_residual_m**2)):.2f} mm "
            f"({int(r.phase_used.sum())} obs), code RMS "
            f"{np.sqrt(np.nanmean(r.code_residual_m**2)):.3f} m ({int(r.code_used.sum())} obs), "
            f"passes {r.ambiguity_m.size}, rejected {int(r.code_rejected.sum())} code / "
            f"{int(r.phase_rejected.sum())} phase, iterations {r.iterations}, "
            f"sigma0 {r.sigma0:.3f}, integrations {r.integrations} "
            f"({r.force_evaluations} force evaluations) after an initial fit of "
            f"{arc.fit.integrations} ({arc.fit.force_evaluations}, reduced model)")
    if seconds is not None:
        line += f", wall time {seconds:.1f} s"
    print(line)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--overlap", action="store_true", help="also solve the two sub-arcs")
    parser.add_argument("--set", action="append", default=[], help="pod key=value override")
    parser.add_argument("-v", action="store_true", help="log the steps (INFO)")
    parser.add_argument("--save", type=Path, help="write the orbit (netCDF) here, to compare")
    parser.add_argument("--antenna", nargs=2, metavar=("ANTEX", "TYPE"),
                        help="the POD's receiver antenna from this ANTEX entry (e.g. an "
                        "estimated PCV map of rule pcv) instead of the config's PCO table")
    args = parser.parse_args()
    if not DATA.exists():
        sys.exit(f"{DATA} is absent: this benchmark needs the real GRACE-A day")
    logging.basicConfig(level=logging.INFO if "-v" in sys.argv else logging.WARNING,
                        format="%(asctime)s %(name)s %(message)s")
    _prepare()
    cfg = yaml.safe_load(CONFIG.read_text())
    for item in args.set:
        key, value = item.split("=", 1)
        cfg["pod"][key] = yaml.safe_load(value)
    cfg = validated(cfg)
    settings = pod_settings(cfg["signals"], cfg["pod"], cfg["code_bias"])
    del settings["code_correction"]   # no code-bias map in this benchmark
    sat = cfg["satellites"]["grace-a"]
    antenna = (leo_antenna(None, {"antex": args.antenna[0], "type": args.antenna[1]})
               if args.antenna else sat["antenna_pco_body_m"])
    common = (_inputs(), *settings.values(), antenna)
    # the satellite's modelled attitude law as the campaign's float_pod job has it (no file)
    law = {"attitude": LeoAttitude.of(sat)}
    tic = time.perf_counter()
    with IntegrationCounter() as counter:
        arc = run_arc(DATE, *common, **law)
    _summary("GRACE-A 2007-080, 00-24 h, 30 s", arc, time.perf_counter() - tic)
    print(counter)
    if args.save:
        arc.orbit.to_netcdf(args.save)
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"peak resident memory {peak_mb:.0f} MB (target wall time < 60 s)")
    if args.overlap:
        day = np.datetime64("2007-03-21T00:00", "ns")
        hour = np.timedelta64(3600, "s")
        a = run_arc(DATE, *common, limits=(day, day + 14 * hour), **law)
        b = run_arc(DATE, *common, limits=(day + 10 * hour, day + 24 * hour), **law)
        _summary("sub-arc 00-14 h", a)
        _summary("sub-arc 10-24 h", b)
        for lo, hi in ((10, 14), (11, 13)):
            rms = rms_rtn(difference_rtn(a.orbit, b.orbit, start=day + lo * hour,
                                         end=day + hi * hour))
            print(f"overlap {lo:02d}-{hi:02d} h RMS [cm]: R {100 * rms['R']:.2f}  "
                  f"T {100 * rms['T']:.2f}  N {100 * rms['N']:.2f}  3D {100 * rms['3D']:.2f}")


if __name__ == "__main__":
    main()
