"""The provenance of the workflow job that writes a product, added by every leopod writer.

A workflow job declares itself once (:func:`set_job`, called by the script boundary,
:func:`leopod.workflow.provenance.record_job`); :func:`leopod.io.netcdf.write_netcdf` then adds
to every netCDF file of the job the CF-1.10 attributes ``history`` (UTC time, leopod version,
rule and script) and ``references`` (the methods of the step) and leopod's ``leopod_settings``
(the step's settings, JSON), ``leopod_inputs`` (JSON: input path -> SHA-256) and
``leopod_config_sha256``; :func:`leopod.io.sp3_write.write_sp3` adds the config hash as a comment
line. Files written outside a workflow job (tests, a library call) carry none of them.

The time of ``history`` is :func:`leopod.io._text.creation_time` when the job starts: the wall
clock, or ``SOURCE_DATE_EPOCH`` if set (the reproducible-builds convention), so that two runs
of the same inputs can still give identical bytes.
"""

from __future__ import annotations

import functools
import hashlib
import json
from dataclasses import dataclass, field
from pathlib import Path

from leopod import __version__
from leopod.io._text import creation_time

__all__ = ["JobProvenance", "current_job", "file_sha256", "set_job"]


def _started() -> str:
    return creation_time().strftime("%Y-%m-%dT%H:%M:%SZ")


@dataclass(frozen=True)
class JobProvenance:
    """What a workflow job records in its products.

    Attributes
    ----------
    rule : str
        The Snakemake rule of the job.
    script : str
        The script it runs (``scripts/<rule>.py``).
    settings : str
        The complete settings of the step (its ``params``), JSON with sorted keys.
    inputs : tuple of str
        The job's input files (paths as the workflow names them), in order.
    config_sha256 : str
        SHA-256 (hex) of the campaign as given (:func:`leopod.workflow.provenance.config_sha256`).
    references : str
        The publications of the step's methods (author-year, ``REFERENCES.md``), or "".
    institution : str
        Who produces the products (campaign key ``institution``), or "" (not written).
    started : str
        UTC time of the job, ISO 8601 (``YYYY-MM-DDThh:mm:ssZ``).
    """

    rule: str
    script: str
    settings: str
    inputs: tuple[str, ...]
    config_sha256: str
    references: str = ""
    institution: str = ""
    started: str = field(default_factory=_started)

    @property
    def history(self) -> str:
        """The CF ``history`` line: time, software, rule and script."""
        return (f"{self.started}: leopod {__version__}, Snakemake rule {self.rule} "
                f"(script {self.script})")

    def input_digests(self) -> dict[str, str]:
        """``{input path: SHA-256}`` of the job's input files (hashed once per job)."""
        return {path: file_sha256(path) for path in self.inputs}

    def netcdf_attributes(self) -> dict[str, str]:
        """The global attributes of the job's netCDF files."""
        attrs = {"history": self.history,
                 "leopod_settings": self.settings,
                 "leopod_inputs": json.dumps(self.input_digests(), sort_keys=True),
                 "leopod_config_sha256": self.config_sha256}
        if self.references:
            attrs["references"] = self.references
        if self.institution:
            attrs["institution"] = self.institution
        return attrs


@functools.cache
def file_sha256(path: str) -> str:
    """SHA-256 (hex) of a file's bytes, read in 1-MB blocks; cached per path (a job reads
    its inputs, it does not change them).

    Raises
    ------
    FileNotFoundError
        If there is no such file.
    """
    digest = hashlib.sha256()
    with open(Path(path), "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


_JOB: list[JobProvenance] = []


def set_job(job: JobProvenance | None) -> None:
    """Declare the job whose products the writers are writing (None: no job)."""
    _JOB[:] = [] if job is None else [job]


def current_job() -> JobProvenance | None:
    """The job declared by :func:`set_job`, or None outside a workflow job."""
    return _JOB[0] if _JOB else None
