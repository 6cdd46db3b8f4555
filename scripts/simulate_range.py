"""Rule simulate_range: the simulated inter-satellite range of a formation pair for a day
(leopod.simulate.ranging), in the grc_kb_rng.csv layout."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one


from leopod.io.grace_orbit_csv import write_kband_range_csv
from leopod.io.netcdf import load_netcdf
from leopod.simulate.ranging import simulated_range
from leopod.simulate.settings import SimulationSettings
from leopod.workflow.log import configure_logging


def main(truth_a, truth_b, out_path, *, settings: SimulationSettings, label: str,
         sigma_m: float) -> None:
    """Range of the truth orbits ``truth_a``, ``truth_b`` (netCDF) into ``out_path``."""
    ds = simulated_range(load_netcdf(truth_a), load_netcdf(truth_b), sigma_m,
                         settings.int_seed(f"range/{label}"))
    write_kband_range_csv(ds, out_path)


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    main(sm.input.a, sm.input.b, sm.output.csv,
         settings=SimulationSettings.from_config(sm.params.settings),
         label=f"{sm.wildcards.pair}/{sm.wildcards.date}",
         sigma_m=sm.params.settings["range_sigma_m"])


if __name__ == "__main__":
    run(snakemake)  # noqa: F821 (injected by Snakemake)
