"""Rule reference_orbit: the arc of each POD solution against a reference orbit over its day
(leopod.validation.reference)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging
from collections.abc import Mapping

from leopod.io.netcdf import load_netcdf, write_netcdf
from leopod.validation.reference import compare_day, read_reference_orbit
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


def main(orbits: Mapping, reference_paths, outputs: Mapping, *, date: str, reference_id,
         time_system, title: str) -> None:
    """Each solution's orbit (``orbits``: solution -> netCDF) minus the reference orbit files
    over ``date`` into ``outputs`` (solution -> netCDF)."""
    reference = read_reference_orbit(reference_paths, sv=reference_id)
    for solution, orbit_path in orbits.items():
        diff = compare_day(load_netcdf(orbit_path), reference, date, time_system=time_system)
        rms = diff.rms_m.sel(period="total")
        log.info("%s minus reference over %s (%d epochs): RMS R %.2f T %.2f N %.2f 3D %.2f cm",
                 solution, date, int(diff.n_epochs.sel(period="total")),
                 *(100 * float(rms.sel(component=c)) for c in ("R", "T", "N", "3D")))
        write_netcdf(diff, outputs[solution], step="reference_orbit",
                     inputs=[orbit_path, *reference_paths], time_system="GPS",
                     title=f"{solution} orbit minus reference {title}")


def run(sm) -> None:
    """Call :func:`main` with the job's files (an orbit input per solution, outputs ``nc`` in
    the order of ``params.solutions``) and settings."""
    configure_logging(sm)
    p = sm.params
    main({s: sm.input[s] for s in p.solutions}, list(sm.input.reference),
         dict(zip(p.solutions, sm.output.nc, strict=True)), date=sm.wildcards.date,
         reference_id=p.reference_id, time_system=p.time_system, title=p.title)


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("reference_orbit", sat="hy2b-sim", date="2019-002")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
