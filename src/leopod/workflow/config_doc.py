"""``config/README.md`` from the campaign schema: every key with type, unit, default, bounds.

::

    python -m leopod.workflow.config_doc            # write config/README.md
    python -m leopod.workflow.config_doc --check    # exit 1 if the file is not up to date

The schema (``workflow/schemas/config.schema.yaml``) is the only source of defaults and the
place of every description; this page is generated from it, one table per top-level section,
one row per key (dotted path; ``<sat>``, ``<name>`` for keys of mappings, ``[]`` for list
items). The unit is the bracket at the end of a description (``[s]``), else the suffix of the
key name (``_m``, ``_s``, ``_deg``, ...; DESIGN: units in key names).
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from collections.abc import Iterator
from pathlib import Path

from leopod.settings import SCHEMA, read_yaml

__all__ = ["key_rows", "render", "main"]

#: Units of key-name suffixes, longest first.
_SUFFIX_UNITS = (("_m2_kg", "m²/kg"), ("_m_min", "m/min"), ("_m_s", "m/s"), ("_m2", "m²"),
                 ("_mm", "mm"), ("_km", "km"), ("_kg", "kg"), ("_deg", "deg"),
                 ("_cyc", "cycles"), ("_hz", "Hz"), ("_ms", "ms"), ("_ns", "ns"), ("_m", "m"),
                 ("_s", "s"), ("_h", "h"))
_UNIT = re.compile(r"\[([^\[\]]{1,20})\]\.?$")
_BOUNDS = (("minimum", "≥ {}"), ("exclusiveMinimum", "> {}"), ("maximum", "≤ {}"),
           ("exclusiveMaximum", "< {}"), ("minItems", "≥ {} items"), ("maxItems", "≤ {} items"),
           ("minProperties", "≥ {} keys"), ("pattern", "matches `{}`"))
_OWNERS = {"satellites": "<sat>", "variants": "<name>", "antenna_pco_body_m": "<band>",
           "systems": "<system>",
           "signals": "<system>", "exclude_days": "<day>", "exclude_pod_days": "<day>"}


def _resolve(node: dict, defs: dict) -> dict:
    """The node with its ``$ref`` (a JSON pointer ``#/$defs/...``) and the ``then`` of an
    ``if`` merged in."""
    if "$ref" in node:
        target = {"$defs": defs}
        for part in node["$ref"].lstrip("#/").split("/"):
            target = target[part]
        node = {**_resolve(target, defs), **{k: v for k, v in node.items() if k != "$ref"}}
    if "then" in node and "$ref" in node["then"]:
        node = {**_resolve(node["then"], defs), **{k: v for k, v in node.items()
                                                   if k not in ("if", "then", "else")}}
    return node


def _types(node: dict, defs: dict) -> str:
    kinds = []
    for branch in node.get("oneOf", []) + node.get("anyOf", []):
        kinds.append(_types(_resolve(branch, defs), defs))
    t = node.get("type", "object" if "properties" in node else "")
    kinds += t if isinstance(t, list) else [t] if t else []
    if "enum" in node:
        return " \\| ".join(f"`{json.dumps(v)}`" for v in node["enum"])
    return " \\| ".join(dict.fromkeys(k for k in kinds if k))


def _unit(key: str, description: str) -> str:
    found = _UNIT.search(description.strip())
    if found:
        return found.group(1)
    return next((unit for suffix, unit in _SUFFIX_UNITS if key.endswith(suffix)), "")


def _bounds(node: dict) -> str:
    out = [text.format(node[key]) for key, text in _BOUNDS if key in node]
    items = node.get("items") if isinstance(node.get("items"), dict) else {}
    out += [f"items {text.format(items[key])}" for key, text in _BOUNDS if key in items]
    return ", ".join(out)


def _children(node: dict, defs: dict) -> Iterator[tuple[str, dict]]:
    """(name, schema) of the keys inside an object node (properties, mapping values,
    conditional parts of allOf, list items)."""
    for name, child in node.get("properties", {}).items():
        yield name, child
    for part in node.get("allOf", []):
        if "then" in part:
            yield from _children(_resolve(part["then"], defs), defs)
    extra = node.get("additionalProperties")
    if isinstance(extra, dict):
        yield "*", extra
    branches = [b for b in node.get("anyOf", []) + node.get("oneOf", []) if "$ref" in b]
    for branch in branches:
        yield from _children(_resolve(branch, defs), defs)


def key_rows(schema: dict) -> Iterator[tuple[str, str, str, str, str, str]]:
    """Every key of the schema: (dotted key, type, unit, default, bounds, description)."""
    defs = schema.get("$defs", {})

    def walk(prefix: str, node: dict) -> Iterator[tuple]:
        node = _resolve(node, defs)
        for name, child in _children(node, defs):
            owner = prefix.rsplit(".", 1)[-1]
            key = f"{prefix}.{_OWNERS.get(owner, '<key>')}" if name == "*" else (
                f"{prefix}.{name}" if prefix else name)
            child = _resolve(child, defs)
            description = " ".join(str(child.get("description", "")).split())
            default = (f"`{json.dumps(child['default'], ensure_ascii=False)}`"
                       if "default" in child else "required" if name in node.get(
                           "required", []) else "")
            items = child.get("items") if isinstance(child.get("items"), dict) else None
            nested = bool(list(_children(child, defs)))
            yield (key, _types(child, defs), "" if nested else _unit(name, description),
                   default, _bounds(child), description)
            if nested:
                yield from walk(key, child)
            elif items and "$ref" in items:
                yield from walk(f"{key}[]", items)

    yield from walk("", schema)


def render(schema_path: str | Path = SCHEMA) -> str:
    """The text of ``config/README.md``."""
    schema = read_yaml(schema_path)
    lines = ["# Campaign keys", "",
             "Generated from `workflow/schemas/config.schema.yaml` by "
             "`python -m leopod.workflow.config_doc`; do not edit by hand (a test checks that it "
             "is up to date). A campaign file sets some of these keys; every other key takes its "
             "default. `leopod init` writes a commented campaign, `leopod check` validates one.",
             "", "Required top-level keys: " + ", ".join(
                 f"`{k}`" for k in schema.get("required", [])) + ".", ""]
    section = None
    for key, kind, unit, default, bounds, description in key_rows(schema):
        top = key.split(".")[0]
        if top != section:
            section = top
            lines += ["", f"## {top}", "", "| key | type | unit | default | bounds | description |",
                      "|---|---|---|---|---|---|"]
        cells = (f"`{key}`", kind, unit, default, bounds, description)
        lines.append("| " + " | ".join(c.replace("|", "\\|") if c is description else c
                                       for c in cells) + " |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    """Write (or with ``--check`` compare) ``config/README.md``; returns the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=Path,
                        default=SCHEMA.parents[2] / "config" / "README.md")
    parser.add_argument("--check", action="store_true",
                        help="exit 1 if the file differs from what the schema gives")
    args = parser.parse_args(argv)
    text = render()
    if args.check:
        same = args.output.is_file() and args.output.read_text() == text
        if not same:
            print(f"{args.output} is not up to date: python -m leopod.workflow.config_doc",
                  file=sys.stderr)
        return 0 if same else 1
    args.output.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
