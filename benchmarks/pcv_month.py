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

    .venv/bin/python benchmarks/pcv_month.py [--days 30] [--method residual direct]
                                             [--iterations 1] [--cores 2]
                                             [--root ../bench_pcv] [--reuse]
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import yaml
from _jobs import benchmark_folder, job_figures
from pcv import campaign_map

from leopod.workflow.layout import Layout

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
CONFIG = REPO / "config" / "hy2b-sim-pcv.yaml"
START = dt.date(2019, 1, 1)
PCV_RULES = ("pcv_neq", "pcv")


def _config(days: int, method: str, applied: Path | None) -> dict:
    cfg = yaml.safe_load(CONFIG.read_text())
    cfg["end_date"] = (START + dt.timedelta(days=days - 1)).isoformat()
    cfg["pcv"]["method"] = method
    sat = cfg["satellites"]["hy2b-sim"]
    # the pattern file of the simulator, from the checkout (the run is elsewhere)
    sat["simulate_antenna"]["antex"] = str((REPO / sat["simulate_antenna"]["antex"]).resolve())
    if applied is not None:                   # the previous iteration's map in the POD
        del sat["antenna_pco_body_m"]
        sat["antenna"] = {"antex": str(applied), "type": "LEOPOD PCV"}
    return cfg


def _days(days: int) -> list[str]:
    return [(START + dt.timedelta(days=k)).strftime("%Y-%j") for k in range(days)]


def _map_path(work: Path, layout: Layout, suffix: str) -> Path:
    return work / layout.results / "pcv" / "hy2b-sim" / f"2019-01.{suffix}"


def run_method(root: Path, days: int, method: str, cores: int, reuse: bool,
               iteration: int = 1) -> dict:
    """Run (or reload) the month of one method and iteration; its figures."""
    work = root / (method if iteration == 1 else f"{method}_{iteration}")
    result = work / "pcv_benchmark.json"
    if reuse and result.exists():
        return json.loads(result.read_text())
    work.mkdir(parents=True, exist_ok=True)
    applied = None
    if iteration > 1:
        previous = root / (method if iteration == 2 else f"{method}_{iteration - 1}")
        applied = _map_path(previous, Layout.of(_config(days, method, None)), "atx")
    cfg = _config(days, method, applied)
    (work / "campaign.yaml").write_text(yaml.safe_dump(cfg))
    layout = Layout.of(cfg)
    # the fixed POD's residuals of every day: the directions at which the truth is stacked
    # (the direct method's map needs only the float POD and the ambiguity tables)
    targets = [_map_path(Path(), layout, "nc"),
               *(Path(layout.results) / "fixed_pod" / "hy2b-sim" / f"{day}_residuals.nc"
                 for day in _days(days))]
    print(f"running the {days}-day {method}-method campaign, iteration {iteration}, in {work} "
          "...", flush=True)
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
    rms = campaign_map(work, days=_days(days))
    out = {"method": method, "iteration": iteration, "days": days, "cores": cores,
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
    args = parser.parse_args()
    if args.days > 31:
        sys.exit("one month: --days up to 31 (the map's period is the month 2019-01)")
    for method in args.method:
        for iteration in range(1, args.iterations + 1):
            _report(run_method(args.root.resolve(), args.days, method, args.cores, args.reuse,
                               iteration))


def _report(f: dict) -> None:
    """Print the figures of one run."""
    print(f"\n## {f['method']} method, iteration {f.get('iteration', 1)}, {f['days']} days, "
          f"{f['cores']} cores: workflow {f['wall_s'] / 60:.1f} min up to the month's map")
    if f["rules"]:
        print(pd.DataFrame(f["rules"]).to_string(index=False, float_format="%.1f"))
    print(f"map minus truth RMS: {f['map_rms_mm']['all']:.2f} mm over the nodes with enough "
          f"residuals, {f['map_rms_mm']['above_10deg']:.2f} mm above 10 deg")


if __name__ == "__main__":
    main()
