"""The campaign configuration: validation against the schema, which is the source of defaults.

The schema ``workflow/schemas/config.schema.yaml`` of the repository checks every key of a
campaign file and supplies every default. The Snakefile validates the campaign with it before
any job starts; :func:`validated` does the same from Python (a test, a benchmark, a script run
from a prompt), and :func:`section_defaults` gives the defaults of one section, e.g. to build
``PodSettings.from_config(section_defaults("pod"))`` in a test.
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import yaml

from leopod.settings import SCHEMA, schema_defaults

__all__ = ["SCHEMA", "load_campaign", "section_defaults", "validated"]

def validated(config: Mapping[str, Any], schema: str | Path = SCHEMA) -> dict:
    """A copy of ``config`` checked against the schema, with every default filled in.

    Raises
    ------
    snakemake.exceptions.WorkflowError
        Naming the offending key and value when the configuration does not conform.
    """
    from snakemake.utils import validate

    out = copy.deepcopy(dict(config))
    validate(out, str(schema), set_default=True)
    return out


def load_campaign(*paths: str | Path, schema: str | Path = SCHEMA) -> dict:
    """Campaign files merged in order (as ``snakemake --configfile a b``) and validated."""
    config: dict = {}
    for path in paths:
        _merge(config, yaml.safe_load(Path(path).read_text()) or {})
    return validated(config, schema)


def _merge(base: dict, overlay: Mapping) -> None:
    for key, value in overlay.items():
        if isinstance(value, Mapping) and isinstance(base.get(key), dict):
            _merge(base[key], value)
        else:
            base[key] = copy.deepcopy(value)


def section_defaults(name: str, schema: str | Path = SCHEMA) -> dict:
    """Defaults of the schema definition ``$defs/<name>`` (see
    :func:`leopod.settings.schema_defaults`)."""
    return schema_defaults(name, schema)
