"""envs/leopod.yaml, the environment of ``snakemake --use-conda`` (issue 23, item 7).

Conda itself is not on this machine, so the environment is not built here; these tests keep
the file in step with pyproject.toml (authority: the package's declared dependencies) and
free of paths that break when Snakemake builds the environment from a copy of the file.
"""

from __future__ import annotations

import os
import re
import tomllib
from pathlib import Path

import yaml

REPO = Path(__file__).resolve().parents[2]
#: conda-forge names of PyPI packages whose names differ there
CONDA_NAMES = {"matplotlib": "matplotlib-base", "netCDF4": "netcdf4"}


def _requirements(entries: list[str], names: dict[str, str] | None = None) -> dict[str, str]:
    """{lower-case package name (renamed by ``names``): version bound} of requirement strings."""
    out = {}
    for entry in entries:
        name, bound = re.match(r"([A-Za-z0-9_.-]+)\s*(.*)", entry).groups()
        out[(names or {}).get(name, name).lower()] = bound.replace(" ", "")
    return out


def test_the_conda_environment_holds_the_dependencies_of_pyproject():
    project = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]
    wanted = _requirements(project["dependencies"], CONDA_NAMES)
    wanted.pop("snakemake")   # the job scripts import the Snakemake that runs them
    env = yaml.safe_load((REPO / "envs" / "leopod.yaml").read_text())
    conda = [d for d in env["dependencies"] if isinstance(d, str) and d != "pip"]
    (pip,) = [d["pip"] for d in env["dependencies"] if isinstance(d, dict)]
    have = _requirements([d for d in conda if not d.startswith("python")] + pip)
    assert have == wanted


def test_the_conda_environment_names_no_path():
    # Snakemake builds the environment from a copy of the file in .snakemake/conda, where
    # a relative path such as "-e ../" names another folder (the issue-23 failure)
    env = yaml.safe_load((REPO / "envs" / "leopod.yaml").read_text())
    (pip,) = [d["pip"] for d in env["dependencies"] if isinstance(d, dict)]
    assert not [p for p in pip if p.startswith(("-e", ".", "/")) or "/" in p]


def test_the_jobs_find_leopod_of_the_checkout_first(monkeypatch, tmp_path):
    # the Snakefile calls source_on_python_path(workflow.basedir) before any job starts;
    # a job's python then imports the checkout's leopod (authority: Python's PYTHONPATH rule,
    # its entries come before site-packages)
    import subprocess
    import sys

    from leopod.workflow.boundary import source_on_python_path

    monkeypatch.setenv("PYTHONPATH", str(tmp_path))
    source_on_python_path(REPO)
    assert os.environ["PYTHONPATH"].split(os.pathsep) == [str(REPO / "src"), str(tmp_path)]
    found = subprocess.run([sys.executable, "-c", "import leopod; print(leopod.__file__)"],
                           capture_output=True, text=True, check=True).stdout.strip()
    assert Path(found) == REPO / "src" / "leopod" / "__init__.py"
