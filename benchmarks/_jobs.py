"""Figures of one workflow job from its Snakemake benchmark file and its log (benchmark scripts).

A job the warm worker ran (leopod.workflow.worker) is measured twice: its benchmark file
(logs/benchmarks/<rule>/...) times the job process, whose wall time is the job's but whose
memory is that of a process waiting for the worker's fork; the fork writes its own peak memory
as the last line of the job's log (logs/<rule>/..., leopod.workflow.worker.FINISHED).
"""

from __future__ import annotations

import re
from pathlib import Path

import pandas as pd

BENCHMARKS = Path("logs/benchmarks")
"""Folder of the rules' benchmark files in a Snakemake working directory."""
_WORKER_PEAK = re.compile(r"worker job finished: exit -?\d+, [\d.]+ s, peak memory (\d+) MB")


def job_figures(work: Path, tsv: Path) -> tuple[float, float]:
    """Wall time [s] and peak memory [MB] of the job whose benchmark file is ``tsv``.

    Parameters
    ----------
    work : Path
        The Snakemake working directory.
    tsv : Path
        The job's benchmark file, below ``work / BENCHMARKS``.
    """
    bench = pd.read_csv(tsv, sep="\t")
    log = (work / "logs" / tsv.relative_to(work / BENCHMARKS)).with_suffix(".log")
    found = _WORKER_PEAK.findall(log.read_text()) if log.exists() else []
    peak = float(found[-1]) if found else float(
        pd.to_numeric(bench["max_rss"], errors="coerce").iloc[-1])
    return float(bench["s"].iloc[-1]), peak
