"""Progress lines of ``leopod run --progress`` (leopod.workflow.progress).

Authority: Snakemake itself (the version installed with leopod) running a three-job
workflow written here: the progress lines must follow its own step counter, name every job and
its wildcards, and pass its error report through.
"""

from __future__ import annotations

import io
import re
import sys
from pathlib import Path

from leopod.workflow.progress import RunProgress, run_with_progress

SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
WORKFLOW = """
rule all:
    input: expand("out/{i}.txt", i=range(3))
rule make:
    output: "out/{i}.txt"
    log: "logs/{i}.log"
    shell: "test {wildcards.i} != {fail} || {{ echo boom > {log}; exit 3; }}; echo {wildcards.i} > {output}"
"""


def _run(tmp_path: Path, fail: int, *extra: str) -> tuple[int, list[str]]:
    (tmp_path / "Snakefile").write_text(WORKFLOW.replace("{fail}", str(fail)))
    out = io.StringIO()
    status = run_with_progress([SNAKEMAKE, "--cores", "1", "--directory", str(tmp_path),
                                "--snakefile", str(tmp_path / "Snakefile"), *extra], out)
    return status, out.getvalue().splitlines()


def test_progress_counts_every_job_of_a_real_run(tmp_path):
    status, lines = _run(tmp_path, -1)
    assert status == 0
    done = [re.match(r"\[(\d+)/(\d+)\s+(\d+)%\] done  (\S+)(.*)$", x) for x in lines]
    done = [m for m in done if m]
    assert [int(m.group(1)) for m in done] == [1, 2, 3, 4]
    assert {int(m.group(2)) for m in done} == {4}
    assert done[-1].group(3) == "100" and done[-1].group(4) == "all"
    starts = sorted(x.split("start ")[1] for x in lines if "] start " in x)
    assert starts == ["all", "make  i=0", "make  i=1", "make  i=2"]
    assert lines[-1].startswith("Complete log(s): ")           # Snakemake's whole log
    assert not any("reason:" in x or "jobid:" in x for x in lines)   # the rest stays there


def test_progress_passes_the_error_of_a_failed_job_through(tmp_path):
    status, lines = _run(tmp_path, 1, "--keep-going")
    assert status != 0
    text = "\n".join(lines)
    assert "Error in rule make:" in text and "logs/1.log" in text
    assert (tmp_path / "logs/1.log").read_text() == "boom\n"
    assert sum("] done  make" in x for x in lines) == 2       # the two other jobs finished


def test_a_dry_run_shows_the_job_table():
    progress = RunProgress()
    shown = [y for x in ("Building DAG of jobs...", "Job stats:", "job      count",
                         "-----  -------", "make         3", "all          1",
                         "total        4", "", "reason: Missing output files")
             for y in progress.feed(x)]
    assert shown[0] == "Job stats:" and shown[-1] == "total        4"
    assert progress.total == 4
