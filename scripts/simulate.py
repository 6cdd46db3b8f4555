"""Snakemake script of rule simulate: see leopod.simulate.campaign."""

from leopod.simulate.campaign import SimulationSettings, simulate_leo_day
from leopod.workflow import configure_logging

if __name__ == "__main__":
    configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    simulate_leo_day(snakemake.wildcards.date, snakemake.params.world_start,  # noqa: F821
                     snakemake.wildcards.sat,  # noqa: F821
                     SimulationSettings.from_config(snakemake.params.settings),  # noqa: F821
                     snakemake.output.obs, snakemake.output.truth_sp3,  # noqa: F821
                     snakemake.output.truth_nc)  # noqa: F821
