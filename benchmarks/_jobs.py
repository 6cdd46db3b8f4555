"""Figures of one workflow job from its Snakemake benchmark file and its log (benchmark scripts).

A job the warm worker ran (leopod.workflow.worker) is measured twice: its benchmark file
(logs/<campaign>/benchmarks/<rule>/...) times the job process, whose wall time is the job's but
whose memory is that of a process waiting for the worker's fork; the fork writes its own peak
memory as the last line of the job's log (logs/<campaign>/<rule>/...,
leopod.workflow.worker.FINISHED).
"""

from __future__ import annotations

import re
from pathlib import Path

import pandas as pd

from leopod.workflow.layout import Layout

_WORKER_PEAK = re.compile(r"worker job finished: exit -?\d+, [\d.]+ s, peak memory (\d+) MB")


def benchmark_folder(work: Path, campaign: str) -> Path:
    """Folder of the rules' benchmark files of a campaign in a Snakemake working directory."""
    return work / Layout(campaign).benchmarks


def job_figures(work: Path, tsv: Path) -> tuple[float, float]:
    """Wall time [s] and peak memory [MB] of the job whose benchmark file is ``tsv``.

    Parameters
    ----------
    work : Path
        The Snakemake working directory.
    tsv : Path
        The job's benchmark file, below ``logs/<campaign>/benchmarks/`` of ``work``.
    """
    bench = pd.read_csv(tsv, sep="\t")
    campaign, _, *rest = tsv.relative_to(work / "logs").parts
    log = work.joinpath("logs", campaign, *rest).with_suffix(".log")
    found = _WORKER_PEAK.findall(log.read_text()) if log.exists() else []
    peak = float(found[-1]) if found else float(
        pd.to_numeric(bench["max_rss"], errors="coerce").iloc[-1])
    return float(bench["s"].iloc[-1]), peak
