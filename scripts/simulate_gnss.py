"""Snakemake script of rule simulate_gnss: see leopod.simulate.campaign."""

import xarray as xr

from leopod.simulate.campaign import simulate_gnss_products
from leopod.simulate.settings import SimulationSettings
from leopod.workflow.log import configure_logging


def main(date, settings, world_start, world_end, biases_path, out):
    with xr.open_dataset(biases_path) as f:
        biases = f.load()
    simulate_gnss_products(date, SimulationSettings.from_config(settings), world_start,
                           world_end, biases, orbit=out.orbit, clock=out.clock,
                           integer_clock=out.integer_clock, wl_bias=out.wl_bias, osb=out.osb)


if __name__ == "__main__":
    configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    sm = snakemake  # noqa: F821
    main(date=sm.wildcards.date, settings=sm.params.settings,
         world_start=sm.params.world_start, world_end=sm.params.world_end,
         biases_path=sm.input.biases, out=sm.output)
