"""The provenance of a script job, declared once per job for every writer of its products.

:func:`record_job` (called by :func:`leopod.workflow.log.configure_logging`, the first call
of every script's ``run``) turns the Snakemake object of the job into a
:class:`leopod.io.provenance.JobProvenance`: the rule and its script, the complete settings
of the step (its ``params``, which carry every setting the step uses), the input files (the
library code and the rule's script, inputs ``code`` and ``script``, left out: ``source`` and
``history`` name the leopod version and the script) and the hash of the campaign. The netCDF
and SP3 writers add them to every product.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
from collections.abc import Mapping
from pathlib import Path

from leopod.io.provenance import JobProvenance, set_job

__all__ = ["STEP_REFERENCES", "config_sha256", "job_provenance", "record_job"]

#: The publications of each step's methods (short forms of REFERENCES.md), for the CF
#: ``references`` attribute of its netCDF files; steps of the closed-loop simulation and of
#: bookkeeping have none.
STEP_REFERENCES = {
    "gnss_products": "SP3-d (Hilla 2016); RINEX clock 3.04; ANTEX 1.4",
    "ingest": "RINEX 3.04; RINEX 2.11; SP3-d (Hilla 2016); RINEX clock 3.04",
    "quality": "Wang et al. (2024), Table 2; Blewitt 1990",
    "code_bias": "Peng et al. (2021); Jiang et al. (2023)",
    "code_bias_stack": "Peng et al. (2021); Jiang et al. (2023)",
    "float_pod": "Jäggi et al. 2006; Wang et al. (2024); Peng et al. (2021); "
                 "IERS Conventions 2010",
    "ambiguity": "Peng et al. (2021); Laurichesse et al. 2009; Jiang et al. (2023)",
    "fixed_pod": "Peng et al. (2021); Laurichesse et al. 2009; Jiang et al. (2023); "
                 "Jäggi et al. 2006; IERS Conventions 2010",
    "kinematic_pod": "Švehla & Rothacher 2005",
    "kinematic_baseline": "Zhang et al. (2024); Kroes et al. 2005",
    "baseline": "Zhang et al. (2024); Kroes et al. 2005",
    "baseline_overlap": "Zhang et al. (2024)",
    "pcv": "Wang et al. (2024); Jäggi et al. 2009",
    "pcv_stack": "Wang et al. (2024); Jäggi et al. 2009",
    "overlap": "Jiang et al. (2023)",
    "overlap_summary": "Jiang et al. (2023)",
    "reference_orbit": "Wang et al. (2024), Table 4",
    "reference_summary": "Wang et al. (2024), Table 4",
    "slr": "Peng et al. (2021), Table IV; Mendes & Pavlis (2004); IERS Conventions 2010",
    "slr_summary": "Peng et al. (2021), Table IV",
}


def config_sha256(config: Mapping) -> str:
    """SHA-256 (hex) of a campaign as given: the merged campaign files (Snakemake's
    ``config``) as JSON with sorted keys and no spaces, UTF-8.

    The campaign as given, not validated: the schema's defaults are those of the leopod
    version the products name (``source``), and validating costs a job about a second.
    """
    text = json.dumps(config, sort_keys=True, separators=(",", ":"), default=str,
                      ensure_ascii=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def _files(named: Mapping) -> list[str]:
    """Paths of a Snakemake input container without its ``code`` (library) and ``script``
    entries."""
    out: list[str] = []
    for key, value in named.items():
        if key in ("code", "script"):
            continue
        out += [str(value)] if isinstance(value, str | os.PathLike) else [str(v) for v in value]
    return list(dict.fromkeys(out))


def job_provenance(sm) -> JobProvenance:
    """The provenance of a script job.

    Parameters
    ----------
    sm : snakemake.script.Snakemake
        The object Snakemake passes to the script (``rule``, ``input``, ``params``,
        ``config``). The script is the one running (``__file__`` of ``__main__``, which
        Snakemake's preamble sets to the rule's script), else ``scripts/<rule>.py``.
    """
    main = getattr(sys.modules.get("__main__"), "__file__", None)
    script = Path(main).name if main and Path(main).parent.name == "scripts" \
        else f"{sm.rule}.py"
    settings = json.dumps(dict(sm.params.items()), sort_keys=True, default=str,
                          ensure_ascii=False)
    return JobProvenance(rule=sm.rule, script=f"scripts/{script}", settings=settings,
                         inputs=tuple(_files(sm.input)),
                         config_sha256=config_sha256(dict(sm.config)),
                         references=STEP_REFERENCES.get(sm.rule, ""),
                         institution=str(sm.config.get("institution") or ""))


def record_job(sm) -> JobProvenance:
    """Declare the job of ``sm`` to the writers (:func:`leopod.io.provenance.set_job`)."""
    job = job_provenance(sm)
    set_job(job)
    return job
