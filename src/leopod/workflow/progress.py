"""Compact progress of a Snakemake run on the terminal (``leopod run --progress``).

Snakemake (9.x) logs, for every job, a block that starts with ``rule <name>:`` (or
``localrule``, ``checkpoint``) and holds ``jobid: <n>`` and ``wildcards: ...``; when a job ends
it logs ``Finished jobid: <n> (Rule: <name>)`` and ``<k> of <m> steps (<p>%) done``; before
any job, the ``Job stats:`` table ends with ``total <m>``. :class:`RunProgress` reads those
lines and turns them into one line per started and per finished job::

    [ 3/14] start float_pod  sat=grace-a, date=2007-080
    [ 4/14  29%] done  float_pod  sat=grace-a, date=2007-080   (running: quality)

Error blocks (``Error in rule ...`` up to the next blank line), the job table, "Nothing to be
done" and the path of Snakemake's complete log are passed through unchanged; everything else is
left to that log (``.snakemake/log/``).
"""

from __future__ import annotations

import re
import subprocess
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TextIO

__all__ = ["RunProgress", "run_with_progress"]

_RULE = re.compile(r"^(?:local)?(?:rule|checkpoint) (\S+):$")
_JOBID = re.compile(r"^\s+jobid: (\d+)$")
_WILDCARDS = re.compile(r"^\s+wildcards: (.*)$")
_FINISHED = re.compile(r"^Finished jobid: (\d+) \(Rule: (\S+)\)$")
_STEPS = re.compile(r"^(\d+) of (\d+) steps \((\d+%)\) done$")
_TOTAL = re.compile(r"^total\s+(\d+)$")
_PASSED = ("Complete log", "Nothing to be done", "Exiting because", "Would remove",
           "This was a dry-run")
_ERROR = ("Error in rule", "Error in group", "MissingInputException", "WorkflowError",
          "RuleException", "IncompleteFilesException", "MissingOutputException",
          "Traceback", "Error:")


@dataclass
class RunProgress:
    """State of a Snakemake run read from its log lines (module docstring).

    Attributes
    ----------
    total : int or None
        Number of jobs of the run (from the job table or the step counter).
    done : int
        Jobs finished.
    running : dict of int to str
        Job id -> ``"<rule>  <wildcards>"`` of the jobs started and not finished.
    """

    total: int | None = None
    done: int = 0
    running: dict[int, str] = field(default_factory=dict)
    _rule: str | None = None
    _jobid: int | None = None
    _wildcards: str = ""
    _finished: str = ""         # label of the job whose end was logged last
    _block: str | None = None   # "stats" or "error" while passing a block through

    def _width(self) -> int:
        return len(str(self.total or 0))

    def _start(self) -> list[str]:
        """Close the pending job block: the job has started."""
        if self._rule is None or self._jobid is None:
            self._rule = self._jobid = None
            return []
        label = f"{self._rule}  {self._wildcards}".rstrip()
        self.running[self._jobid] = label
        self._rule, self._jobid, self._wildcards = None, None, ""
        return [f"[{self.done:{self._width()}d}/{self.total or '?'}] start {label}"]

    def feed(self, line: str) -> list[str]:
        """Read one line of Snakemake's output; return the lines to show (maybe none)."""
        line = line.rstrip("\n")
        if self._block == "error":
            if not line.strip():
                self._block = None
            return [line] if line.strip() else []
        if self._block == "stats":
            total = _TOTAL.match(line)
            if total:
                self.total, self._block = int(total.group(1)), None
            return [line]
        out = []
        indented = line[:1].isspace()
        if self._rule is not None and not indented:
            out += self._start()
        if (m := _RULE.match(line)):
            self._rule = m.group(1)
        elif self._rule is not None and (m := _JOBID.match(line)):
            self._jobid = int(m.group(1))
        elif self._rule is not None and (m := _WILDCARDS.match(line)):
            self._wildcards = m.group(1)
        elif (m := _FINISHED.match(line)):
            self._finished = self.running.pop(int(m.group(1)), m.group(2))
        elif (m := _STEPS.match(line)):
            self.done, self.total = int(m.group(1)), int(m.group(2))
            others = sorted({r.split()[0] for r in self.running.values()})
            out.append(f"[{self.done:{self._width()}d}/{self.total} {m.group(3):>4s}] done  "
                       f"{self._finished}" + (f"   (running: {', '.join(others)})" if others else ""))
        elif line.startswith("Job stats:"):
            self._block = "stats"
            out.append(line)
        elif line.startswith(_ERROR):
            self._block = "error"
            out.append(line)
        elif line.startswith(_PASSED):
            out.append(line)
        return out


def run_with_progress(cmd: Sequence[str], stream: TextIO = sys.stdout) -> int:
    """Run Snakemake with its output read by :class:`RunProgress`; return its exit status.

    Parameters
    ----------
    cmd : sequence of str
        The Snakemake command line.
    stream : text stream
        Where the progress lines go.
    """
    progress = RunProgress()
    with subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          bufsize=1) as proc:
        for line in proc.stdout:
            for shown in progress.feed(line):
                print(shown, file=stream, flush=True)
    return proc.returncode
