"""Rule reference_orbit: a POD arc against a reference orbit over its day
(leopod.validation.reference)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging

from leopod.io.netcdf import load_netcdf, write_netcdf
from leopod.validation.reference import compare_day, read_reference_orbit
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


def main(orbit_path, reference_paths, out_path, *, date: str, reference_id, time_system,
         solution: str, title: str) -> None:
    """Orbit (netCDF) minus the reference orbit files over ``date`` into ``out_path``."""
    reference = read_reference_orbit(reference_paths, sv=reference_id)
    diff = compare_day(load_netcdf(orbit_path), reference, date, time_system=time_system)
    rms = diff.rms_m.sel(period="total")
    log.info("%s minus reference over %s (%d epochs): RMS R %.2f T %.2f N %.2f 3D %.2f cm",
             solution, date, int(diff.n_epochs.sel(period="total")),
             *(100 * float(rms.sel(component=c)) for c in ("R", "T", "N", "3D")))
    write_netcdf(diff, out_path, step="reference_orbit", inputs=[orbit_path, *reference_paths],
                 time_system="GPS", title=f"{solution} orbit minus reference {title}")


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    p = sm.params
    main(sm.input.orbit, list(sm.input.reference), sm.output.nc, date=sm.wildcards.date,
         reference_id=p.reference_id, time_system=p.time_system, solution=p.solution,
         title=p.title)


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("reference_orbit", sat="hy2b-sim", solution="fixed_pod",
                                   date="2019-002")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
