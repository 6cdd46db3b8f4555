"""config/README.md, generated from the campaign schema (leopod.workflow.config_doc).

Authorities: the committed file must be what the schema gives now; the schema validator itself
(``load_campaign`` fills every default) says which keys exist and what their defaults are.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

from leopod.settings import SCHEMA, read_yaml
from leopod.workflow.config import load_campaign, section_defaults
from leopod.workflow.config_doc import key_rows, main, render

REPO = Path(__file__).resolve().parents[2]


def test_the_committed_page_is_up_to_date():
    assert (REPO / "config" / "README.md").read_text() == render(), (
        "run: python -m leopod.workflow.config_doc")
    assert main(["--check"]) == 0


def _flat(prefix: str, value) -> dict:
    if not isinstance(value, dict) or not value:
        return {prefix: value}
    out = {}
    for key, item in value.items():
        out.update(_flat(f"{prefix}.{key}", item))
    return out


def test_every_key_of_a_validated_campaign_has_a_row():
    # the default campaign with every default filled in by the validator
    config = load_campaign(REPO / "config" / "config.yaml")
    keys = [key for key, *_ in key_rows(read_yaml(SCHEMA))]
    # a row key '<sat>' (any '<...>') stands for every name of a mapping
    rows = re.compile("|".join(re.sub(r"<[a-z]+>", r"[^.]+", re.escape(k).replace(
        r"\<", "<").replace(r"\>", ">")) for k in keys))
    flat = {k: v for top, value in config.items() for k, v in _flat(top, value).items()}
    missing = sorted(k for k in flat if not rows.fullmatch(k))
    assert not missing, missing[:10]
    assert len(keys) > 300


def test_the_defaults_shown_are_those_the_validator_fills():
    rows = {key: default for key, _, _, default, _, _ in key_rows(read_yaml(SCHEMA))}
    pod = _flat("pod", section_defaults("pod"))
    checked = 0
    for key, value in pod.items():
        if key in rows and rows[key].startswith("`"):
            assert rows[key] == f"`{json.dumps(value, ensure_ascii=False)}`", key
            checked += 1
    assert checked > 30
