"""The one convention by which a section of the campaign configuration becomes typed settings.

Every tunable of the library is a field of a frozen dataclass that derives from
:class:`Settings` and lives beside the code it tunes (``PodSettings`` in
:mod:`leopod.estimation.float_pod`, ``ArSettings`` in :mod:`leopod.ambiguity.resolve`, …).
The fields carry no defaults: the campaign schema (``workflow/schemas/config.schema.yaml`` of
the repository) is the single source of them. :meth:`Settings.from_config` takes a section of
the configuration, fills the keys it lacks from the schema definition the class names in
``SCHEMA_DEF`` (a validated configuration has them all already), and keeps the keys that are
its fields; the other keys of the section belong to other settings or to the workflow (e.g.
``ambiguity.enabled``). ``tests/test_settings.py`` checks that every field has its key in the
schema.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
from collections.abc import Mapping
from pathlib import Path
from typing import Any, ClassVar, Self

import yaml

__all__ = ["SCHEMA", "Settings", "fill_defaults", "frozen_value", "read_yaml", "schema_defaults"]

#: The campaign schema of the repository checkout (leopod runs from its checkout).
SCHEMA = Path(__file__).resolve().parents[2] / "workflow" / "schemas" / "config.schema.yaml"


#: libyaml's safe loader when PyYAML was built with it (7x faster on the schema), else Python's.
_SAFE_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def read_yaml(path: str | Path) -> Any:
    """Content of a YAML file, read with the safe loader (libyaml's when available)."""
    with open(path, encoding="utf-8") as f:
        return yaml.load(f, Loader=_SAFE_LOADER)


@functools.lru_cache(maxsize=4)
def _schema(path: str) -> dict:
    return read_yaml(path)


def schema_defaults(name: str, schema: str | Path = SCHEMA) -> dict:
    """Defaults of the schema definition ``$defs/<name>``: what the campaign validation fills
    into an empty section (nested sections, list items and model-dependent keys included).

    Parameters
    ----------
    name : str
        A definition of the schema: ``pod``, ``quality``, ``ambiguity``, ``code_bias``,
        ``slr_validation``, ``force_drag``, ``simulate``, …

    Raises
    ------
    KeyError
        If the schema has no such definition.
    """
    return copy.deepcopy(_defaults(name, str(schema)))


@functools.lru_cache(maxsize=64)
def _defaults(name: str, schema: str) -> dict:
    instance: dict = {}
    fill_defaults(name, instance, schema)   # an empty section may lack required keys
    return instance


def fill_defaults(name: str, instance: dict, schema: str | Path = SCHEMA) -> list:
    """Set the defaults of ``$defs/<name>`` into ``instance`` (in place) while validating it.

    Returns
    -------
    list of jsonschema.ValidationError
        What does not conform (missing required keys included).

    Raises
    ------
    KeyError
        If the schema has no such definition.
    """
    full = copy.deepcopy(_schema(str(schema)))  # defaults are set by reference: a fresh copy
    if name not in full["$defs"]:
        raise KeyError(f"the campaign schema has no definition '{name}' (known: "
                       f"{', '.join(full['$defs'])})")
    root = {"$schema": full["$schema"], "$defs": full["$defs"], "$ref": f"#/$defs/{name}"}
    return list(_default_validator()(root).iter_errors(instance))


@functools.lru_cache(maxsize=1)
def _default_validator():
    """Draft 2020-12 validator class that sets the defaults of ``properties`` as Snakemake's
    does (here on a copy of each default and only into mappings)."""
    import jsonschema

    base = jsonschema.Draft202012Validator
    check_properties = base.VALIDATORS["properties"]

    def properties(validator, props, instance, schema):
        if validator.is_type(instance, "object"):
            for key, sub in props.items():
                if "default" in sub:
                    instance.setdefault(key, copy.deepcopy(sub["default"]))
        yield from check_properties(validator, props, instance, schema)

    return jsonschema.validators.extend(base, {"properties": properties})


def frozen_value(value: Any) -> Any:
    """``value`` with its lists turned into tuples (recursively), so settings are hashable."""
    if isinstance(value, list | tuple):
        return tuple(frozen_value(v) for v in value)
    return value


class Settings:
    """Base of the settings dataclasses (decorate subclasses with ``dataclass(frozen=True)``).

    Subclasses name the schema definition that holds their keys and defaults in
    ``SCHEMA_DEF`` (None: the section must hold every field, e.g. ``signals.<system>``).
    """

    SCHEMA_DEF: ClassVar[str | None] = None

    @classmethod
    def from_config(cls, section: Mapping[str, Any]) -> Self:
        """Settings from a configuration section, schema defaults for the keys it lacks.

        Parameters
        ----------
        section : mapping
            The section (validated or partial).

        Raises
        ------
        ValueError
            When a field is neither in the section nor a default of the schema definition.
        """
        names = [f.name for f in dataclasses.fields(cls)]
        values = dict(section)
        if cls.SCHEMA_DEF and any(n not in values for n in names):
            # a validated section has every key: the schema is only read for a partial one
            values = {**schema_defaults(cls.SCHEMA_DEF), **section}
        missing = [n for n in names if n not in values]
        if missing:
            raise ValueError(f"{cls.__name__}: the configuration section has no "
                           f"{', '.join(missing)} and the campaign schema "
                           f"({cls.SCHEMA_DEF or 'no definition'}) gives no default")
        return cls(**{n: frozen_value(values[n]) for n in names})
