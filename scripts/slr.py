"""Rule slr: laser ranging residuals of one POD arc (leopod.validation.slr)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

from collections.abc import Mapping

from leopod.frames.leo_attitude import LeoAttitude
from leopod.io.attitude import load_leo_attitude
from leopod.io.blq import read_blq
from leopod.io.crd import read_crd
from leopod.io.netcdf import load_netcdf, write_netcdf
from leopod.io.sinex import read_sinex_eccentricities, read_sinex_stations
from leopod.validation.slr import SlrResidualSettings, slr_residuals
from leopod.workflow.boundary import attitude_files, plain
from leopod.workflow.log import configure_logging


def main(inputs: Mapping, out_path, *, retro_offset_body_m, settings: SlrResidualSettings,
         solution: str, title: str, attitude: LeoAttitude | None = None) -> None:
    """SLR residuals of an orbit. ``inputs``: ``orbit`` (netCDF), ``normal_points`` (CRD),
    ``stations`` (SINEX), optional ``eccentricities`` (SINEX) and ``ocean_loading`` (BLQ)."""
    res = slr_residuals(
        load_netcdf(inputs["orbit"]), read_crd(inputs["normal_points"]),
        read_sinex_stations(inputs["stations"]),
        read_sinex_eccentricities(inputs["eccentricities"])
        if inputs.get("eccentricities") else None,
        retro_offset_body_m=retro_offset_body_m, settings=settings,
        ocean_loading=read_blq(inputs["ocean_loading"]) if inputs.get("ocean_loading") else None,
        attitude=attitude)
    write_netcdf(res, out_path, step="slr", inputs=[v for k, v in inputs.items() if k != "code"],
                 time_system="UTC", reference_frame="ITRF",
                 title=f"SLR residuals of the {solution} orbit {title}")


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    p = sm.params
    main(plain(sm.input), sm.output.nc, retro_offset_body_m=p.retro_offset_body_m,
         settings=SlrResidualSettings.from_config(p.settings), solution=p.solution,
         title=p.title, attitude=load_leo_attitude(p.attitude, attitude_files(sm)))


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("slr", sat="hy2b-sim", solution="fixed_pod", date="2019-002")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
