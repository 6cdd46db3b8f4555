"""Benchmark of the PCV estimation over one month of 30-s data, both methods (issue 22).

The campaign of config/hy2b-sim-pcv.yaml (simulated with the real GOCE antenna pattern,
../shared/data/antex/GOCE_MAIN_0001.ATX, processed without it) over ``--days`` days from
2019-01-01, once per ``--method``: ``residual`` (Wang et al. 2024, eqs. 12-13: the fixed POD's
ionosphere-free phase residuals stacked on the antenna grid, rule pcv) and ``direct`` (eqs.
10-11: one reduced normal-equation file per day, rule pcv_neq, summed and solved by rule pcv).
Each runs from scratch in ``<root>/<method>`` with ``snakemake --cores C`` up to the month's
map (results/hy2b-sim-pcv/pcv/hy2b-sim/2019-01.nc) and the fixed POD of every day. Printed per method: the workflow's wall
time, and for the PCV rules (pcv_neq, pcv) the number of jobs, their summed and largest run
time and their peak memory (Snakemake benchmark files; the memory of a job the warm worker
ran is its fork's, from its log); then the map against the truth (benchmarks/pcv.py
``campaign_map``: the GOCE pattern stacked at the fixed-POD residual directions of the month
as the map is, RMS over the nodes with enough residuals, all and above 10° elevation).
``--iterations N``: the campaign again with the previous map applied (the satellite's antenna
the ANTEX that rule pcv wrote, as config/hy2b-sim-pcv.yaml describes), in
``<root>/<method>_<k>``; its map is the previous one plus the new estimate (Wang et al. 2024
iterate three times).

``--pattern synthetic``: the simulator's antenna is instead the smooth ±1 cm pattern of
benchmarks/pcv.py ``synthetic_pcv_m`` (orders 2 and 3 in azimuth, nothing a grid of 10° cannot
hold), its phase centres ``--pco-z-error-mm`` higher than the POD's PCO; ``--estimate-pco-z``
adds a PCO-Z to the direct method. Printed too: the map against the truth with the parts like
a constant, a PCO-Z and a horizontal offset removed from the difference (what the POD's
clock and orbit take, the datum of leopod.antenna.pcv_direct), and the PCO-Z estimate.

    .venv/bin/python benchmarks/pcv_month.py [--days 30] [--method residual direct]
                                             [--iterations 1] [--cores 2]
                                             [--root ../bench_pcv] [--reuse]
                                             [--pattern goce|synthetic]
                                             [--pco-z-error-mm 0] [--estimate-pco-z]
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import xarray as xr
import yaml
from _jobs import benchmark_folder, job_figures
from pcv import GOCE, SYNTHETIC_TYPE, TRUTH_ANTENNA, campaign_map, write_synthetic_antex

from leopod.gnss.leo_antenna import leo_antenna
from leopod.workflow.layout import Layout

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
CONFIG = REPO / "config" / "hy2b-sim-pcv.yaml"
START = dt.date(2019, 1, 1)
PCV_RULES = ("pcv_neq", "pcv")


def _config(days: int, method: str, applied: dict | None, truth: dict | None = None,
            pco_z: bool = False, step_deg: float = 10.0) -> dict:
    cfg = yaml.safe_load(CONFIG.read_text())
    cfg["end_date"] = (START + dt.timedelta(days=days - 1)).isoformat()
    cfg["pcv"].update(method=method, az_step_deg=step_deg, zenith_step_deg=step_deg)
    if pco_z:
        cfg["pcv"]["estimate_pco_z"] = True
    sat = cfg["satellites"]["hy2b-sim"]
    # the pattern file of the simulator, from the checkout (the run is elsewhere)
    sat["simulate_antenna"]["antex"] = str((REPO / sat["simulate_antenna"]["antex"]).resolve())
    if truth is not None:
        sat["simulate_antenna"] = truth
    if applied is not None:          # the previous iteration's map (or the truth) in the POD
        del sat["antenna_pco_body_m"]
        sat["antenna"] = applied
    return cfg


def _days(days: int) -> list[str]:
    return [(START + dt.timedelta(days=k)).strftime("%Y-%j") for k in range(days)]


def _map_path(work: Path, layout: Layout, suffix: str) -> Path:
    return work / layout.results / "pcv" / "hy2b-sim" / f"2019-01.{suffix}"


def _truth(root: Path, pattern: str, pco_z_error_mm: float) -> tuple[dict | None, object]:
    """The simulator's antenna (config entry, None: the GOCE one of the config file) and
    the truth antenna of the map comparison."""
    if pattern == "goce":
        return None, TRUTH_ANTENNA
    entry = {"antex": str(write_synthetic_antex(root / "synthetic_pcv.atx",
                                                pco_z_error_mm * 1e-3)),
             "type": SYNTHETIC_TYPE}
    return entry, leo_antenna(None, entry)


def fixed_orbit_rms_m(work: Path, layout: Layout, days: list[str]) -> float:
    """3D RMS of the fixed-POD orbits minus the simulated truth over the days (each day's
    epochs from 00:00 to 24:00 only) [m]."""
    truth = xr.open_dataset(next(work.glob("resources/*/simulate/*/truth_orbit.nc")))
    squares = []
    for day in days:
        orbit = xr.load_dataset(work / layout.results / "fixed_pod" / "hy2b-sim"
                                / f"{day}_orbit.nc")
        t0 = np.datetime64(dt.datetime.strptime(day, "%Y-%j"), "ns")
        orbit = orbit.sel(time=(orbit.time >= t0) & (orbit.time < t0 + np.timedelta64(1, "D")))
        d = orbit.pos_itrf_m.values - truth.pos_itrf_m.sel(time=orbit.time.values).values
        squares.append(np.sum(d**2, axis=1))
    return float(np.sqrt(np.concatenate(squares).mean()))


def run_method(root: Path, days: int, method: str, cores: int, reuse: bool,
               iteration: int = 1, pattern: str = "goce", pco_z_error_mm: float = 0.0,
               pco_z: bool = False, true_pattern: bool = False, step_deg: float = 10.0) -> dict:
    """Run (or reload) the month of one method and iteration (or, ``true_pattern``, with the
    simulator's antenna in the POD); its figures."""
    work = root / ("true" if true_pattern else method if iteration == 1
                   else f"{method}_{iteration}")
    result = work / "pcv_benchmark.json"
    if reuse and result.exists():
        return json.loads(result.read_text())
    work.mkdir(parents=True, exist_ok=True)
    truth, truth_antenna = _truth(root, pattern, pco_z_error_mm)
    applied = None
    if true_pattern:
        applied = truth or {"antex": str(GOCE), "type": "GOCE"}
    elif iteration > 1:
        previous = root / (method if iteration == 2 else f"{method}_{iteration - 1}")
        applied = {"antex": str(_map_path(previous, Layout.of(_config(days, method, None)),
                                          "atx")), "type": "LEOPOD PCV"}
    cfg = _config(days, method, applied, truth, pco_z, step_deg)
    (work / "campaign.yaml").write_text(yaml.safe_dump(cfg))
    layout = Layout.of(cfg)
    # the fixed POD's residuals of every day: the directions at which the truth is stacked
    # (the direct method's map needs only the float POD and the ambiguity tables)
    targets = [_map_path(Path(), layout, "nc"),
               *(Path(layout.results) / "fixed_pod" / "hy2b-sim" / f"{day}_residuals.nc"
                 for day in _days(days))]
    print(f"running the {days}-day {method}-method campaign, "
          f"{'the true pattern in the POD' if true_pattern else f'iteration {iteration}'}, "
          f"in {work} ...", flush=True)
    t0 = time.perf_counter()
    proc = subprocess.run([SNAKEMAKE, "--snakefile", str(REPO / "Snakefile"), "--directory",
                           str(work), "--cores", str(cores), *map(str, targets), "--configfile",
                           str(work / "campaign.yaml")], capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        sys.exit(f"snakemake failed in {work}:\n{proc.stderr[-4000:]}")
    rows = []
    folder = benchmark_folder(work, layout.campaign)
    for rule in PCV_RULES:
        figures = [job_figures(work, tsv) for tsv in (folder / rule).rglob("*.tsv")]
        if figures:
            s, mb = zip(*figures, strict=True)
            rows.append({"rule": rule, "jobs": len(s), "sum_s": sum(s), "max_s": max(s),
                         "max_rss_mb": max(mb)})
    rms = campaign_map(work, days=_days(days), truth_antenna=truth_antenna)
    estimate = xr.load_dataset(_map_path(work, layout, "nc"))
    out = {"method": method, "iteration": iteration, "days": days, "cores": cores,
           "pattern": pattern, "pco_z_error_mm": pco_z_error_mm, "true_pattern": true_pattern,
           "fixed_orbit_3d_rms_cm": 1e2 * fixed_orbit_rms_m(work, layout, _days(days)),
           "pco_z_estimate_mm": 1e3 * float(estimate.attrs.get("pco_z_m", np.nan)),
           "pco_z_sigma_mm": 1e3 * float(estimate.attrs.get("pco_z_sigma_m", np.nan)),
           "wall_s": wall, "rules": rows, "map_rms_mm": {k: 1e3 * v for k, v in rms.items()}}
    result.write_text(json.dumps(out, indent=1))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--days", type=int, default=30)
    parser.add_argument("--method", nargs="+", default=["residual", "direct"],
                        choices=["residual", "direct"])
    parser.add_argument("--iterations", type=int, default=1)
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--root", type=Path, default=REPO.parent / "bench_pcv")
    parser.add_argument("--reuse", action="store_true")
    parser.add_argument("--pattern", choices=("goce", "synthetic"), default="goce",
                        help="the simulated antenna: the real GOCE pattern (default) or the "
                        "smooth +-1 cm one of benchmarks/pcv.py synthetic_pcv_m")
    parser.add_argument("--pco-z-error-mm", type=float, default=0.0,
                        help="with --pattern synthetic: its phase centres this much higher "
                        "than the POD's PCO [mm]")
    parser.add_argument("--estimate-pco-z", action="store_true",
                        help="direct method: a PCO-Z with the map (pcv.estimate_pco_z)")
    parser.add_argument("--step", type=float, default=10.0,
                        help="grid step in azimuth and zenith [deg] (pcv.az_step_deg, "
                        "pcv.zenith_step_deg)")
    parser.add_argument("--true-pattern", action="store_true",
                        help="one run (in <root>/true) with the simulator's antenna in the POD: "
                        "the orbit the maps should reach")
    args = parser.parse_args()
    if args.days > 31:
        sys.exit("one month: --days up to 31 (the map's period is the month 2019-01)")
    if args.pco_z_error_mm and args.pattern != "synthetic":
        sys.exit("--pco-z-error-mm needs --pattern synthetic (the GOCE file is used as it is)")
    if args.true_pattern:
        _report(run_method(args.root.resolve(), args.days, args.method[0], args.cores,
                           args.reuse, pattern=args.pattern,
                           pco_z_error_mm=args.pco_z_error_mm, true_pattern=True))
        return
    for method in args.method:
        for iteration in range(1, args.iterations + 1):
            _report(run_method(args.root.resolve(), args.days, method, args.cores, args.reuse,
                               iteration, args.pattern, args.pco_z_error_mm,
                               args.estimate_pco_z, step_deg=args.step))


def _report(f: dict) -> None:
    """Print the figures of one run."""
    print(f"\n## {f['method']} method, iteration {f.get('iteration', 1)}, {f['days']} days, "
          f"{f['cores']} cores: workflow {f['wall_s'] / 60:.1f} min up to the month's map")
    if f["rules"]:
        print(pd.DataFrame(f["rules"]).to_string(index=False, float_format="%.1f"))
    if "fixed_orbit_3d_rms_cm" in f:
        print("fixed orbits minus truth, 3D RMS over the days: "
              f"{f['fixed_orbit_3d_rms_cm']:.3f} cm")
    rms = f["map_rms_mm"]
    print(f"map minus truth RMS: {rms['all']:.2f} mm over the nodes with enough "
          f"residuals, {rms['above_10deg']:.2f} mm above 10 deg; without the parts like a "
          f"constant, a PCO-Z and a horizontal offset {rms.get('datum_all', np.nan):.2f} / "
          f"{rms.get('datum_above_10deg', np.nan):.2f} mm")
    if np.isfinite(f.get("pco_z_estimate_mm", np.nan)):
        print(f"PCO-Z correction along body +Z {f['pco_z_estimate_mm']:.2f} +- "
              f"{f['pco_z_sigma_mm']:.2f} mm (truth {-f.get('pco_z_error_mm', 0.0):g} mm: the "
              "phase centres higher, towards body -Z)")


if __name__ == "__main__":
    main()
