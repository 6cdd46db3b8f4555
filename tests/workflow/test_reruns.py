"""Partial reruns of a campaign: what Snakemake plans after a change, and only that.

A two-satellite, four-day simulated campaign across a month boundary (two monthly code-bias
periods) is "completed" without computing anything: every output is created empty and
``snakemake --touch --forceall`` records the provenance of every job (parameters, input set,
code). Each test then changes one thing and asks ``snakemake -n`` which jobs it would run.

Authority for the expected job sets: the data flow of the workflow (DESIGN.md section 2 and
the rules' inputs): a POD setting feeds float_pod, ambiguity and fixed_pod of every arc; a
satellite's settings feed only its own jobs; a day's observations enter its own ingest and
quality, the code-bias map of its month, and the arcs that contain the day (30-h arcs reach
3 h into both neighbouring days); a library module reruns the steps whose scripts import it.

The workflow runs from a copy of the repository's workflow files and leopod sources (fixture
``checkout``), so that a test can edit a library file without touching the checkout the tests
run from.
"""

from __future__ import annotations

import copy
import os
import re
import shutil
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

import pytest
import yaml
from _campaign_config import default_config

REPO = Path(__file__).resolve().parents[2]
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
#: What a copy of the workflow needs: the Snakefile and what it reads, and the leopod sources
#: whose files the rules list as inputs (leopod.workflow.campaign.library_root).
WORKFLOW_FILES = ("Snakefile", "workflow", "scripts", "config", "profiles", "envs", "src/leopod")
SATS = ("hy2b-sim", "leo2-sim")
DAYS = ("2019-030", "2019-031", "2019-032", "2019-033")  # 30 Jan to 2 Feb 2019


def _config(**changes) -> dict:
    cfg = default_config(start_date="2019-01-30", end_date="2019-02-02", **changes)
    second = copy.deepcopy(cfg["satellites"]["hy2b-sim"])
    second.update(name="LEO-2 (simulated)", simulate_orbit={"altitude_km": 500.0, "ltan_h": 14.0})
    cfg["satellites"]["leo2-sim"] = second
    return cfg


def _snakemake(checkout: Path, work: Path, cfg: dict, *args: str) -> str:
    path = work / "campaign.yaml"
    path.write_text(yaml.safe_dump(cfg))
    proc = subprocess.run([SNAKEMAKE, "--snakefile", str(checkout / "Snakefile"), "--directory",
                           str(work), *args, "--configfile", str(path)],
                          check=False, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return proc.stdout + proc.stderr


def _planned(checkout: Path, work: Path, cfg: dict) -> list[tuple[str, dict]]:
    """(rule, wildcards) of every job ``snakemake -n`` of the workflow in ``checkout`` would
    run."""
    out = _snakemake(checkout, work, cfg, "-n")
    jobs = []
    for block in re.split(r"\n(?=\[.*\]\n\s*rule |\s*rule )", out):
        rule = re.search(r"rule (\w+):", block)
        if rule is None:
            continue
        wildcards = re.search(r"wildcards: (.*)", block)
        pairs = dict(p.split("=", 1) for p in wildcards.group(1).split(", ")) if wildcards else {}
        jobs.append((rule.group(1), pairs))
    return jobs


def _count(jobs) -> Counter:
    return Counter(rule for rule, _ in jobs)


@pytest.fixture(scope="module")
def checkout(tmp_path_factory) -> Path:
    """A copy of the repository's workflow and leopod sources (modification times kept)."""
    root = tmp_path_factory.mktemp("checkout")
    for name in WORKFLOW_FILES:
        source = REPO / name
        if source.is_dir():
            shutil.copytree(source, root / name, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            shutil.copy2(source, root / name)
    return root


@pytest.fixture(scope="module")
def completed(checkout, tmp_path_factory) -> Path:
    """A work directory where every job of the campaign counts as done (empty outputs)."""
    work = tmp_path_factory.mktemp("campaign")
    summary = _snakemake(checkout, work, _config(), "--summary")
    for line in summary.splitlines()[1:]:
        name = line.split("\t")[0]
        if name.startswith(("results/", "resources/")):
            (work / name).parent.mkdir(parents=True, exist_ok=True)
            (work / name).touch()
    # one product larger than Snakemake's default checksum limit (1 MB)
    (work / "resources/hy2b-sim/simulate/gnss/2019-031.sp3").write_bytes(b"*" * 2_000_000)
    _snakemake(checkout, work, _config(), "--touch", "--forceall", "--cores", "1")
    assert _planned(checkout, work, _config()) == []  # nothing left to do
    return work


@pytest.fixture()
def work(completed, tmp_path) -> Path:
    """A private copy of the completed campaign (modification times kept)."""
    copy = tmp_path / "work"
    shutil.copytree(completed, copy, symlinks=True)
    return copy


DOWNSTREAM_OF_POD = {"float_pod", "ambiguity", "fixed_pod", "overlap", "reference_orbit", "slr",
                     "overlap_summary", "reference_summary", "slr_summary", "campaign_summary",
                     "all"}


def test_a_pod_setting_reruns_pod_and_validation_only(checkout, work):
    jobs = _planned(checkout, work, _config(**{"pod.outlier_k": 4.0}))
    counts = _count(jobs)
    assert set(counts) == DOWNSTREAM_OF_POD
    assert counts["float_pod"] == counts["fixed_pod"] == len(SATS) * len(DAYS)
    assert counts["overlap"] == len(SATS) * (len(DAYS) - 1)   # float and fixed in one job
    # the dry run gives the reason: float_pod's parameters changed, the rest follows
    out = _snakemake(checkout, work, _config(**{"pod.outlier_k": 4.0}), "-n")
    assert "Params have changed since last execution" in out


def test_an_ambiguity_setting_keeps_the_float_solution(checkout, work):
    jobs = _planned(checkout, work, _config(**{"ambiguity.nl_max_dev_cyc": 0.1}))
    counts = _count(jobs)
    assert "float_pod" not in counts
    assert counts["ambiguity"] == counts["fixed_pod"] == len(SATS) * len(DAYS)
    # a validation job compares both solutions of its day: the float orbit's comparisons are
    # made again with the fixed one's (from the same float files, the same numbers)
    assert counts["reference_orbit"] == counts["slr"] == len(SATS) * len(DAYS)


def test_a_satellite_setting_reruns_that_satellite_only(checkout, work):
    cfg = _config()
    cfg["satellites"]["leo2-sim"]["antenna_pco_body_m"]["L1"] = [0.0, 0.0, -0.30]
    jobs = _planned(checkout, work, cfg)
    assert {w["sat"] for _, w in jobs if "sat" in w} == {"leo2-sim"}
    # the antenna offset enters the simulated observations, so everything of leo2-sim from
    # its simulate jobs on, but not the shared world (GNSS products, biases)
    counts = _count(jobs)
    assert counts["simulate"] == counts["ingest"] == counts["float_pod"] == len(DAYS)
    assert "simulate_gnss" not in counts and "simulate_world" not in counts


def test_the_code_bias_period_reruns_maps_and_everything_downstream(checkout, work):
    jobs = _planned(checkout, work, _config(**{"code_bias.period": "campaign"}))
    counts = _count(jobs)
    assert {w["period"] for r, w in jobs if r == "code_bias"} == {"campaign"}
    assert counts["code_bias"] == len(SATS)
    assert counts["float_pod"] == len(SATS) * len(DAYS)
    assert not {"simulate", "simulate_gnss", "ingest", "quality"} & set(counts)


def test_new_observations_of_one_day_rerun_what_uses_that_day(checkout, work):
    # a replaced RINEX file of leo2-sim on 2019-032 (1 February): new content and time (a
    # newer file with the checksum Snakemake recorded would not count as changed)
    rinex = work / "resources/hy2b-sim/simulate/leo2-sim/2019-032.rnx"
    rinex.write_text("new observations\n")
    later = time.time() + 3600
    os.utime(rinex, (later, later))
    jobs = _planned(checkout, work, _config())
    per_day = {(r, w["date"]) for r, w in jobs if "date" in w}
    assert {w["sat"] for _, w in jobs if "sat" in w} == {"leo2-sim"}
    assert {("ingest", "2019-032"), ("quality", "2019-032")} <= per_day
    assert not {d for r, d in per_day if r in ("ingest", "quality")} - {"2019-032"}
    # the February map changes; the January map and the arc of 30 January do not
    assert {w["period"] for r, w in jobs if r == "code_bias"} == {"2019-02"}
    assert {d for r, d in per_day if r == "float_pod"} == {"2019-031", "2019-032", "2019-033"}
    # the overlap 30/31 January compares with the new arc of the 31st
    assert {d for r, d in per_day if r == "overlap"} == set(DAYS[:-1])


def test_a_library_change_reruns_the_steps_that_import_it(checkout, work):
    # screening.py is imported by scripts/fixed_pod.py alone (leopod.workflow.campaign.
    # script_library_files). The rules list the sources of the checkout the Snakefile is in
    # (here the copy), so the copy's file is changed. Snakemake compares the content of small
    # inputs, not only their time, so a comment line is appended for the dry run; bytes and
    # time are put back for the other tests of the module, which share the copy.
    module = checkout / "src/leopod/ambiguity/screening.py"
    original, stat = module.read_bytes(), module.stat()
    try:
        module.write_bytes(original + b"# changed\n")
        counts = _count(_planned(checkout, work, _config()))
    finally:
        module.write_bytes(original)
        os.utime(module, ns=(stat.st_atime_ns, stat.st_mtime_ns))
    assert counts["fixed_pod"] == len(SATS) * len(DAYS)
    assert not {"float_pod", "ambiguity", "quality", "ingest"} & set(counts)


def test_an_interrupted_campaign_resumes_where_it_stopped(checkout, work):
    # the run stopped during the fixed POD of hy2b-sim on 2 February: its outputs and those
    # of its ambiguity fixing are missing, everything else is done
    for path in (work / "results/hy2b-sim/fixed_pod/hy2b-sim").glob("2019-033*"):
        path.unlink()
    (work / "results/hy2b-sim/ambiguity/hy2b-sim/2019-033.nc").unlink()
    jobs = _planned(checkout, work, _config())
    per_day = {(r, w.get("sat"), w.get("date")) for r, w in jobs if "date" in w}
    assert per_day == {("ambiguity", "hy2b-sim", "2019-033"),
                       ("fixed_pod", "hy2b-sim", "2019-033"),
                       ("overlap", "hy2b-sim", "2019-032"),
                       ("reference_orbit", "hy2b-sim", "2019-033"),
                       ("slr", "hy2b-sim", "2019-033")}


def test_the_slurm_profile_renders_grouped_jobs_without_slurm(tmp_path):
    # profiles/slurm: the POD chain of each satellite-day is one group job ("pod"), the short
    # per-day steps are grouped by up to 10 components ("prepare"); -n needs no SLURM.
    cfg = _config()
    path = tmp_path / "campaign.yaml"
    path.write_text(yaml.safe_dump(cfg))
    proc = subprocess.run([SNAKEMAKE, "--snakefile", str(REPO / "Snakefile"), "--profile",
                           str(REPO / "profiles/slurm"), "-n", "--directory", str(tmp_path),
                           "--configfile", str(path)],
                          check=False, capture_output=True, text=True, timeout=600)
    out = proc.stdout + proc.stderr
    assert proc.returncode == 0, out[-3000:]
    assert out.count("Group job pod") == len(SATS) * len(DAYS)
    # 8 satellite-days of simulate/ingest/quality in blocks of 10 components
    assert out.count("Group job prepare") == 1
    assert "runtime=" in out and "mem_mb=" in out


def test_an_identical_newer_input_does_not_rerun(checkout, work):
    # a product fetched again with the same 2 MB (newer time) is compared by checksum
    # (profiles/default: max-checksum-file-size; Snakemake's default limit is 1 MB), so
    # nothing reruns
    sp3 = work / "resources/hy2b-sim/simulate/gnss/2019-031.sp3"
    later = time.time() + 3600
    os.utime(sp3, (later, later))
    assert _planned(checkout, work, _config()) == []
