"""Snakemake script of rule simulate_truth: see leopod.simulate.campaign."""

from leopod.simulate.campaign import simulate_truth, write_code_bias_maps, write_truth_orbit
from leopod.simulate.settings import SimulationSettings
from leopod.workflow.log import configure_logging


def main(sat, settings, world_start, world_end, truth_path, map_path):
    sim = SimulationSettings.from_config(settings)
    write_truth_orbit(simulate_truth(sim, sat, world_start, world_end), truth_path)
    write_code_bias_maps(sim, map_path)


if __name__ == "__main__":
    configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    sm = snakemake  # noqa: F821
    main(sat=sm.wildcards.sat, settings=sm.params.settings, world_start=sm.params.world_start,
         world_end=sm.params.world_end, truth_path=sm.output.truth,
         map_path=sm.output.code_bias_map)
