"""Glue between Snakemake scripts and the library: logging set-up and the job's provenance for
every step."""

from __future__ import annotations

import logging
import sys

from leopod.io._text import FormatError
from leopod.workflow.provenance import record_job

__all__ = ["configure_logging"]


def configure_logging(snakemake) -> logging.Logger:
    """Send ``logging`` to the rule's log file and stderr; log uncaught exceptions there too;
    declare the job's provenance to the product writers
    (:func:`leopod.workflow.provenance.record_job`).

    A :class:`leopod.io.FormatError` (bad or damaged input: its message names the file, line
    and field) is logged as that message alone; any other exception with its traceback.

    Parameters
    ----------
    snakemake : snakemake.script.Snakemake
        The object Snakemake passes to ``script:`` rules.

    Returns
    -------
    logging.Logger
        The root logger, configured.
    """
    handlers: list[logging.Handler] = [logging.StreamHandler(sys.stderr)]
    if snakemake.log:
        handlers.append(logging.FileHandler(str(snakemake.log[0]), mode="w"))
    logging.basicConfig(level=logging.INFO, handlers=handlers, force=True,
                        format="%(asctime)s %(levelname)s %(name)s: %(message)s")
    logging.captureWarnings(True)
    logger = logging.getLogger()

    def _hook(exc_type, exc, tb):
        if issubclass(exc_type, FormatError):
            logger.error("step %s failed: %s", snakemake.rule, exc)
        else:
            logger.error("step %s failed", snakemake.rule, exc_info=(exc_type, exc, tb))

    sys.excepthook = _hook
    logger.info("rule %s, wildcards %s", snakemake.rule, dict(snakemake.wildcards))
    job = record_job(snakemake)
    logger.info("campaign config sha256 %s", job.config_sha256)
    return logger
