"""The default campaign config (config/config.yaml) with some keys changed, for workflow tests."""

from __future__ import annotations

from pathlib import Path

import yaml

REPO = Path(__file__).resolve().parents[2]


def default_config(**changes) -> dict:
    """config/config.yaml with ``changes`` applied; keys are dotted paths (``"pod.outlier_k"``)."""
    cfg = yaml.safe_load((REPO / "config" / "config.yaml").read_text())
    for dotted, value in changes.items():
        node = cfg
        keys = dotted.split(".")
        for key in keys[:-1]:
            node = node[key]
        node[keys[-1]] = value
    return cfg
