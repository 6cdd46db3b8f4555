"""The campaign configuration: validation against the schema, which is the source of defaults.

The schema ``workflow/schemas/config.schema.yaml`` of the repository checks every key of a
campaign file and supplies every default. The Snakefile validates the campaign with it before
any job starts; :func:`validated` does the same from Python (a test, a benchmark, a script run
from a prompt). :func:`section_defaults` gives the defaults of one section, e.g. to build
``PodSettings.from_config(section_defaults("pod"))`` in a test, and :func:`with_defaults` a
partial section completed as the campaign validation completes it, e.g.
``SimulationSettings.from_config(with_defaults("simulate", {"interval_s": 10.0}))``.
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from leopod.settings import SCHEMA, fill_defaults, read_yaml, schema_defaults

__all__ = ["SCHEMA", "load_campaign", "section_defaults", "validated", "with_defaults"]

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
        _merge(config, read_yaml(path) or {})
    return validated(config, schema)


def _merge(base: dict, overlay: Mapping) -> None:
    for key, value in overlay.items():
        if isinstance(value, Mapping) and isinstance(base.get(key), dict):
            _merge(base[key], value)
        else:
            base[key] = copy.deepcopy(value)


def section_defaults(name: str, schema: str | Path = SCHEMA) -> dict:
    """Defaults of the schema definition ``$defs/<name>``: what the campaign validation fills
    into an empty section (nested sections, list items and model-dependent keys included).

    Parameters
    ----------
    name : str
        A section with a definition in the schema: ``pod``, ``quality``, ``ambiguity``,
        ``code_bias``, ``validation``, ``download``, ``simulate``, ``simulate_slr``, …

    Returns
    -------
    dict
        Without the keys the schema requires and does not default (``pod.forces``).

    Raises
    ------
    KeyError
        If the schema has no such definition.
    """
    return schema_defaults(name, schema)


def with_defaults(name: str, section: Mapping[str, Any], schema: str | Path = SCHEMA) -> dict:
    """A copy of ``section`` validated against ``$defs/<name>`` with every default filled in.

    A partial section means what it means in a campaign file: a key that is given replaces
    its default (a mapping such as ``simulate.systems`` is replaced, not merged), the keys
    that are not given take their defaults, nested sections included.

    Parameters
    ----------
    name : str
        A definition of the schema (:func:`section_defaults`).
    section : mapping
        The keys that differ from the defaults.

    Raises
    ------
    KeyError
        If the schema has no such definition.
    snakemake.exceptions.WorkflowError
        Naming the offending key and value when the section does not conform.
    """
    return _filled(name, copy.deepcopy(dict(section)), schema, required=True)


def _filled(name: str, instance: dict, schema: str | Path, *, required: bool) -> dict:
    """``instance`` with the defaults of ``$defs/<name>`` set in place, by the validator the
    Snakefile uses (jsonschema 2020-12 with defaults, :func:`snakemake.utils.validate`)."""
    import jsonschema
    from snakemake.exceptions import WorkflowError

    errors = [e for e in fill_defaults(name, instance, schema)
              if required or e.validator != "required"]
    if errors:
        error = jsonschema.exceptions.best_match(errors)
        raise WorkflowError(f"Error validating the section '{name}'.", error)
    return instance
