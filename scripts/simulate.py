"""Snakemake script of rule simulate: see leopod.simulate.campaign."""

import xarray as xr

from leopod.simulate.campaign import simulate_leo_day
from leopod.simulate.settings import SimulationSettings
from leopod.workflow.log import configure_logging


def main(date, sat, settings, world_start, world_end, pco_body_m, truth_path, biases_path, out):
    with xr.open_dataset(truth_path) as f:
        truth = f.load()
    with xr.open_dataset(biases_path) as f:
        biases = f.load()
    simulate_leo_day(date, sat, SimulationSettings.from_config(settings), world_start, world_end,
                     truth, biases, pco_body_m or None, rinex3=out.rinex3, rinex2=out.rinex2,
                     truth_sp3=out.truth_sp3, truth_nc=out.truth_nc, crd=out.crd)


if __name__ == "__main__":
    configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    sm = snakemake  # noqa: F821
    main(date=sm.wildcards.date, sat=sm.wildcards.sat, settings=sm.params.settings,
         world_start=sm.params.world_start, world_end=sm.params.world_end,
         pco_body_m=sm.params.pco_body_m, truth_path=sm.input.truth,
         biases_path=sm.input.biases, out=sm.output)
