"""Benchmark (issue 24, item 5): 1-s onboard data through ingest, quality and float POD.

The default campaign (config/config.yaml) over three days with the simulator's observation
interval set to 1 s (``simulate.interval_s``: 86 400 epochs a day, 30 times the default
30-s volume; the middle day's 30-h arc reads 108 000 epochs of its three days), run with
Snakemake up to the float POD of the middle day in its own working directory. The POD
samples at ``pod.sampling_s`` (30 s, the schema default): it reads only those epochs of the
daily files (:meth:`leopod.estimation.arc.ArcData.read`), while ingest and quality keep every
epoch (cycle slips, code noise). Printed: wall time and peak memory per job (Snakemake
benchmark files; a job of the warm worker: its fork's peak memory from the job's log), the
epochs and file sizes per day, and the peak memory of reading the arc's files with and
without the decimation (each in a fresh process).

    .venv/bin/python benchmarks/high_rate.py [--root ../scratch-1s] [--cores 2] [--reuse]

``--reuse`` skips Snakemake when the float POD of the middle day exists (figures of the last
run).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import yaml
from _jobs import benchmark_folder, job_figures

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
SAT, DAYS, MIDDLE = "hy2b-sim", ("2019-001", "2019-002", "2019-003"), "2019-002"
#: The default campaign's name and products folder (config/config.yaml).
CAMPAIGN = "hy2b-sim"
RESULTS = f"results/{CAMPAIGN}"
TARGET = f"{RESULTS}/float_pod/{SAT}/{MIDDLE}_orbit.nc"
STEPS = ("simulate", "gnss_products", "ingest", "quality", "code_bias", "float_pod")

# reads the arc's daily files as the float POD does, in a fresh process; prints JSON
_READ = """
import json, resource, sys, time
from leopod.estimation.arc import ArcData
days, step = json.loads(sys.argv[1]), json.loads(sys.argv[2])
files = {{"obs": [f"{results}/ingest/{sat}/{{d}}_obs.nc" for d in days],
          "quality": [f"{results}/quality/{sat}/{{d}}.nc" for d in days],
          "leo": [f"{results}/ingest/{sat}/{{d}}_leo.nc" for d in days],
          "orbit": [f"{results}/gnss_products/{{d}}_orbit.nc" for d in days],
          "clock": [f"{results}/gnss_products/{{d}}_clock.nc" for d in days]}}
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
tic = time.perf_counter()
data = ArcData.read(files, sampling_s=step)
wall = time.perf_counter() - tic
for q in data.quality:
    q.load()            # the POD reads these variables (pass ids, angles) too
print(json.dumps({{"wall_s": wall, "import_mb": base,
                  "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                  "epochs": [int(o.sizes["time"]) for o in data.obs],
                  "data_mb": sum(ds.nbytes for ds in (*data.obs, *data.quality)) / 1e6}}))
""".format(sat=SAT, results=RESULTS)


def _config() -> dict:
    cfg = yaml.safe_load((REPO / "config" / "config.yaml").read_text())
    cfg["start_date"], cfg["end_date"] = "2019-01-01", "2019-01-03"
    cfg["simulate"]["interval_s"] = 1.0
    if cfg["campaign"] != CAMPAIGN:
        raise ValueError(f"config/config.yaml: campaign {cfg['campaign']!r}, not {CAMPAIGN!r}")
    return cfg


def run(work: Path, cores: int, reuse: bool) -> float | None:
    """Run the campaign to the middle day's float POD; the wall time [s] (None if reused)."""
    work.mkdir(parents=True, exist_ok=True)
    (work / "campaign.yaml").write_text(yaml.safe_dump(_config()))
    if reuse and (work / TARGET).exists():
        return None
    tic = time.perf_counter()
    subprocess.run([SNAKEMAKE, "--snakefile", str(REPO / "Snakefile"), "--directory",
                    str(work), TARGET, "--cores", str(cores), "--configfile",
                    str(work / "campaign.yaml")], check=True, capture_output=True)
    return time.perf_counter() - tic


def read_figures(work: Path, sampling_s: float | None) -> dict:
    """Figures of reading the arc's files in a fresh process (:data:`_READ`)."""
    proc = subprocess.run([sys.executable, "-c", _READ, json.dumps(list(DAYS)),
                           json.dumps(sampling_s)], cwd=work, check=True, capture_output=True,
                          text=True)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", type=Path, default=REPO.parent / "scratch-1s")
    ap.add_argument("--cores", type=int, default=2)
    ap.add_argument("--reuse", action="store_true")
    args = ap.parse_args()
    work = args.root.resolve()
    wall = run(work, args.cores, args.reuse)
    print(f"1-s campaign in {work}: "
          + (f"{wall / 60:.1f} min to the float POD of {MIDDLE}" if wall else "reused"))
    print(f"{'job':<32s} {'wall s':>8s} {'peak MB':>8s}")
    for step in STEPS:
        folder = benchmark_folder(work, CAMPAIGN) / step
        for tsv in sorted(folder.rglob("*.tsv")):
            s, mb = job_figures(work, tsv)
            name = f"{step} {tsv.relative_to(folder).with_suffix('')}"
            print(f"{name:<32s} {s:8.1f} {mb:8.0f}")
    for day in DAYS:
        sizes = {kind: (work / RESULTS / kind).stat().st_size / 1e6 for kind in
                 (f"ingest/{SAT}/{day}_obs.nc", f"ingest/{SAT}/{day}_gnss.nc",
                  f"quality/{SAT}/{day}.nc")}
        print(f"{day}: " + ", ".join(f"{k} {v:.0f} MB" for k, v in sizes.items()))
    print("\nreading the arc's observation and quality files as the float POD does:")
    for step in (None, 30.0):
        f = read_figures(work, step)
        label = "every epoch" if step is None else f"sampling {step:g} s"
        print(f"  {label:<14s}: epochs per day {f['epochs']}, {f['data_mb']:.0f} MB of arrays, "
              f"{f['wall_s']:.1f} s, peak memory {f['peak_mb']:.0f} MB "
              f"(after the imports {f['import_mb']:.0f} MB)")


if __name__ == "__main__":
    main()
