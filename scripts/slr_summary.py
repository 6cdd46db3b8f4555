"""Rule slr_summary: SLR statistics per station (Peng et al. 2021, Table IV), per elevation
bin (Peng et al. 2021, Figs. 17-18) and projected on R/T/N (Wang et al. 2024, Table 5)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging
from collections.abc import Mapping

import pandas as pd
import xarray as xr

from leopod.io import write_text
from leopod.io.netcdf import load_netcdf, write_netcdf
from leopod.plots.slr import plot_slr_elevation, plot_slr_residuals_time, plot_slr_stations
from leopod.plots.tables import frame_tables, html_page
from leopod.validation.slr_statistics import (
    elevation_statistics,
    rtn_projection,
    station_statistics,
)
from leopod.workflow.boundary import plain
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


#: The columns of the per-station and per-elevation tables.
_COLUMNS = ("n_np", "mean_m", "std_m", "rms_m")


def _frames(stats: dict[str, xr.Dataset], dim: str) -> dict[str, pd.DataFrame]:
    """``{solution: table}`` of the statistics along ``dim`` (:data:`_COLUMNS`)."""
    frames = {}
    for solution, ds in stats.items():
        df = pd.DataFrame({n: ds[n].values for n in _COLUMNS}, index=ds[dim].values.astype(str))
        df.index.name = dim
        frames[solution] = df
    return frames


def _table(stats: dict[str, xr.Dataset], dim: str) -> str:
    """CSV of the statistics of every solution along ``dim``."""
    return pd.concat([df.assign(solution=s).set_index("solution", append=True)
                      for s, df in _frames(stats, dim).items()]).to_csv(float_format="%.5f")


def main(residual_files: Mapping, outputs: Mapping, *, elevation_bin_deg: float,
         title: str) -> None:
    """Statistics of the daily SLR residual files of every solution (``{solution: [paths]}``,
    the last one is plotted over time) into ``outputs``: ``nc``, ``stations_csv``,
    ``stations_html`` (report table), ``elevation_csv``, ``stations_png``, ``elevation_png``, ``time_png``."""
    solutions = list(residual_files)
    residuals = {s: xr.concat([load_netcdf(p) for p in files], dim="point")
                 for s, files in residual_files.items()}
    stations = {s: station_statistics(r) for s, r in residuals.items()}
    elevation = {s: elevation_statistics(r, elevation_bin_deg) for s, r in residuals.items()}
    rtn = {s: rtn_projection(r) for s, r in residuals.items()}
    for s in solutions:
        total = stations[s].sel(station="total")
        log.info("%s: %d normal points, mean %.2f cm, STD %.2f cm", s, int(total.n_np),
                 100 * float(total.mean_m), 100 * float(total.std_m))
    index = pd.Index(solutions, name="solution")
    ds = xr.merge([xr.concat(list(stations.values()), dim=index),
                   xr.concat(list(elevation.values()), dim=index).rename(
                       {k: f"elevation_{k}" for k in ("n_np", "mean_m", "std_m", "rms_m")}),
                   xr.concat(list(rtn.values()), dim=index).rename(
                       {k: f"rtn_{k}" for k in rtn[solutions[0]].data_vars})],
                  combine_attrs="override")
    write_netcdf(ds, outputs["nc"], step="slr_summary",
                 inputs=[f for files in residual_files.values() for f in files],
                 time_system="UTC", title=f"SLR residual statistics {title}")
    write_text(outputs["stations_csv"], _table(stations, "station"))
    write_text(outputs["stations_html"], html_page(f"{title}: SLR residuals per station",
                                                   frame_tables(
        _frames(stations, "station"), row_header="station", missing="no normal points",
        aggregate=lambda label: label == "total")))
    write_text(outputs["elevation_csv"], _table(elevation, "elevation_deg"))
    plot_slr_stations(stations, outputs["stations_png"], title=title)
    plot_slr_elevation(residuals, elevation, outputs["elevation_png"], title=title)
    plot_slr_residuals_time(residuals[solutions[-1]], outputs["time_png"],
                            title=f"{title} {solutions[-1]}")


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    files = plain(sm.input)
    main({s: files[s] for s in sm.params.solutions}, plain(sm.output),
         elevation_bin_deg=sm.params.settings["elevation_bin_deg"], title=sm.params.title)


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("slr_summary", sat="hy2b-sim")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
