"""Rule overlap: the arc of a day against the next day's arc over their common span, for each
POD solution (leopod.validation.overlap)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging

from leopod.io.netcdf import load_netcdf, write_netcdf
from leopod.validation.overlap import overlap
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


def main(orbit_a, orbit_b, out_path, *, trim_s: float, title: str) -> None:
    """Overlap of two orbit files (netCDF) into ``out_path``."""
    ov = overlap(load_netcdf(orbit_a), load_netcdf(orbit_b), trim_s=trim_s)
    rms = ov.rms_m
    log.info("overlap %s to %s (%d epochs): RMS R %.2f T %.2f N %.2f 3D %.2f cm",
             ov.attrs["span_start"], ov.attrs["span_end"], int(ov.n_epochs),
             *(100 * float(rms.sel(component=c)) for c in ("R", "T", "N", "3D")))
    write_netcdf(ov, out_path, step="overlap", inputs=[orbit_a, orbit_b], time_system="GPS",
                 title=f"orbit overlap {title}")


def run(sm) -> None:
    """Call :func:`main` for each POD solution of the job (inputs ``<solution>_a`` and
    ``<solution>_b``, outputs ``nc`` in the order of ``params.solutions``)."""
    configure_logging(sm)
    for solution, out in zip(sm.params.solutions, sm.output.nc, strict=True):
        main(sm.input[f"{solution}_a"], sm.input[f"{solution}_b"], out,
             trim_s=sm.params.trim_s, title=f"{solution} {sm.params.title}")


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("overlap", sat="hy2b-sim", date="2019-002")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
