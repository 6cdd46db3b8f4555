"""Benchmark: float and ambiguity-fixed POD of one simulated day of the default campaign.

Prepares the day's inputs with the workflow (``snakemake
results/<campaign>/ambiguity/<sat>/<date>.nc`` in the working directory ``--directory``, default
the repository; the float POD runs once there), then runs the float_pod, ambiguity and fixed_pod jobs of that day with their scripts,
in-process as Snakemake would (:func:`leopod.workflow.boundary.mock_snakemake`: same inputs,
settings and outputs), each step ``--repeat`` times in a fresh process, and prints per step the
best wall time and the CPU time of that run (the job's process; on a machine shared with other
work the CPU time is the steadier figure), the orbit integrations and force evaluations, and the
peak memory: once for
a job alone and once as in the workflow's warm worker (what the worker loads before it forks a
job, :func:`leopod.workflow.worker.preload`, is loaded first and not timed; the ~0.2 s of the
job process that hands the job over are not included either). The fixed POD's time is what it
adds on top of the float POD and the ambiguity step. As in a workflow
run, the job's process gets its ``threads`` (1 for these rules) in the thread-count variables
of the linear-algebra libraries (``OPENBLAS_NUM_THREADS`` etc., which Snakemake sets for a
script job); a second BLAS thread made a Cholesky factorisation of the POD's normal matrix
up to 0.6 s slower instead of faster on the 2-core development machine.

    .venv/bin/python benchmarks/pod_day.py [--date 2019-002] [--repeat 3] [--directory D]
                                           [--configfile F]

``--configfile`` (with ``--directory``) benchmarks another campaign, e.g. a combined GPS+BDS
one (``pod.system: [G, C]``); the default is config/config.yaml.
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

from _counting import IntegrationCounter

from leopod.workflow.config import read_campaign
from leopod.workflow.layout import Layout

REPO = Path(__file__).resolve().parents[1]
STEPS = ("float_pod", "ambiguity", "fixed_pod")
THREADS = 1
"""``threads`` of the three rules (workflow/rules/pod.smk; checked in each job)."""
#: The variables Snakemake sets to a job's ``threads`` (snakemake.shell).
THREAD_VARIABLES = ("OMP_NUM_THREADS", "GOTO_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                    "MKL_NUM_THREADS", "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")


def _one(step: str, date: str, root: Path, config: Path, sat: str, warm: bool) -> None:
    """Run one job in this process and print its figures as JSON; ``warm``: first load what the
    workflow's warm worker loads before it forks a job (leopod.workflow.worker.preload)."""
    import importlib.util

    from leopod.workflow.boundary import mock_snakemake
    from leopod.workflow.worker import preload

    if warm:
        preload()
    logging.basicConfig(level=logging.WARNING)
    job = mock_snakemake(step, root=root, configfiles=[config], snakefile=REPO / "Snakefile",
                         sat=sat, date=date)
    if job.threads != THREADS:
        raise SystemExit(f"rule {step} has {job.threads} threads: set THREADS")
    for path in [*job.output, *job.log]:   # Snakemake makes these folders before a job
        Path(path).parent.mkdir(parents=True, exist_ok=True)
    spec = importlib.util.spec_from_file_location(step, REPO / "scripts" / f"{step}.py")
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    tic, cpu = time.perf_counter(), time.process_time()
    with IntegrationCounter() as counter:
        script.run(job)
    wall, cpu = time.perf_counter() - tic, time.process_time() - cpu
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps({"wall_s": wall, "cpu_s": cpu, "integrations": counter.integrations,
                      "compiled": counter.compiled, "evaluations": counter.evaluations,
                      "peak_mb": peak_mb}))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--date", default="2019-002")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--directory", type=Path, default=REPO)
    parser.add_argument("--configfile", type=Path, default=REPO / "config" / "config.yaml")
    parser.add_argument("--sat", help="POD line (satellite id or <sat>_<variant>); default: "
                        "the first satellite of the campaign")
    parser.add_argument("--step", choices=STEPS, help=argparse.SUPPRESS)   # internal
    parser.add_argument("--warm", action="store_true", help=argparse.SUPPRESS)   # internal
    args = parser.parse_args()
    root = args.directory.resolve()
    if args.sat is None:
        from leopod.workflow.config import load_campaign

        args.sat = next(iter(load_campaign(args.configfile)["satellites"]))
    if args.step:
        _one(args.step, args.date, root, args.configfile.resolve(), args.sat, args.warm)
        return
    results = Layout.of(read_campaign(args.configfile)).results
    target = f"{results}/ambiguity/{args.sat}/{args.date}.nc"
    subprocess.run([str(Path(sys.executable).with_name("snakemake")), target, "--cores", "2",
                    "--snakefile", str(REPO / "Snakefile"), "--directory", str(root),
                    "--configfile", str(args.configfile.resolve())],
                   check=True, capture_output=True)
    print(f"{args.configfile.name}, {args.sat} {args.date}: best of {args.repeat} runs per step")
    env = {**os.environ, **dict.fromkeys(THREAD_VARIABLES, str(THREADS))}
    for warm in (False, True):
        print("in the warm worker (imports, kernels, EOP preloaded; leopod.workflow.worker)"
              if warm else "alone (a process of its own, imports not timed)")
        for step in STEPS:
            runs = []
            for _ in range(args.repeat):
                out = subprocess.run([sys.executable, __file__, "--step", step, "--date",
                                      args.date, "--directory", str(root), "--sat", args.sat,
                                      "--configfile", str(args.configfile.resolve()),
                                      *(["--warm"] if warm else [])], check=True,
                                     capture_output=True, text=True, cwd=REPO / "benchmarks",
                                     env=env)
                runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
            best = min(runs, key=lambda r: r["wall_s"])
            print(f"  {step:10s} wall {best['wall_s']:6.2f} s (CPU {best['cpu_s']:6.2f} s)  "
                  f"{best['integrations']} "
                  f"integrations ({best['compiled']} compiled), {best['evaluations']} force "
                  f"evaluations, peak memory {best['peak_mb']:.0f} MB")


if __name__ == "__main__":
    main()
