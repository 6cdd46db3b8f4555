"""Benchmark: kinematic POD of the default simulated day and of the real GRACE-A day.

Runs the workflow's kinematic_pod job (with everything before it) in two campaign
directories, once per kind of ambiguities (a campaign file with ``kinematic.enabled`` and
``kinematic.ambiguities`` is written beside the campaign's), and prints:

- simulated day (config/config.yaml, first day): kinematic minus the simulator's truth orbit,
  RMS of R, T, N and 3D, float and fixed, and the share of the day's epochs solved;
- GRACE-A 2007-080 (config/grace-a-2007.yaml, float only): kinematic minus the float
  reduced-dynamic orbit, RMS of R, T, N and 3D, and the share of epochs solved.

    .venv/bin/python benchmarks/kinematic_pod.py [--sim-directory D] [--grace-directory G]

The directories are campaign working directories beside ../shared (e.g. /work/scratch-kin),
so that the GRACE-A campaign's ../shared paths resolve.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.validation.compare import difference_rtn, rms_rtn
from leopod.workflow.config import read_campaign
from leopod.workflow.layout import Layout

REPO = Path(__file__).resolve().parents[1]


def _kinematic(root: Path, config: Path, sat: str, date: str, ambiguities: str) -> tuple:
    """Run the kinematic_pod job of ``sat``/``date`` and return its dataset and wall time."""
    extra = root / f"kinematic_{ambiguities}.yaml"
    extra.write_text(f"kinematic:\n  enabled: true\n  ambiguities: {ambiguities}\n")
    results = Layout.of(read_campaign(config)).results
    target = f"{results}/kinematic_pod/{sat}/{date}.nc"
    snakemake = [str(Path(sys.executable).with_name("snakemake")), target, "--cores", "2",
                 "--snakefile", str(REPO / "Snakefile"), "--directory", str(root),
                 "--configfile", str(config), str(extra)]
    subprocess.run(snakemake, check=True, capture_output=True)     # the steps before it
    tic = time.perf_counter()
    subprocess.run(snakemake + ["--forcerun", "kinematic_pod"], check=True, capture_output=True)
    wall = time.perf_counter() - tic
    kept = root / f"{results}/kinematic_pod/{sat}/{date}_{ambiguities}.nc"
    shutil.copyfile(root / target, kept)
    return xr.load_dataset(kept), wall


def _line(label: str, ds: xr.Dataset, reference: xr.Dataset, wall: float) -> str:
    solved = ds.solved.values == 1
    rms = rms_rtn(difference_rtn(ds.isel(time=np.flatnonzero(solved)), reference))
    return (f"{label:<34s} R {100 * rms['R']:6.2f}  T {100 * rms['T']:6.2f}  N "
            f"{100 * rms['N']:6.2f}  3D {100 * rms['3D']:6.2f} cm   solved "
            f"{100 * solved.mean():5.1f} % of {solved.size} epochs   job {wall:5.1f} s")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sim-directory", type=Path, default=Path("/work/scratch-kin"))
    parser.add_argument("--grace-directory", type=Path, default=Path("/work/scratch-kin-grace"))
    args = parser.parse_args()
    sim, grace = args.sim_directory.resolve(), args.grace_directory.resolve()
    sat, date = "hy2b-sim", "2019-001"
    print(f"kinematic POD, simulated {sat} {date} (config/config.yaml), minus the truth orbit")
    for ambiguities in ("float", "fixed"):
        ds, wall = _kinematic(sim, REPO / "config" / "config.yaml", sat, date, ambiguities)
        truth = xr.load_dataset(sim / f"resources/hy2b-sim/simulate/{sat}/{date}_truth.nc")
        print(_line(f"  {ambiguities} ambiguities", ds, truth, wall))
    sat, date = "grace-a", "2007-080"
    print(f"kinematic POD, real {sat} {date} (config/grace-a-2007.yaml), minus the float "
          "reduced-dynamic orbit")
    ds, wall = _kinematic(grace, REPO / "config" / "grace-a-2007.yaml", sat, date, "float")
    reference = xr.load_dataset(grace / f"results/grace-a-2007/float_pod/{sat}/{date}_orbit.nc")
    print(_line("  float ambiguities", ds, reference, wall))


if __name__ == "__main__":
    main()
