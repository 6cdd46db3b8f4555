"""Snakemake script of rule simulate_gnss: see leopod.simulate.campaign."""

from leopod.simulate.campaign import SimulationSettings, simulate_gnss_products
from leopod.workflow import configure_logging

if __name__ == "__main__":
    configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    simulate_gnss_products(snakemake.wildcards.date, snakemake.params.world_start,  # noqa: F821
                           SimulationSettings.from_config(snakemake.params.settings),  # noqa: F821
                           snakemake.output.orbit, snakemake.output.clock)  # noqa: F821
