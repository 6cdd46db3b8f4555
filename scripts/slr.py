"""Rule slr: laser ranging residuals of the arc of each POD solution (leopod.validation.slr)."""

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


def main(inputs: Mapping, outputs: Mapping, *, retro_offset_body_m,
         settings: SlrResidualSettings, title: str, attitude: LeoAttitude | None = None) -> None:
    """SLR residuals of the orbit of each solution. ``inputs``: an orbit (netCDF) per solution
    named in ``outputs`` (solution -> netCDF), ``normal_points`` (CRD), ``stations`` (SINEX),
    optional ``eccentricities`` (SINEX) and ``ocean_loading`` (BLQ)."""
    normal_points = read_crd(inputs["normal_points"])
    stations = read_sinex_stations(inputs["stations"])
    eccentricities = (read_sinex_eccentricities(inputs["eccentricities"])
                      if inputs.get("eccentricities") else None)
    ocean_loading = read_blq(inputs["ocean_loading"]) if inputs.get("ocean_loading") else None
    shared = [v for k, v in inputs.items() if k != "code" and k not in outputs]
    for solution, out_path in outputs.items():
        res = slr_residuals(load_netcdf(inputs[solution]), normal_points, stations,
                            eccentricities, retro_offset_body_m=retro_offset_body_m,
                            settings=settings, ocean_loading=ocean_loading, attitude=attitude)
        write_netcdf(res, out_path, step="slr", inputs=[inputs[solution], *shared],
                     time_system="UTC", reference_frame="ITRF",
                     title=f"SLR residuals of the {solution} orbit {title}")


def run(sm) -> None:
    """Call :func:`main` with the job's files (an orbit input per solution, outputs ``nc`` in
    the order of ``params.solutions``) and settings."""
    configure_logging(sm)
    p = sm.params
    main(plain(sm.input), dict(zip(p.solutions, sm.output.nc, strict=True)),
         retro_offset_body_m=p.retro_offset_body_m,
         settings=SlrResidualSettings.from_config(p.settings), title=p.title,
         attitude=load_leo_attitude(p.attitude, attitude_files(sm)))


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("slr", sat="hy2b-sim", date="2019-002")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
