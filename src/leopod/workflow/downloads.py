"""Downloads inside a campaign: ``download:<family>`` in the config becomes a file the
``download_<family>`` rule writes under ``resources/download/`` (a cache shared by the campaigns
of a working directory, keyed by family and day: :mod:`leopod.workflow.layout`).

A campaign names its inputs by path template
(``products.gnss_orbit: "/data/cod{gpsweek}{dow}.sp3"``) or by product family of the catalogue
(``products.gnss_orbit: "download:cod_orbit"``). The second form is rewritten here, before any
rule sees the config, into the path the family's download rule produces, so every other rule
reads downloaded and local files alike.
"""

from __future__ import annotations

import copy
from pathlib import Path

from leopod.download.catalogue import Catalogue, Family
from leopod.workflow.campaign import input_references
from leopod.workflow.layout import DOWNLOAD_ROOT

__all__ = ["PREFIX", "destination_template", "load_catalogue", "resolve_downloads",
           "uses_downloads"]

#: Prefix of a config value that names a product family instead of a path.
PREFIX = "download:"

def destination_template(family: Family) -> str:
    """Path template of a family's downloaded (decompressed) file.

    ``resources/download/<family>/{date}<suffix>`` for daily families (``{date}`` =
    ``YYYY-DDD``), ``resources/download/<family>/<family><suffix>`` for static ones.
    """
    stem = "{date}" if family.period == "day" else family.name
    return f"{DOWNLOAD_ROOT}/{family.name}/{stem}{family.suffix}"


def load_catalogue(settings: dict, default: str | Path) -> Catalogue:
    """The campaign's catalogue: ``download.catalogue`` (or ``default``) with the archive
    URLs of ``download.archive_urls`` replaced (e.g. by a local mirror)."""
    catalogue = Catalogue.from_yaml(settings.get("catalogue") or default)
    urls = settings.get("archive_urls") or {}
    return catalogue.with_archive_urls(urls) if urls else catalogue


def uses_downloads(config: dict) -> bool:
    """True if any input of the campaign is given as ``download:<family>``."""
    return any(isinstance(c.get(k), str) and c[k].startswith(PREFIX)
               for _, c, k in input_references(config))


def resolve_downloads(config: dict, catalogue: Catalogue) -> tuple[dict, list[str]]:
    """Replace ``download:<family>`` values by the family's download destination.

    Parameters
    ----------
    config : dict
        The validated campaign config (not modified).
    catalogue : Catalogue
        Product families available.

    Returns
    -------
    config : dict
        A copy with the references replaced by path templates.
    families : list of str
        The families the campaign downloads, sorted.

    Raises
    ------
    ValueError
        An unknown family, naming the config entry and the known families.
    """
    config = copy.deepcopy(config)
    used = set()
    for where, container, key in input_references(config):
        value = container.get(key)
        if not (isinstance(value, str) and value.startswith(PREFIX)):
            continue
        name = value[len(PREFIX):].strip()
        try:
            family = catalogue.family(name)
        except ValueError as err:
            raise ValueError(f"{where}: {err}") from None
        container[key] = destination_template(family)
        used.add(name)
    return config, sorted(used)
