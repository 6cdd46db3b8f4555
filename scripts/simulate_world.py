"""Snakemake script of rule simulate_world: see leopod.simulate.campaign."""

from leopod.simulate.campaign import simulate_world_truth
from leopod.simulate.settings import SimulationSettings
from leopod.workflow.log import configure_logging


def main(settings, sats, world_start, world_end, out):
    simulate_world_truth(SimulationSettings.from_config(settings), sats, world_start, world_end,
                         biases_path=out.biases, stations_path=out.stations,
                         eccentricities_path=out.eccentricities)


if __name__ == "__main__":
    configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    sm = snakemake  # noqa: F821
    main(settings=sm.params.settings, sats=list(sm.params.sats),
         world_start=sm.params.world_start, world_end=sm.params.world_end, out=sm.output)
