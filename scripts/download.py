"""Snakemake script of the download_<family> rules: see leopod.download.fetch_product."""

from leopod.download import fetch_product
from leopod.workflow.downloads import load_catalogue
from leopod.workflow.log import configure_logging


def main(family, date, dest, settings, default_catalogue, log):
    catalogue = load_catalogue(settings, default_catalogue)
    fetch_product(catalogue, family, date, dest, mirrors=settings["mirrors"],
                  offline=settings["offline"], retries=settings["retries"],
                  retry_delay_s=settings["retry_delay_s"], timeout_s=settings["timeout_s"],
                  log=log)


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    sm = snakemake  # noqa: F821
    main(sm.params.family, sm.wildcards.get("date"), sm.output[0], sm.config["download"],
         sm.params.default_catalogue, log)
