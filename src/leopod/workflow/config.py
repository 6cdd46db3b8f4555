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
import datetime as dt
import difflib
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from leopod.settings import SCHEMA, fill_defaults, read_yaml, schema_defaults

__all__ = ["SCHEMA", "campaign_problems", "load_campaign", "read_campaign", "section_defaults",
           "validated", "with_defaults"]

#: Longest message of one problem (a schema message can quote a whole section).
_MAX_MESSAGE = 240

def validated(config: Mapping[str, Any], schema: str | Path = SCHEMA) -> dict:
    """A copy of ``config`` checked against the schema, with every default filled in.

    Raises
    ------
    snakemake.exceptions.WorkflowError
        Listing every problem in one line each (:func:`campaign_problems`: the key, what was
        expected, a did-you-mean for a misspelt key) when the configuration does not conform.
    """
    from snakemake.exceptions import WorkflowError
    from snakemake.utils import validate

    out = copy.deepcopy(dict(config))
    try:
        validate(out, str(schema), set_default=True)
    except WorkflowError:
        # explain a failure in one line per problem (no second pass over a valid campaign)
        problems = campaign_problems(config, schema) or ["see Snakemake's message above"]
        raise WorkflowError("the campaign configuration does not conform to the schema "
                            f"({Path(schema).name}):\n"
                            + "\n".join(f"  - {p}" for p in problems)) from None
    return out


def campaign_problems(config: Mapping[str, Any], schema: str | Path = SCHEMA) -> list[str]:
    """Every place where ``config`` breaks the schema, one short line each: the key path, what
    was expected and, for an unknown key, the closest known keys of its section.

    Parameters
    ----------
    config : mapping
        The campaign as given (before defaults).
    schema : str or Path
        The campaign schema (JSON Schema 2020-12 in YAML).

    Returns
    -------
    list of str
        Empty when the campaign conforms.
    """
    import jsonschema

    document = read_yaml(schema)
    validator = jsonschema.Draft202012Validator(document)
    problems = []
    for error in sorted(validator.iter_errors(dict(config)),
                        key=lambda e: [str(p) for p in e.absolute_path]):
        problems.extend(_describe(error))
    return list(dict.fromkeys(problems))


def _where(path) -> str:
    return ".".join(str(p) for p in path) or "the campaign"


def _describe(error) -> list[str]:
    """One line per problem of a jsonschema error (unknown keys one line each)."""
    where = _where(error.absolute_path)
    if error.validator == "additionalProperties" and isinstance(error.instance, Mapping):
        known = list((error.schema.get("properties") or {}))
        patterns = list((error.schema.get("patternProperties") or {}))
        out = []
        for key in error.instance:
            if key in known or any(re.search(p, str(key)) for p in patterns):
                continue
            close = difflib.get_close_matches(str(key), known, n=2, cutoff=0.6)
            hint = (f"did you mean {' or '.join(repr(c) for c in close)}?" if close
                    else f"known keys: {', '.join(known)}" if known else "no keys allowed")
            prefix = "" if where == "the campaign" else f"{where}."
            out.append(f"{prefix}{key}: unknown key; {hint}")
        return out
    if error.validator in ("oneOf", "anyOf") and error.context:
        # the alternative whose type the value has (else jsonschema's most relevant one)
        import jsonschema

        typed = [e for e in error.context if e.validator != "type"] or error.context
        return _describe(jsonschema.exceptions.best_match(typed))
    if error.validator == "required":
        return [f"{where}: {error.message}"]
    if (error.validator == "type" and isinstance(error.instance, dt.date)
            and "string" in str(error.validator_value)):
        return [f"{where}: a date must be quoted in YAML, e.g. \"{error.instance.isoformat()}\""]
    if error.validator in ("type", "enum", "minimum", "maximum", "exclusiveMinimum",
                           "exclusiveMaximum", "pattern", "minItems", "maxItems", "const"):
        expected = {"type": "of type", "enum": "one of", "minimum": ">=", "maximum": "<=",
                    "exclusiveMinimum": ">", "exclusiveMaximum": "<", "pattern": "matching",
                    "minItems": "at least this many items:", "maxItems":
                    "at most this many items:", "const": "equal to"}[error.validator]
        return [f"{where}: {_short(repr(error.instance))} is not {expected} "
                f"{_short(repr(error.validator_value))}"]
    return [f"{where}: {_short(error.message)}"]


def _short(text: str) -> str:
    return text if len(text) <= _MAX_MESSAGE else text[:_MAX_MESSAGE - 1] + "…"


def load_campaign(*paths: str | Path, schema: str | Path = SCHEMA) -> dict:
    """Campaign files merged in order (as ``snakemake --configfile a b``) and validated."""
    return validated(read_campaign(*paths), schema)


def read_campaign(*paths: str | Path) -> dict:
    """Campaign files merged in order (as ``snakemake --configfile a b``), not validated."""
    config: dict = {}
    for path in paths:
        _merge(config, read_yaml(path) or {})
    return config


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
