"""Rule simulate_truth: the true orbit of a simulated satellite, the code-bias map truth and
the manoeuvre file (leopod.simulate.campaign)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

from leopod.simulate.campaign import (
    simulate_truth,
    write_code_bias_maps,
    write_manoeuvre_file,
    write_truth_orbit,
)
from leopod.simulate.formation import FormationSettings
from leopod.simulate.settings import SimulationSettings
from leopod.workflow.log import configure_logging


def main(sat: str, settings: SimulationSettings, world_start: str, world_end: str, truth_path,
         map_path, manoeuvre_path, formation: FormationSettings | None = None) -> None:
    """Integrate the truth orbit of ``sat`` (a follower of ``formation`` if given) over the
    world's span into ``truth_path``, write its burns into ``manoeuvre_path`` and the
    simulated code-bias maps into ``map_path``."""
    truth = simulate_truth(settings, sat, world_start, world_end, formation=formation)
    write_truth_orbit(truth, truth_path)
    write_manoeuvre_file(truth, manoeuvre_path)
    write_code_bias_maps(settings, map_path)


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    main(sat=sm.wildcards.sat, settings=SimulationSettings.from_config(sm.params.settings),
         world_start=sm.params.world_start, world_end=sm.params.world_end,
         truth_path=sm.output.truth, map_path=sm.output.code_bias_map,
         manoeuvre_path=sm.output.manoeuvres,
         formation=(None if sm.params.formation is None
                    else FormationSettings.from_config(sm.params.formation)))


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("simulate_truth", sat="hy2b-sim")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
