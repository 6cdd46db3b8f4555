"""Rule simulate: onboard observations, truth and SLR normal points of one simulated
satellite-day (leopod.simulate.campaign)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

from collections.abc import Mapping

import xarray as xr

from leopod.frames.leo_attitude import LeoAttitude
from leopod.io.attitude import load_leo_attitude
from leopod.simulate.campaign import simulate_leo_day
from leopod.simulate.settings import SimulationSettings
from leopod.workflow.boundary import attitude_files, leo_antenna_of, plain
from leopod.workflow.log import configure_logging


def main(date: str, sat: str, settings: SimulationSettings, world_start: str, world_end: str,
         pco_body_m, truth_path, biases_path, outputs: Mapping,
         attitude: LeoAttitude | None = None) -> None:
    """Simulate ``sat`` on ``date`` into ``outputs``: ``rinex3``, ``rinex2`` (absent without
    simulated GPS), ``truth_sp3``, ``truth_nc`` and ``crd``."""
    with xr.open_dataset(truth_path) as f:
        truth = f.load()
    with xr.open_dataset(biases_path) as f:
        biases = f.load()
    simulate_leo_day(date, sat, settings, world_start, world_end, truth, biases,
                     pco_body_m or None, rinex3=outputs["rinex3"], rinex2=outputs.get("rinex2"),
                     truth_sp3=outputs["truth_sp3"], truth_nc=outputs["truth_nc"],
                     crd=outputs["crd"], leo_attitude=attitude)


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    antenna = leo_antenna_of(sm.params.pco_body_m, sm.params.leo_antenna, plain(sm.input))
    main(sm.wildcards.date, sm.wildcards.sat, SimulationSettings.from_config(sm.params.settings),
         sm.params.world_start, sm.params.world_end, antenna, sm.input.truth,
         sm.input.biases, plain(sm.output), load_leo_attitude(sm.params.attitude, attitude_files(sm)))


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("simulate", sat="hy2b-sim", date="2019-002")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
