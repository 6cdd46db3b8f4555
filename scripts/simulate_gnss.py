"""Rule simulate_gnss: GNSS orbit, clock and bias products of one simulated day
(leopod.simulate.campaign)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

from collections.abc import Mapping

import xarray as xr

from leopod.simulate.campaign import simulate_gnss_products
from leopod.simulate.settings import SimulationSettings
from leopod.workflow.boundary import plain
from leopod.workflow.log import configure_logging


def main(date: str, settings: SimulationSettings, world_start: str, world_end: str,
         biases_path, outputs: Mapping) -> None:
    """Products of ``date`` into ``outputs``: ``orbit`` (SP3), ``clock`` and
    ``integer_clock`` (RINEX clock), ``wl_bias``, ``osb`` and ``dcb_p1c1`` (CODE-style
    P1-C1 DCBs of the simulated satellites)."""
    with xr.open_dataset(biases_path) as f:
        biases = f.load()
    simulate_gnss_products(date, settings, world_start, world_end, biases,
                           orbit=outputs["orbit"], clock=outputs["clock"],
                           integer_clock=outputs["integer_clock"], wl_bias=outputs["wl_bias"],
                           osb=outputs["osb"], dcb_p1c1=outputs.get("dcb_p1c1"))


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    main(sm.wildcards.date, SimulationSettings.from_config(sm.params.settings),
         sm.params.world_start, sm.params.world_end, sm.input.biases, plain(sm.output))


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("simulate_gnss", date="2019-002")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
