"""Snakemake script of rule slr_summary: SLR statistics per station (seed 000 Table IV), per
elevation bin (seed 000 Figs. 17-18) and projected on R/T/N (seed 001 Table 5)."""

import pandas as pd
import xarray as xr

from leopod.io import write_text
from leopod.io.netcdf import write_netcdf
from leopod.plots.slr import plot_slr_elevation, plot_slr_residuals_time, plot_slr_stations
from leopod.validation.slr_statistics import (
    elevation_statistics,
    rtn_projection,
    station_statistics,
)
from leopod.workflow.log import configure_logging


def _table(stats: dict[str, xr.Dataset], dim: str, names) -> str:
    frames = []
    for solution, ds in stats.items():
        df = pd.DataFrame({n: ds[n].values for n in names}, index=ds[dim].values.astype(str))
        df.index.name = dim
        frames.append(df.assign(solution=solution).set_index("solution", append=True))
    return pd.concat(frames).to_csv(float_format="%.5f")


def main(inp, out, params, log):
    residuals = {s: xr.concat([xr.load_dataset(p) for p in inp[s]], dim="point")
                 for s in params.solutions}
    bin_deg = params.settings["elevation_bin_deg"]
    stations = {s: station_statistics(r) for s, r in residuals.items()}
    elevation = {s: elevation_statistics(r, bin_deg) for s, r in residuals.items()}
    rtn = {s: rtn_projection(r) for s, r in residuals.items()}
    for s in params.solutions:
        total = stations[s].sel(station="total")
        log.info("%s: %d normal points, mean %.2f cm, STD %.2f cm", s, int(total.n_np),
                 100 * float(total.mean_m), 100 * float(total.std_m))
    index = pd.Index(list(params.solutions), name="solution")
    ds = xr.merge([xr.concat(list(stations.values()), dim=index),
                   xr.concat(list(elevation.values()), dim=index).rename(
                       {k: f"elevation_{k}" for k in ("n_np", "mean_m", "std_m", "rms_m")}),
                   xr.concat(list(rtn.values()), dim=index).rename(
                       {k: f"rtn_{k}" for k in rtn[params.solutions[0]].data_vars})],
                  combine_attrs="override")
    write_netcdf(ds, out.nc, step="slr_summary",
                 inputs=[f for s in params.solutions for f in inp[s]], time_system="UTC",
                 title=f"SLR residual statistics {params.title}")
    write_text(out.stations_csv, _table(stations, "station", ("n_np", "mean_m", "std_m", "rms_m")))
    write_text(out.elevation_csv, _table(elevation, "elevation_deg",
                                         ("n_np", "mean_m", "std_m", "rms_m")))
    plot_slr_stations(residuals, out.stations_png, title=params.title)
    plot_slr_elevation(residuals, out.elevation_png, title=params.title, bin_deg=bin_deg)
    plot_slr_residuals_time(residuals[params.solutions[-1]], out.time_png,
                            title=f"{params.title} {params.solutions[-1]}")


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    main(snakemake.input, snakemake.output, snakemake.params, log)  # noqa: F821
