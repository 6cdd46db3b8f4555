"""Benchmark of the code-bias map estimation for one month of 30-s data (issue 6).

Prepares the quality outputs of the three simulated default-campaign days with the workflow if
they are missing (``snakemake results/hy2b-sim/quality/hy2b-sim/2019-00{1,2,3}.nc``), writes 30
daily quality files to a temporary directory by repeating these days with their times shifted
(the cost depends on the number of observations and passes, not on their content), and times
what rule ``code_bias`` does for a monthly period: reading the 30 files and estimating the 5° ×
5° maps of every code (C1C, C1W, C2W). Prints wall time, peak memory and the observation counts.

    .venv/bin/python benchmarks/code_bias.py [--days 30] [--truth]

``--truth`` also compares the monthly map of the default campaign
(results/hy2b-sim/code_bias/hy2b-sim/2019-01.nc, made by ``make run``) with the simulated HY-2B
P1 map over the nodes with at least 200 observations (issue 6; the constant is removed) and prints
the C1W multipath RMS before and after the correction.
"""

from __future__ import annotations

import argparse
import logging
import resource
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.codebias.estimate import MapSettings
from leopod.codebias.period import estimate_period
from leopod.codebias.products import grid_of, node_vector
from leopod.codebias.samples import load_quality
from leopod.simulate.code_bias_map import CodeBiasMap
from leopod.workflow.config import load_campaign

REPO = Path(__file__).resolve().parents[1]
DAYS = ("2019-001", "2019-002", "2019-003")
#: The products of the default campaign (config/config.yaml: campaign hy2b-sim).
RESULTS = REPO / "results" / "hy2b-sim"
QUALITY = RESULTS / "quality" / "hy2b-sim"


def _prepare() -> None:
    targets = [QUALITY / f"{d}.nc" for d in DAYS]
    missing = [str(t.relative_to(REPO)) for t in targets if not t.exists()]
    if missing:
        subprocess.run([str(REPO / ".venv" / "bin" / "snakemake"), "--cores", "2", *missing],
                       cwd=REPO, check=True)


def _month(tmp: Path, n_days: int) -> list[Path]:
    paths = []
    for k in range(n_days):
        src = QUALITY / f"{DAYS[k % len(DAYS)]}.nc"
        with xr.open_dataset(src) as ds:
            names = ["el_deg", "az_deg", "pass_id", *(v for v in ds.data_vars
                                                       if v.startswith("mp_"))]
            day = ds[names].load()
        shift = np.timedelta64(k - k % len(DAYS), "D")
        day = day.assign_coords(time=day.time + shift)
        path = tmp / f"day{k:02d}.nc"
        day.to_netcdf(path)
        paths.append(path)
    return paths


def _truth_check() -> None:
    path = RESULTS / "code_bias" / "hy2b-sim" / "2019-01.nc"
    maps = xr.load_dataset(path)
    grid = grid_of(maps)
    est = node_vector(maps, "C1W", 0)
    count = grid.from_grid(maps["count"].sel(signal="C1W", mode=0).values)
    az, el = grid.node_directions()
    ok = np.isfinite(est) & (count >= 200)
    # the map the default campaign simulated (config/config.yaml, schema defaults)
    (truth_map,) = load_campaign(REPO / "config" / "config.yaml")["simulate"]["code_bias_maps"]
    err = est[ok] - CodeBiasMap.from_config(truth_map)(az[ok], el[ok])
    p1 = maps.sel(signal="C1W")
    before, after = float(p1.mp_rms_all_before_m), float(p1.mp_rms_all_after_m)
    print(f"{path.relative_to(REPO)}: C1W map minus truth over {ok.sum()} nodes with >= 200 "
          f"obs: RMS {100 * np.sqrt(np.mean((err - err.mean()) ** 2)):.2f} cm (constant "
          f"{100 * err.mean():+.1f} cm); MP RMS {before:.3f} -> {after:.3f} m "
          f"({100 * (1 - after / before):.1f} % less) over "
          f"{100 * float(p1.covered_fraction):.1f} % of the observations")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--days", type=int, default=30)
    parser.add_argument("--truth", action="store_true")
    args = parser.parse_args()
    if args.truth:
        _truth_check()
    logging.basicConfig(level=logging.WARNING)
    _prepare()
    with tempfile.TemporaryDirectory() as tmp:
        paths = _month(Path(tmp), args.days)
        t0 = time.perf_counter()
        quality = [load_quality(str(p), None) for p in paths]
        t1 = time.perf_counter()
        maps, stats = estimate_period(quality, None, MapSettings(), period="bench",
                                      satellite="hy2b-sim")
        t2 = time.perf_counter()
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"days: {args.days}, signals: {' '.join(maps.signal.values)}")
    for sig, st in stats.items():
        s = maps.sel(signal=sig)
        print(f"  {sig}: {st.n_total} MP observations, MP RMS {float(s.mp_rms_all_before_m):.3f}"
              f" -> {float(s.mp_rms_all_after_m):.3f} m, "
              f"{int((grid_of(maps).from_grid(s['count'].isel(mode=0).values) >= 200).sum())}"
              f" nodes with >= 200 obs, {100 * float(s.covered_fraction):.1f} % covered")
    print(f"read {t1 - t0:.1f} s, estimate {t2 - t1:.1f} s, total {t2 - t0:.1f} s "
          f"(target < 60 s); peak RSS {peak_mb:.0f} MB")


if __name__ == "__main__":
    main()
