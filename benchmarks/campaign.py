"""Campaign-scale benchmark (issue 9): simulated campaigns of 1, 7 and 30 days, all stages.

Each campaign is the default one (config/config.yaml: one simulated HY-2B-like satellite, 30-s
data, simulation -> ingest -> quality -> monthly code-bias map -> float POD -> ambiguity fixing
-> fixed POD -> overlaps, SLR and truth-orbit validation -> summary -> HTML report) over N days
from 2019-01-01 (code_bias.min_count 40 instead of 200, as a one-day map needs), run from
scratch in its own working directory with ``snakemake --cores C``. Printed per campaign: wall
time of the workflow and of the report, wall time per day, and per rule the number of jobs, mean
and max run time and peak memory (the rules' Snakemake benchmark files,
logs/<campaign>/benchmarks/<rule>/...; the memory of a job the warm worker ran is its fork's,
from the job's log; the job count includes the target rule "all"). Then the scaling fit ``T(N) =
a + b N``, the check "7 days take < 7/30 of 30 days plus a constant", the largest job memory,
and the projected cost of 10 years x 3 satellites. The job time per satellite-day is given for
all jobs and for the processing alone: without the rules that simulate the campaign's data
(``simulate*``: truth orbit, world, GNSS products and observations), whose place a real
campaign's downloads take; the projection uses the processing alone.

    .venv/bin/python benchmarks/campaign.py [--days 1 7 30] [--cores 2] [--root ../bench]
                                            [--reuse]

``--reuse`` skips campaigns whose working directory already has a result table and only
prints it again. Figures are written to ``<root>/campaign_benchmark.json``.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import platform
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import yaml
from _jobs import benchmark_folder, job_figures

from leopod.workflow.layout import Layout

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
START = dt.date(2019, 1, 1)
# GHOST (DLR): 5-10 min per 24-30 h arc on a desktop (../shared/ANCHORS.md)
GHOST_MIN_PER_ARC = (5.0, 10.0)
#: The folders of the default campaign (config/config.yaml), whose copies run here.
LAYOUT = Layout.of(yaml.safe_load((REPO / "config" / "config.yaml").read_text()))


def _config(days: int) -> dict:
    cfg = yaml.safe_load((REPO / "config" / "config.yaml").read_text())
    # one day of 30-s data touches most 5-deg nodes fewer than 200 times, and empty nodes
    # drop their C1W codes: the same lower count for every N keeps the 1-day campaign solvable
    cfg["code_bias"]["min_count"] = 40
    cfg["start_date"] = START.isoformat()
    cfg["end_date"] = (START + dt.timedelta(days=days - 1)).isoformat()
    return cfg


def _snakemake(work: Path, args: list[str]) -> tuple[float, int]:
    """Run Snakemake in ``work``; wall time [s] and number of jobs run."""
    t0 = time.perf_counter()
    proc = subprocess.run([SNAKEMAKE, "--snakefile", str(REPO / "Snakefile"), "--directory",
                           str(work), *args, "--configfile", str(work / "campaign.yaml")],
                          check=False, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        sys.exit(f"snakemake failed in {work}:\n{proc.stderr[-4000:]}")
    done = re.findall(r"(\d+) of (\d+) steps \(100%\) done", proc.stdout + proc.stderr)
    return wall, int(done[-1][1]) if done else 0


def _rule_table(work: Path) -> pd.DataFrame:
    """Per rule: jobs, mean/max run time [s], peak memory [MB] from the benchmark files."""
    rows = []
    folder = benchmark_folder(work, LAYOUT.campaign)
    for tsv in folder.rglob("*.tsv"):
        rule = tsv.relative_to(folder).parts[0]
        wall, peak = job_figures(work, tsv)
        rows.append({"rule": rule, "s": wall, "max_rss_mb": peak})
    table = pd.DataFrame(rows).groupby("rule").agg(
        jobs=("s", "size"), mean_s=("s", "mean"), max_s=("s", "max"), sum_s=("s", "sum"),
        max_rss_mb=("max_rss_mb", "max"))
    return table.sort_values("sum_s", ascending=False)


def run_campaign(root: Path, days: int, cores: int, reuse: bool) -> dict:
    """Run (or reload) one campaign; its figures."""
    work = root / f"{days}d"
    result = work / "campaign_benchmark.json"
    if reuse and result.exists():
        return json.loads(result.read_text())
    work.mkdir(parents=True, exist_ok=True)
    (work / "campaign.yaml").write_text(yaml.safe_dump(_config(days)))
    print(f"running the {days}-day campaign in {work} ...", flush=True)
    wall, jobs = _snakemake(work, ["--cores", str(cores)])
    report, _ = _snakemake(work, ["--report", str(work / LAYOUT.report)])
    table = _rule_table(work)
    figures = {"days": days, "cores": cores, "wall_s": wall, "report_s": report,
               "jobs": jobs, "cpu_s": float(table["sum_s"].sum()),
               "max_rss_mb": float(table["max_rss_mb"].max()),
               "rules": table.reset_index().to_dict(orient="records")}
    result.write_text(json.dumps(figures, indent=1))
    return figures


def _print_campaign(f: dict) -> None:
    print(f"\n## {f['days']} day(s), {f['cores']} cores: workflow {f['wall_s'] / 60:.1f} min "
          f"({f['wall_s'] / f['days']:.0f} s/day), report {f['report_s']:.1f} s, "
          f"{f['jobs']} jobs, {f['cpu_s'] / 60:.1f} min of job time, "
          f"peak job memory {f['max_rss_mb']:.0f} MB")
    print(f"{'rule':<20s} {'jobs':>5s} {'mean s':>8s} {'max s':>8s} {'sum s':>8s} {'max MB':>8s}")
    for r in f["rules"]:
        print(f"{r['rule']:<20s} {r['jobs']:5d} {r['mean_s']:8.1f} {r['max_s']:8.1f} "
              f"{r['sum_s']:8.1f} {r['max_rss_mb']:8.0f}")


def _print_scaling(results: list[dict]) -> None:
    n = np.array([f["days"] for f in results], float)
    total = np.array([f["wall_s"] + f["report_s"] for f in results])
    print("\n## Scaling (workflow + report wall time)")
    if n.size >= 2:
        b, a = np.polyfit(n, total, 1)
        print(f"T(N) = {a:.0f} s + {b:.1f} s x N days (least squares over N = "
              f"{', '.join(str(int(k)) for k in n)})")
        for k, t in zip(n, total, strict=True):
            print(f"  N = {int(k):3d}: {t / 60:6.1f} min measured, {(a + b * k) / 60:6.1f} min fit")
    by_days = {f["days"]: f["wall_s"] + f["report_s"] for f in results}
    if {1, 7, 30} <= set(by_days):
        constant = by_days[1]
        print(f"7 days: {by_days[7] / 60:.1f} min; 7/30 of 30 days + the 1-day time: "
              f"{(7 / 30 * by_days[30] + constant) / 60:.1f} min -> "
              f"{'yes' if by_days[7] < 7 / 30 * by_days[30] + constant else 'NO'}")
    if 30 in by_days:
        print(f"30 days: {by_days[30] / 60:.1f} min (target < 60 min): "
              f"{'yes' if by_days[30] < 3600 else 'NO'}")
    largest = max(results, key=lambda f: f["days"])
    simulation = sum(r["sum_s"] for r in largest["rules"] if r["rule"].startswith("simulate"))
    per_day_all = largest["cpu_s"] / largest["days"]
    per_day_cpu = (largest["cpu_s"] - simulation) / largest["days"]
    sat_days = 10 * 365.25 * 3
    print(f"\n## Job time per satellite-day of the {largest['days']}-day campaign: "
          f"{per_day_all:.1f} s all jobs, {per_day_cpu:.1f} s without the simulation of the "
          f"data ({simulation:.0f} s in the simulate* rules)")
    print(f"\n## Projection from the processing of the {largest['days']}-day campaign "
          f"({per_day_cpu:.1f} s of job time per satellite-day)")
    for cores in (2, 64, 512):
        print(f"  10 years x 3 satellites ({sat_days:.0f} satellite-days) on {cores:3d} cores: "
              f"{sat_days * per_day_cpu / cores / 3600:8.1f} h")
    ghost = [m * 60 * sat_days / 3600 for m in GHOST_MIN_PER_ARC]
    print(f"  GHOST at 5-10 min per arc on one core: {ghost[0]:.0f}-{ghost[1]:.0f} core-hours; "
          f"leopod: {sat_days * per_day_cpu / 3600:.0f} core-hours "
          f"({per_day_cpu / 60:.1f} min per satellite-day, all processing stages)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--days", type=int, nargs="+", default=[1, 7, 30])
    ap.add_argument("--cores", type=int, default=2)
    ap.add_argument("--root", type=Path, default=REPO.parent / "bench-campaign")
    ap.add_argument("--reuse", action="store_true")
    args = ap.parse_args()
    print(f"host: {platform.node()}, {platform.processor() or platform.machine()}, "
          f"python {platform.python_version()}")
    results = [run_campaign(args.root.resolve(), d, args.cores, args.reuse) for d in args.days]
    for f in results:
        _print_campaign(f)
    _print_scaling(results)
    (args.root / "campaign_benchmark.json").write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
