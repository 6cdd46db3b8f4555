"""Which jobs of a campaign run failed and why, read from their log files (``leopod status``).

With ``--keep-going`` Snakemake finishes every job that does not depend on a failed one, but a
failed day also holds back what needs it: the arcs of its neighbours (30-h arcs read the
neighbouring days), the code-bias map of its period and the campaign summary. The failures
are in the jobs' logs: every step logs ``step <rule> failed: <message>`` (a
:class:`leopod.io.FormatError`: the file, line and field) or ``step <rule> failed`` followed
by the traceback (:func:`leopod.workflow.log.configure_logging`), and its first line names the
rule and wildcards. This module reads them back, assigns each failure to its day and gives
the days to leave out (config ``exclude_days``, or ``exclude_pod_days`` for a day whose POD
failed on usable data) so that a second run finishes the others and the campaign summary
lists the failed days with their reasons.
"""

from __future__ import annotations

import ast
import re
from dataclasses import dataclass
from pathlib import Path

from leopod.workflow.layout import Layout

__all__ = ["POD_STEPS", "STEP_ORDER", "Failure", "failed_days", "failures", "gate_verdicts",
           "orbit_days"]

_RULE = re.compile(r" INFO root: rule (?P<rule>\S+), wildcards (?P<wildcards>\{.*\})$")
_FAILED = re.compile(r" ERROR root: step (?P<rule>\S+) failed(?:: (?P<message>.*))?$")
_LOG_LINE = re.compile(r"^\d{4}-\d{2}-\d{2} \d{2}:\d{2}:\d{2},\d{3} ")
_DAY = re.compile(r"^(?P<date>\d{4}-\d{3})(?:/|$)")
_EXIT = re.compile(r" worker job finished: exit (?P<status>-?\d+),")
_GATE = re.compile(r" WARNING \S+: (?:float|fixed) POD (?P<date>\d{4}-\d{3}): quality gate "
                   r"(?P<verdict>.*)$")
#: Steps in the order of the DAG: the first failed step of a day is its reason.
STEP_ORDER = ("simulate_gnss", "simulate", "locate", "download", "gnss_products", "ingest",
              "quality", "code_bias", "float_pod", "ambiguity", "fixed_pod", "kinematic_pod")
#: The steps of a day's POD: a day failed there has usable data (config exclude_pod_days).
POD_STEPS = ("float_pod", "ambiguity", "fixed_pod", "kinematic_pod")


@dataclass(frozen=True)
class Failure:
    """A failed job.

    Attributes
    ----------
    rule : str
        The job's rule.
    wildcards : dict
        Its wildcards (``sat``, ``date``, ``period``, ``entry``, ``path``, ...).
    message : str
        The error: the message of a FormatError, else the last line of the traceback.
    log : Path
        The job's log file.
    """

    rule: str
    wildcards: dict
    message: str
    log: Path

    @property
    def day(self) -> str | None:
        """The day ``YYYY-DDD`` the job belongs to (its ``date`` wildcard, or the folder of a
        located daily input), None for a job of several days (a period, the campaign)."""
        if "date" in self.wildcards:
            return str(self.wildcards["date"])
        match = _DAY.match(str(self.wildcards.get("path", "")))
        return match["date"] if match else None

    @property
    def in_pod(self) -> bool:
        """True if the job is a POD step (:data:`POD_STEPS`): the day's data passed."""
        return self.rule in POD_STEPS

    @property
    def reason(self) -> str:
        """One line: ``<rule>: <message>``."""
        return f"{self.rule}: {self.message}"


def _message(lines: list[str], start: int, inline: str | None) -> str:
    """The error of a failure logged at ``lines[start]``: its inline message, else the last
    line of the traceback that follows (the exception and its text)."""
    if inline:
        return inline.strip()
    last = ""
    for line in lines[start + 1:]:
        if _LOG_LINE.match(line):
            break
        if line.strip() and not line.startswith(" "):
            last = line.strip()
    return last or "failed (no message in the log)"


def _read_failure(log: Path) -> Failure | None:
    """The failure logged in ``log``, or None if the job did not fail there (a job killed
    from outside, e.g. for memory, logs nothing: it shows as a day without its products)."""
    lines = log.read_text(errors="replace").splitlines()
    rule, wildcards = None, {}
    for k, line in enumerate(lines):
        found = _RULE.search(line)
        if found and rule is None:
            rule = found["rule"]
            try:
                wildcards = dict(ast.literal_eval(found["wildcards"]))
            except (ValueError, SyntaxError):
                wildcards = {}
        failed = _FAILED.search(line)
        if failed:
            return Failure(rule=failed["rule"], wildcards=wildcards,
                           message=_message(lines, k, failed["message"]), log=log)
        ended = _EXIT.search(line)
        if ended and int(ended["status"]) != 0 and rule is not None:
            return Failure(rule=rule, wildcards=wildcards, log=log,
                           message=f"exit status {ended['status']} (sys.exit, no error logged)")
    return None


def failures(directory: str | Path, layout: Layout) -> list[Failure]:
    """Failed jobs of a campaign run in ``directory`` (its ``logs/<campaign>/``; every log
    keeps the last attempt of its job), in the order of their log paths.

    Parameters
    ----------
    directory : str or Path
        The Snakemake working directory.
    layout : Layout
        The campaign's folders (:mod:`leopod.workflow.layout`).
    """
    logs = Path(directory) / layout.logs
    found = []
    for log in sorted(logs.rglob("*.log")):
        if log.relative_to(logs).parts[0] == "benchmarks":
            continue
        failure = _read_failure(log)
        if failure is not None:
            found.append(failure)
    return found


def failed_days(found: list[Failure], days: list[str]) -> dict[str, Failure]:
    """Day -> its failure (the first failed step of the day in the DAG's order) of the
    ``days`` that have a failed job of their own.

    Parameters
    ----------
    found : list of Failure
        :func:`failures`.
    days : list of str
        Days ``YYYY-DDD`` of the campaign (failures of other days, e.g. of a campaign run
        with other dates in the same directory, are left out).
    """
    def rank(failure: Failure) -> int:
        rule = "download" if failure.rule.startswith("download_") else failure.rule
        return STEP_ORDER.index(rule) if rule in STEP_ORDER else len(STEP_ORDER)

    out: dict[str, Failure] = {}
    for failure in sorted((f for f in found if f.day in days), key=rank):
        out.setdefault(failure.day, failure)
    return {day: out[day] for day in days if day in out}


def gate_verdicts(directory: str | Path, layout: Layout, solution: str, sat: str,
                  days: list[str]) -> dict[str, str]:
    """Day -> verdict of the quality gate (:mod:`leopod.validation.quality_gate`) of the
    ``days`` whose POD step ``solution`` produced an orbit that did not pass it (suspect or
    failed, with the reasons), from the step's logs."""
    out = {}
    for day in days:
        log = Path(directory) / layout.logs / solution / sat / f"{day}.log"
        if log.is_file():
            for line in log.read_text(errors="replace").splitlines():
                found = _GATE.search(line)
                if found and found["date"] == day:
                    out[day] = found["verdict"]
    return out


def orbit_days(directory: str | Path, layout: Layout, solution: str, sat: str,
               days: list[str]) -> list[str]:
    """The ``days`` with the daily SP3 of a POD step
    (``results/<campaign>/<solution>/<sat>/<day>.sp3``)."""
    folder = Path(directory) / layout.results / solution / sat
    return [d for d in days if (folder / f"{d}.sp3").is_file()]
