"""The SLURM profile on a real one-node SLURM cluster (issue 23, item 6).

A one-node cluster (slurmctld + slurmd on this machine, leopod.workflow.local_slurm) runs the
one-day simulated campaign through ``leopod run --profile slurm``; the same campaign runs
locally. Authority: the profile's own promises (profiles/slurm/config.yaml: per-day group jobs
``prepare`` and ``pod``, the rules' threads and memory requested from SLURM, ``retries: 1``
after a node failure or preemption) and the local run, whose outputs the cluster run must
reproduce byte for byte. Skipped where SLURM is not installed or this is not root (Debian:
``apt-get install slurmctld slurmd slurm-client munge``).
"""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
import yaml
from _campaign_config import default_config, output_digests

from leopod.workflow import local_slurm

LEOPOD = str(Path(sys.executable).with_name("leopod"))
#: Both runs write the same `history` time (leopod.io.provenance follows SOURCE_DATE_EPOCH,
#: https://reproducible-builds.org/specs/source-date-epoch/; 2019-01-01 00:00:00 UTC).
REPRODUCIBLE = {"SOURCE_DATE_EPOCH": "1546300800"}

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(not local_slurm.available(),
                       reason="needs root and SLURM (apt-get install slurmctld slurmd "
                              "slurm-client munge)"),
]


def _campaign(folder: Path) -> Path:
    folder.mkdir()
    path = folder / "one.yaml"
    path.write_text(yaml.safe_dump(default_config(end_date="2019-01-01",
                                                  **{"code_bias.min_count": 40})))
    return path


def _cancel_first(rule_part: str, env: dict, done: threading.Event, cancelled: list) -> None:
    """Cancel (scancel) the first running SLURM job whose comment (the rule or group of the
    Snakemake job) starts with ``rule_part``, as a preemption would; its id goes to
    ``cancelled``."""
    while not done.is_set():
        out = subprocess.run(["squeue", "-h", "-t", "RUNNING", "-o", "%i %k"], env=env,
                             capture_output=True, text=True).stdout
        for line in out.splitlines():
            job, _, comment = line.partition(" ")
            if comment.startswith(rule_part):
                subprocess.run(["scancel", job], env=env, check=True)
                cancelled.append(job)
                return
        time.sleep(0.5)


def test_the_one_day_campaign_on_a_slurm_cluster_equals_a_local_run(tmp_path):
    local = _campaign(tmp_path / "local")
    proc = subprocess.run([LEOPOD, "run", str(local), "--directory", str(local.parent),
                           "--cores", "2"], capture_output=True, text=True, timeout=1800,
                          env={**os.environ, **REPRODUCIBLE})
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]

    cluster = tmp_path / "cluster"
    env = {**os.environ, **REPRODUCIBLE, **local_slurm.start(cluster)}
    try:
        slurm = _campaign(tmp_path / "slurm")
        done, cancelled = threading.Event(), []
        # the group job of the day's short steps is cancelled once while it runs
        canceller = threading.Thread(target=_cancel_first,
                                     args=("rule_prepare_", env, done, cancelled))
        canceller.start()
        start = time.monotonic()
        proc = subprocess.run(
            [LEOPOD, "run", str(slurm), "--directory", str(slurm.parent), "--profile", "slurm",
             "--", "--slurm-status-command", "squeue", "--slurm-no-account",
             "--slurm-init-seconds-before-status-checks", "2"],
            capture_output=True, text=True, timeout=3600, env=env)
        wall = time.monotonic() - start
        done.set()
        canceller.join()
        jobs = subprocess.run(["squeue", "-h", "-t", "all", "-o", "%i|%k|%T|%C|%m"], env=env,
                              capture_output=True, text=True, check=True).stdout
    finally:
        local_slurm.stop(cluster)
    log = proc.stdout + proc.stderr
    assert proc.returncode == 0, log[-5000:]
    rows = [line.split("|") for line in jobs.splitlines()]
    print(f"SLURM run: {len(rows)} SLURM jobs, {wall:.0f} s wall")
    # the groups hold the rules the profile puts in them (the plugin's job comment:
    # rule_<group>_<rules in lexicographic order>), one SLURM job per group and day
    prepare = [r for r in rows if r[1].startswith("rule_prepare_")]
    pod = [r for r in rows if r[1].startswith("rule_pod_")]
    assert {r[1] for r in prepare} == {
        "rule_prepare_gnss_products_ingest_quality_simulate_simulate_gnss"}
    assert [r[1] for r in pod] == ["rule_pod_ambiguity_fixed_pod_float_pod_reference_orbit_slr"]
    # retries: 1 — the cancelled group job was submitted again and finished
    assert len(cancelled) == 1
    assert sorted(r[2] for r in prepare) == ["CANCELLED", "COMPLETED"]
    # resources: a single-rule job asks SLURM for its rule's memory and threads
    # (workflow/rules/simulate.smk: simulate_truth mem_mb 2000, threads 1)
    (truth,) = [r for r in rows if r[1].startswith("rule_simulate_truth")]
    assert truth[2] == "COMPLETED" and truth[3] == "1" and truth[4] == "2000M"
    assert all(r[2] == "COMPLETED" for r in rows if r[0] not in cancelled)
    # the same bytes as the local run, every file of results/ and resources/
    a, b = output_digests(local.parent), output_digests(slurm.parent)
    assert len(a) > 60 and a.keys() == b.keys()
    assert [name for name in a if a[name] != b[name]] == []
