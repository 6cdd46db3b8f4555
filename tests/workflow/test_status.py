"""Failed jobs and days read back from the job logs (leopod.workflow.status, leopod status).

The log lines are those leopod.workflow.log.configure_logging writes (authority: its format
string and its excepthook); the tests write them as a failed job leaves them.
"""

from __future__ import annotations

from pathlib import Path

from leopod.workflow.layout import Layout
from leopod.workflow.status import failed_days, failures, gate_verdicts, orbit_days

STAMP = "2026-11-27 14:00:00,000"
#: The campaign whose logs are read; OTHER: a second campaign of the same directory.
LAYOUT, OTHER = Layout("camp"), Layout("other")


def _log(work: Path, rel: str, rule: str, wildcards: dict, *lines: str,
         layout: Layout = LAYOUT) -> Path:
    path = work / layout.logs / rel
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join([f"{STAMP} INFO root: rule {rule}, wildcards {wildcards}",
                               *lines]) + "\n")
    return path


def test_failures_name_the_step_the_day_and_the_error(tmp_path):
    _log(tmp_path, "ingest/sat/2019-002.log", "ingest", {"sat": "sat", "date": "2019-002"},
         f"{STAMP} ERROR root: step ingest failed: files/sat/2019-002.rnx: line 901, field "
         "'epoch': record cut short")
    _log(tmp_path, "float_pod/sat/2019-004.log", "float_pod", {"sat": "sat", "date": "2019-004"},
         f"{STAMP} INFO leopod.estimation.arc: arc of 2019-004",
         f"{STAMP} ERROR root: step float_pod failed",
         "Traceback (most recent call last):",
         '  File "scripts/float_pod.py", line 1, in <module>',
         "    run(snakemake)",
         "ValueError: no observations between 2019-01-03T21:00 and 2019-01-05T03:00",
         f"{STAMP} INFO leopod.workflow.worker: worker job finished: exit 1, 2.00 s, peak "
         "memory 900 MB")
    _log(tmp_path, "locate/products.gnss_orbit/2019-003/g.sp3.log", "locate",
         {"entry": "products.gnss_orbit", "path": "2019-003/g.sp3"},
         f"{STAMP} ERROR root: step locate failed",
         "FileNotFoundError: input file files/gnss/2019-003.sp3 does not exist")
    # the ingest of the same day failed too (it waits for nothing: a second reason)
    _log(tmp_path, "ingest/sat/2019-003.log", "ingest", {"sat": "sat", "date": "2019-003"},
         f"{STAMP} ERROR root: step ingest failed: no GNSS orbit")
    _log(tmp_path, "code_bias/sat/2019-01.log", "code_bias", {"sat": "sat", "period": "2019-01"},
         f"{STAMP} ERROR root: step code_bias failed: too few observations")
    _log(tmp_path, "kinematic_pod/sat/2019-005.log", "kinematic_pod",
         {"sat": "sat", "date": "2019-005"},
         f"{STAMP} INFO leopod.workflow.worker: worker job finished: exit 2, 2.00 s, peak "
         "memory 900 MB")
    _log(tmp_path, "ingest/sat/2019-001.log", "ingest", {"sat": "sat", "date": "2019-001"},
         f"{STAMP} INFO leopod.workflow.worker: worker job finished: exit 0, 2.00 s, peak "
         "memory 900 MB")
    (tmp_path / LAYOUT.benchmarks / "ingest").mkdir(parents=True)
    (tmp_path / LAYOUT.benchmarks / "ingest/x.log").write_text("step ingest failed: not a job log")
    # a failure of another campaign in the same directory is not this campaign's
    _log(tmp_path, "ingest/sat/2019-001.log", "ingest", {"sat": "sat", "date": "2019-001"},
         f"{STAMP} ERROR root: step ingest failed: the other campaign's", layout=OTHER)

    found = failures(tmp_path, LAYOUT)
    assert sorted(f.rule for f in found) == ["code_bias", "float_pod", "ingest", "ingest",
                                             "kinematic_pod", "locate"]
    by_day = {f.day: f for f in found}
    assert by_day["2019-004"].message == ("ValueError: no observations between "
                                          "2019-01-03T21:00 and 2019-01-05T03:00")
    assert by_day[None].rule == "code_bias"        # a period: no day of its own
    days = [f"2019-00{k}" for k in range(1, 6)]
    failed = failed_days(found, days)
    assert list(failed) == ["2019-002", "2019-003", "2019-004", "2019-005"]
    assert failed["2019-005"].message == "exit status 2 (sys.exit, no error logged)"
    assert failed["2019-002"].reason == ("ingest: files/sat/2019-002.rnx: line 901, field "
                                         "'epoch': record cut short")
    # the first step of the DAG is the reason of a day: the missing product, not its ingest
    assert failed["2019-003"].reason.startswith("locate: FileNotFoundError: input file "
                                                "files/gnss/2019-003.sp3")
    assert failed["2019-003"].log.name == "g.sp3.log"
    assert failed_days(found, ["2019-001"]) == {}
    assert failed["2019-004"].in_pod and not failed["2019-002"].in_pod


def test_orbit_days_are_the_days_with_a_daily_sp3(tmp_path):
    folder = tmp_path / LAYOUT.results / "float_pod/sat"
    folder.mkdir(parents=True)
    (folder / "2019-001.sp3").write_text("")
    (folder / "2019-002_arc.sp3").write_text("")
    other = tmp_path / OTHER.results / "float_pod/sat"
    other.mkdir(parents=True)
    (other / "2019-002.sp3").write_text("")
    assert orbit_days(tmp_path, LAYOUT, "float_pod", "sat", ["2019-001", "2019-002"]) \
        == ["2019-001"]


def test_gate_verdicts_are_those_of_the_pod_logs(tmp_path):
    # leopod.estimation.write.gate_arc logs a verdict other than ok as a warning
    _log(tmp_path, "float_pod/sat/2019-001.log", "float_pod", {"sat": "sat", "date": "2019-001"},
         f"{STAMP} INFO leopod.estimation.write: float POD 2019-001: quality gate ok")
    _log(tmp_path, "float_pod/sat/2019-002.log", "float_pod", {"sat": "sat", "date": "2019-002"},
         f"{STAMP} WARNING leopod.estimation.write: float POD 2019-002: quality gate failed "
         "(coverage_pct 8.3 < 16)")
    days = ["2019-001", "2019-002", "2019-003"]
    assert gate_verdicts(tmp_path, LAYOUT, "float_pod", "sat", days) == {
        "2019-002": "failed (coverage_pct 8.3 < 16)"}
