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


def output_digests(work: Path) -> dict[str, str]:
    """SHA-256 of every file the jobs of a run in ``work`` wrote to results/ and resources/
    (the report, a separate command, aside)."""
    import hashlib

    return {str(p.relative_to(work)): hashlib.sha256(p.read_bytes()).hexdigest()
            for folder in ("results", "resources") for p in sorted((work / folder).rglob("*"))
            if p.is_file() and p.name != "report.html"}
