"""The script boundary: what Snakemake hands a script, as plain Python, and the same from a prompt.

Every ``scripts/<rule>.py`` has the same three parts:

- ``main(...)``: plain paths and typed settings in, files out; it calls the library and is
  what tests call. The library below it never sees a Snakemake object.
- ``run(snakemake)``: turns the job's input/output/params into those paths and settings
  (``Settings.from_config`` of the validated config sections, model files resolved).
- ``if __name__ == "__main__":``: Snakemake injects ``snakemake``; run by hand
  (``python scripts/<rule>.py`` from the repository root), :func:`mock_snakemake` builds the
  same object for an example job of the default campaign, so a step can be debugged from a
  prompt or an IDE with the workflow's own inputs (the idea of PyPSA-Eur's ``mock_snakemake``).
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

__all__ = ["REPOSITORY", "attitude_files", "mock_snakemake", "plain", "source_on_python_path"]

#: Root of the repository checkout (Snakefile, config/, scripts/).
REPOSITORY = Path(__file__).resolve().parents[3]


def source_on_python_path(basedir) -> None:
    """Put the checkout's ``src/`` (of the Snakefile folder ``basedir``) first on the
    ``PYTHONPATH`` that the jobs inherit, so that they import leopod from this checkout: in a
    ``--use-conda`` environment (envs/leopod.yaml holds leopod's dependencies only, since
    Snakemake builds it from a copy of the file, where no relative pip path finds the
    checkout) as elsewhere (the source that ``make setup`` installs in editable mode)."""
    os.environ["PYTHONPATH"] = os.pathsep.join(
        p for p in (str(Path(basedir) / "src"), os.environ.get("PYTHONPATH")) if p)


def attitude_files(sm) -> list[str]:
    """The job's attitude files (input ``attitude``: the days its arc reaches), or [] when the
    satellite's attitude law reads none (``common.smk``: ``attitude_inputs``)."""
    files = plain(sm.input).get("attitude", [])
    return [files] if isinstance(files, str) else list(files)


def leo_antenna_of(pco_body_m, antenna, files) -> object:
    """The satellite's antenna for the library (:func:`leopod.gnss.leo_antenna.leo_antenna`):
    a :class:`~leopod.gnss.leo_antenna.LeoAntenna` read from the job's input ``leo_antex``
    (``common.smk``: ``antenna_inputs``) when ``antenna`` (params ``leo_antenna``, the
    ``satellites.<sat>.antenna`` block) names an ANTEX file, else the PCO table
    ``pco_body_m``."""
    from leopod.gnss.leo_antenna import leo_antenna

    path = (files or {}).get("leo_antex")
    if antenna and antenna.get("antex") is not None and not path:
        raise ValueError(f"satellites.<sat>.antenna.antex {antenna['antex']!r}: the job has no "
                         "input leo_antex (the rule needs unpack(antenna_inputs))")
    return leo_antenna(pco_body_m, antenna, path)


def plain(named) -> dict[str, str | list[str]]:
    """A Snakemake input/output container as a dict of str paths (lists for lists of files).

    Parameters
    ----------
    named : snakemake.io.Namedlist or mapping
        ``snakemake.input`` or ``snakemake.output`` (only the named entries are kept).
    """
    out = {}
    for key, value in named.items():
        out[key] = str(value) if isinstance(value, str | os.PathLike) else [str(v) for v in value]
    return out


def mock_snakemake(rule: str, *, configfiles: Iterable[str | Path] = ("config/config.yaml",),
                   root: str | Path = REPOSITORY, snakefile: str | Path | None = None,
                   **wildcards: str):
    """The ``snakemake`` object of one job, built by Snakemake itself outside a workflow run.

    The working directory becomes ``root`` (the job's paths are relative to it), as in a
    workflow run. The job's inputs need not exist: the object is what the script would get.

    Parameters
    ----------
    rule : str
        Rule name, e.g. ``"float_pod"``.
    configfiles : iterable of str or Path
        Campaign files (relative to ``root``), merged in order as ``--configfile``.
    root : str or Path
        Working directory of the job (a campaign directory, as ``snakemake --directory``).
    snakefile : str or Path, optional
        The workflow (default: ``root/Snakefile``).
    **wildcards : str
        The job's wildcards, e.g. ``sat="hy2b-sim", date="2019-002"``.

    Returns
    -------
    snakemake.script.Snakemake
        With ``input``, ``output``, ``params``, ``wildcards``, ``log``, ``threads``,
        ``resources``, ``config`` and ``rule`` as a workflow run would give them.

    Raises
    ------
    ValueError
        If the wildcards do not match those of the rule.
    """
    from snakemake.api import SnakemakeApi
    from snakemake.dag import DAG
    from snakemake.jobs import Job
    from snakemake.script import Snakemake
    from snakemake.settings.types import (
        ConfigSettings,
        DAGSettings,
        OutputSettings,
        ResourceSettings,
        StorageSettings,
        WorkflowSettings,
    )

    root = Path(root).resolve()
    os.chdir(root)
    with SnakemakeApi(OutputSettings()) as api:
        workflow_api = api.workflow(
            resource_settings=ResourceSettings(), storage_settings=StorageSettings(),
            config_settings=ConfigSettings(configfiles=[root / c for c in configfiles]),
            workflow_settings=WorkflowSettings(),
            snakefile=Path(snakefile).resolve() if snakefile else root / "Snakefile",
            workdir=root)
        workflow = workflow_api.dag(dag_settings=DAGSettings()).workflow_api._workflow
        job_rule = workflow.get_rule(rule)
        if set(job_rule.wildcard_names) != set(wildcards):
            raise ValueError(f"rule {rule} has the wildcards {sorted(job_rule.wildcard_names)}, "
                             f"not {sorted(wildcards)}")
        job = Job(job_rule, DAG(workflow, rules=workflow.rules), wildcards_dict=dict(wildcards))
        return Snakemake(job.input, job.output, job.params, job.wildcards, job.threads,
                         job.resources, job.log, workflow.config, job_rule.name, None)

