"""Benchmark (issue 24, item 5): a 30-day campaign with 3 bad days finishes the other 27.

The default campaign (config/config.yaml) over N days (default 30, from 2019-01-01) is
simulated, its files copied to ``<root>/files`` and read from there as a real campaign's
(source ``files``), with three days broken:

- day 6: the RINEX file cut in the middle of an epoch record (a truncated download);
- day 15: the GNSS orbit product (SP3) missing;
- day 24: the receiver stopped after 20 minutes (a valid RINEX file with 40 epochs: the day's
  data cannot give its orbit).

Then ``leopod run --exclude-failed`` (Snakemake ``--keep-going``; the days with a failed job are
left out, config ``exclude_days``, and the campaign runs again until no new day fails) and
``leopod status``. Printed: wall time of the simulation and of the campaign, jobs per pass, the
failed days with their reasons, the days with an orbit, and the quality-gate list of the
campaign summary.

    .venv/bin/python benchmarks/bad_days.py [--root ../scratch-30d] [--days 30] [--cores 2]
"""

from __future__ import annotations

import argparse
import datetime as dt
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import yaml

REPO = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent
SAT = "hy2b-sim"
START = dt.date(2019, 1, 1)


def _day(k: int) -> str:
    """Day id of the k-th campaign day (1-based)."""
    return (START + dt.timedelta(days=k - 1)).strftime("%Y-%j")


def _config(days: int, files: Path | None = None) -> dict:
    cfg = yaml.safe_load((REPO / "config" / "config.yaml").read_text())
    cfg["start_date"] = START.isoformat()
    cfg["end_date"] = (START + dt.timedelta(days=days - 1)).isoformat()
    if files is not None:
        sat = cfg["satellites"][SAT]
        sat["source"] = "files"
        sat["observations"] = str(files / "{sat}/{date}.rnx")
        cfg["products"].update(gnss_orbit=str(files / "gnss/{date}.sp3"),
                               gnss_clock=str(files / "gnss/{date}_int.clk"),
                               wl_bias=str(files / "gnss/{date}.wsb"),
                               dcb_p1c1=str(files / "gnss/{date}_p1c1.dcb"))
    return cfg


def _cut_mid_record(rnx: Path) -> None:
    lines = rnx.read_text().splitlines(keepends=True)
    rnx.write_text("".join(lines[: len(lines) // 2 + 3]))


def _stop_after(rnx: Path, minutes: int) -> None:
    """Keep the header and the epochs before ``minutes`` past midnight (RINEX 3 '>' records)."""
    out = []
    for line in rnx.read_text().splitlines(keepends=True):
        if line.startswith(">"):
            hour, minute = int(line[13:15]), int(line[16:18])
            if hour * 60 + minute >= minutes:
                break
        out.append(line)
    rnx.write_text("".join(out))


def break_days(files: Path) -> dict[str, str]:
    """Break three days of the copied files; day -> what was done."""
    bad = {_day(6): "RINEX cut in the middle of an epoch record",
           _day(15): "GNSS orbit product (SP3) missing",
           _day(24): "receiver stopped after 20 min"}
    _cut_mid_record(files / SAT / f"{_day(6)}.rnx")
    (files / "gnss" / f"{_day(15)}.sp3").unlink()
    _stop_after(files / SAT / f"{_day(24)}.rnx", 20)
    return bad


def _timed(cmd: list[str], log: Path) -> tuple[float, int, str]:
    tic = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    log.write_text(proc.stdout + proc.stderr)
    return time.perf_counter() - tic, proc.returncode, proc.stdout + proc.stderr


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", type=Path, default=REPO.parent / "scratch-30d")
    ap.add_argument("--days", type=int, default=30)
    ap.add_argument("--cores", type=int, default=2)
    args = ap.parse_args()
    work = args.root.resolve()
    work.mkdir(parents=True, exist_ok=True)
    sim = work / "simulate.yaml"
    sim.write_text(yaml.safe_dump(_config(args.days)))
    wall, code, out = _timed([str(BIN / "snakemake"), "--snakefile", str(REPO / "Snakefile"),
                              "--directory", str(work), "--cores", str(args.cores), "--until",
                              "simulate", "simulate_gnss", "--configfile", str(sim)],
                             work / "simulate.log")
    if code:
        sys.exit(f"simulation failed:\n{out[-3000:]}")
    print(f"simulation of {args.days} days: {wall / 60:.1f} min")
    files = work / "files"
    shutil.rmtree(files, ignore_errors=True)
    shutil.copytree(work / "resources/hy2b-sim/simulate", files)
    for day, what in break_days(files).items():
        print(f"  broken: {day}  {what}")
    campaign = work / "campaign.yaml"
    campaign.write_text(yaml.safe_dump(_config(args.days, files)))
    (work / "results/hy2b-sim/failed_days.yaml").unlink(missing_ok=True)
    wall, code, out = _timed([str(BIN / "leopod"), "run", str(campaign), "--directory", str(work),
                              "--cores", str(args.cores), "--exclude-failed"], work / "run.log")
    passes = re.findall(r"(\d+) of (\d+) steps \((\d+)%\) done", out)
    totals = [m for m in re.findall(r"^total\s+(\d+)$", out, flags=re.M)]
    print(f"\nleopod run --exclude-failed: {wall / 60:.1f} min, exit {code}; jobs planned per "
          f"pass {totals}, last progress line per pass: "
          + ", ".join(f"{a}/{b}" for a, b, _ in passes[-3:]))
    print("\n".join(line for line in out.splitlines()
                    if re.match(r"^\s+\d{4}-\d{3}\s|^\d+ day\(s\) failed|^campaign |"
                                r"^\s+\S+ (float|fixed)_pod: ", line)))
    html = work / f"results/hy2b-sim/summary/{SAT}.html"
    if html.exists():
        items = re.findall(r"<li>(.*?)</li>", html.read_text())
        print(f"\ncampaign summary ({html}): {len(items)} day(s) in the quality-gate list")
        for item in items:
            print(f"  {item}")


if __name__ == "__main__":
    main()
