"""The download_<family> rules: fetch one product file (leopod.download.fetch_product)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging
from collections.abc import Mapping

from leopod.download import fetch_product
from leopod.settings import schema_defaults
from leopod.workflow.downloads import load_catalogue
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


def main(family: str, date: str | None, dest, settings: Mapping, default_catalogue) -> None:
    """Fetch the file of ``family`` (and ``date``, None for static products) into ``dest``
    with the campaign's ``download`` settings."""
    catalogue = load_catalogue(settings, default_catalogue)
    fetch_product(catalogue, family, date, dest, mirrors=settings["mirrors"],
                  offline=settings["offline"], retries=settings["retries"],
                  retry_delay_s=settings["retry_delay_s"], timeout_s=settings["timeout_s"],
                  log=log)


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    # not a param on purpose (download.smk): a changed mirror list refetches nothing
    settings = {**schema_defaults("download"), **sm.config.get("download", {})}
    main(sm.params.family, sm.wildcards.get("date"), sm.output[0], settings,
         sm.params.default_catalogue)


if __name__ == "__main__":
    # the default campaign downloads nothing: call main() by hand, or run through Snakemake
    run(snakemake)  # noqa: F821 (injected by Snakemake)
