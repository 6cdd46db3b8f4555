"""Rule simulate_world: GNSS biases and SLR stations shared by the simulated satellites
(leopod.simulate.campaign)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

from leopod.simulate.campaign import simulate_world_truth
from leopod.simulate.settings import SimulationSettings
from leopod.workflow.log import configure_logging


def main(settings: SimulationSettings, sats, world_start: str, world_end: str, biases_path,
         stations_path, eccentricities_path) -> None:
    """Write the world's biases (netCDF), SLR stations and eccentricities (SINEX)."""
    simulate_world_truth(settings, sats, world_start, world_end, biases_path=biases_path,
                         stations_path=stations_path, eccentricities_path=eccentricities_path)


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    main(SimulationSettings.from_config(sm.params.settings), list(sm.params.sats),
         sm.params.world_start, sm.params.world_end, biases_path=sm.output.biases,
         stations_path=sm.output.stations, eccentricities_path=sm.output.eccentricities)


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: the job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("simulate_world")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
