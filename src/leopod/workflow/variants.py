"""Solution variants: several POD solutions of each satellite side by side.

A campaign's ``variants`` maps a variant name to keys of the ``pod`` and ``ambiguity``
sections that replace the campaign's, e.g. the GPS-only, BDS-only and combined solutions of
one satellite from one campaign (Jiang et al. 2023 compare GPS and BDS-3 periods; Zhang et
al. 2024 GPS, BDS-3 and GPS + BDS-3)::

    pod: {system: [G, C]}
    variants:
      G: {pod: {system: G}}
      C: {pod: {system: C}}

Every satellite then has one *POD line* per solution: its own id for the campaign's solution
and ``<sat>_<variant>`` for each variant (satellite ids have no underscore, schema). The
upstream steps (ingest, quality, code-bias maps) run once per satellite; the POD, ambiguity
and validation steps run per line and write their products under the line id, so each
variant has its own campaign summary. A formation pair (``satellites.<follower>.formation``)
likewise has one *pair line* per solution: ``<leader>-<follower>`` of the two satellites'
own lines and ``<leader>-<follower>_<variant>`` of their lines of each variant, e.g. the GPS,
BDS-3 and GPS + BDS-3 baselines of Zhang et al. (2024) from one campaign.
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from pathlib import Path
from typing import Any, NamedTuple

from leopod.settings import SCHEMA
from leopod.workflow.config import validated

__all__ = ["SEPARATOR", "FormationPair", "formation_pairs", "pod_lines", "variant_config"]

#: Between the satellite id and the variant name in a POD line id.
SEPARATOR = "_"

#: Sections whose keys a variant may replace.
VARIANT_SECTIONS = ("pod", "ambiguity")


def pod_lines(config: Mapping[str, Any]) -> dict[str, tuple[str, str | None]]:
    """POD lines of a validated campaign: ``{line id: (satellite, variant or None)}``.

    The satellites come first in config order (their own id, the campaign's solution), then
    their variants in config order.
    """
    lines: dict[str, tuple[str, str | None]] = {sat: (sat, None) for sat in config["satellites"]}
    for sat in config["satellites"]:
        for name in config.get("variants", {}):
            lines[f"{sat}{SEPARATOR}{name}"] = (sat, name)
    return lines


class FormationPair(NamedTuple):
    """A pair line: the POD lines of a formation pair in one solution.

    Attributes
    ----------
    leader, follower : str
        POD line ids (:func:`pod_lines`) of the leader and the follower.
    base : str
        Id of the pair line of the campaign's own solution (the pair of the satellites).
    variant : str or None
        The variant of both lines; None for the campaign's solution.
    """

    leader: str
    follower: str
    base: str
    variant: str | None


def formation_pairs(config: Mapping[str, Any], satellites) -> dict[str, FormationPair]:
    """Pair lines of a validated campaign: ``{pair id: FormationPair}`` (module docstring).

    Parameters
    ----------
    config : mapping
        The validated campaign.
    satellites : collection of str
        Satellites processed (a pair needs both).
    """
    pairs: dict[str, FormationPair] = {}
    for sat, block in config["satellites"].items():
        leader = (block.get("formation") or {}).get("leader")
        if sat not in satellites or leader not in satellites:
            continue
        base = f"{leader}-{sat}"
        pairs[base] = FormationPair(leader, sat, base, None)
        for name in config.get("variants", {}):
            pairs[f"{base}{SEPARATOR}{name}"] = FormationPair(
                f"{leader}{SEPARATOR}{name}", f"{sat}{SEPARATOR}{name}", base, name)
    return pairs


def variant_config(raw: Mapping[str, Any], name: str, schema: str | Path = SCHEMA) -> dict:
    """The validated campaign of variant ``name``.

    Parameters
    ----------
    raw : mapping
        The campaign as given (before validation: the defaults of the keys a variant replaces
        must follow from the replaced values, e.g. model-dependent defaults).
    name : str
        A key of ``raw["variants"]``.
    schema : str or Path
        The campaign schema.

    Returns
    -------
    dict
        The campaign with the variant's ``pod`` and ``ambiguity`` keys in place of the
        campaign's (whole keys are replaced, not merged), validated with defaults filled in.

    Raises
    ------
    ValueError
        If the variant would switch ambiguity resolution on or off (every line of a campaign
        has the same solutions, float and fixed or float only).
    """
    variant = raw["variants"][name]
    merged = copy.deepcopy(dict(raw))
    for section in VARIANT_SECTIONS:
        if section in variant:
            merged[section] = {**merged.get(section, {}), **copy.deepcopy(variant[section])}
    if "enabled" in variant.get("ambiguity", {}):
        raise ValueError(
            f"variants.{name}.ambiguity.enabled: a variant cannot switch ambiguity resolution "
            "on or off (all lines of a campaign have the same solutions)"
        )
    return validated(merged, schema)
