"""The one convention by which a section of the campaign configuration becomes typed settings.

Every tunable of the library is a field of a frozen dataclass that derives from
:class:`Settings` and lives beside the code it tunes (``PodSettings`` in
:mod:`leopod.estimation.float_pod`, ``ArSettings`` in :mod:`leopod.ambiguity.resolve`, …).
The fields carry no defaults: the campaign schema (``workflow/schemas/config.schema.yaml``) is
the single source of them. :meth:`Settings.from_config` takes a section of a *validated*
configuration (defaults filled in by the schema, :func:`leopod.workflow.config.validated`)
and keeps the keys that are its fields; the other keys of the section belong to other
settings or to the workflow (e.g. ``ambiguity.enabled``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any, Self

__all__ = ["Settings", "frozen_value"]


def frozen_value(value: Any) -> Any:
    """``value`` with its lists turned into tuples (recursively), so settings are hashable."""
    if isinstance(value, list | tuple):
        return tuple(frozen_value(v) for v in value)
    return value


class Settings:
    """Base of the settings dataclasses (decorate subclasses with ``dataclass(frozen=True)``)."""

    @classmethod
    def from_config(cls, section: Mapping[str, Any]) -> Self:
        """Settings from a validated configuration section.

        Parameters
        ----------
        section : mapping
            The section with every field of ``cls`` present (schema defaults applied).

        Raises
        ------
        KeyError
            When a field is missing: the section was not validated against the schema, or
            the schema lacks the key.
        """
        names = [f.name for f in dataclasses.fields(cls)]
        missing = [n for n in names if n not in section]
        if missing:
            raise KeyError(f"{cls.__name__}: the configuration section has no "
                           f"{', '.join(missing)} (validate it against the campaign schema, "
                           "which holds the defaults)")
        return cls(**{n: frozen_value(section[n]) for n in names})
