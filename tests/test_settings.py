"""Typed settings: the campaign schema is the single source of their keys and defaults.

Authority: the schema itself (workflow/schemas/config.schema.yaml) and the contract of
leopod.settings: a settings field without a schema key would have no default and no check.
"""

from __future__ import annotations

import dataclasses
import importlib
import pkgutil

import pytest

import leopod
from leopod.settings import SCHEMA, Settings, _schema, schema_defaults


def _settings_classes() -> list[type[Settings]]:
    for module in pkgutil.walk_packages(leopod.__path__, "leopod."):
        importlib.import_module(module.name)
    found, todo = [], list(Settings.__subclasses__())
    while todo:
        cls = todo.pop()
        found.append(cls)
        todo.extend(cls.__subclasses__())
    return sorted(found, key=lambda c: c.__qualname__)


CLASSES = _settings_classes()


def test_settings_classes_are_found():
    names = {c.__name__ for c in CLASSES}
    assert {"PodSettings", "ArcSettings", "QualitySettings", "ArSettings", "MapSettings",
            "SlrResidualSettings", "DragSettings", "SystemSignals"} <= names


@pytest.mark.parametrize("cls", CLASSES, ids=lambda c: c.__name__)
def test_every_field_is_a_key_of_its_schema_definition(cls):
    assert dataclasses.is_dataclass(cls) and cls.__dataclass_params__.frozen
    fields = [f for f in dataclasses.fields(cls)]
    assert all(f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
               for f in fields), "defaults belong to the schema"
    if cls.SCHEMA_DEF is None:
        return
    keys = set(_schema(str(SCHEMA))["$defs"][cls.SCHEMA_DEF]["properties"])
    assert {f.name for f in fields} <= keys


def test_from_config_fills_schema_defaults_and_names_what_is_missing():
    from leopod.estimation.float_pod import PodSettings
    from leopod.signals import SystemSignals

    pod = PodSettings.from_config({"outlier_k": 4.0})
    assert pod.outlier_k == 4.0
    assert pod.code_sigma_m == schema_defaults("pod")["code_sigma_m"]
    assert pod.pulse_sigma_m_s == tuple(schema_defaults("pod")["pulse_sigma_m_s"])
    with pytest.raises(ValueError, match="pod_code"):
        SystemSignals.from_config({"phase": ["L1C", "L2W"], "code": ["C1C"]})
