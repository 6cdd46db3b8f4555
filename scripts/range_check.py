"""Rule range_check: the length of every baseline solution of a formation pair-day against the
inter-satellite range (leopod.validation.formation)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging

import numpy as np
import xarray as xr

from leopod.io.grace_orbit_csv import read_kband_range_csv
from leopod.io.netcdf import load_netcdf, write_netcdf
from leopod.plots.validation import plot_range_check
from leopod.time.calendar import parse_date_id
from leopod.validation.formation import range_residuals
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


def _solutions(dynamic: xr.Dataset, kinematic: xr.Dataset | None) -> dict:
    """``{label: (times, baseline_itrf_m)}`` of every solution of the day."""
    out = {"dynamic float": (dynamic.time.values, dynamic.float_baseline_itrf_m.values),
           "dynamic DD-fixed": (dynamic.time.values, dynamic.baseline_itrf_m.values)}
    if kinematic is not None:
        for system in kinematic.system.values:
            for kind in kinematic.ambiguities.values:
                b = kinematic.baseline_itrf_m.sel(system=system, ambiguities=kind)
                label = f"kinematic {system} {'DD-fixed' if kind == 'fixed' else kind}"
                out[label] = (kinematic.time.values, b.values)
    return out


def main(range_path, dynamic_path, kinematic_path, nc_path, figure_path, *, date: str,
         title: str) -> None:
    """Residuals |baseline| − range of every solution over the day ``date`` (YYYY-DDD), their
    statistics and figure."""
    rng = read_kband_range_csv(range_path)
    dynamic = load_netcdf(dynamic_path)
    kinematic = None if kinematic_path is None else load_netcdf(kinematic_path)
    day = np.datetime64(parse_date_id(date), "ns")
    times = dynamic.time.values
    times = times[(times >= day) & (times < day + np.timedelta64(1, "D"))]
    labels, residuals, stats = [], [], []
    for label, (t, base) in _solutions(dynamic, kinematic).items():
        res = range_residuals(base, t, rng.range_m.values, rng.time.values)
        res = xr.DataArray(res, coords={"time": t}).reindex(time=times).values
        ok = np.isfinite(res)
        mean = float(np.mean(res[ok])) if ok.any() else np.nan
        std = float(np.std(res[ok])) if ok.any() else np.nan
        rms = float(np.sqrt(np.mean(res[ok] ** 2))) if ok.any() else np.nan
        log.info("%s: |baseline| - range mean %+.2f mm, STD %.2f mm, RMS %.2f mm (%d epochs)",
                 label, 1e3 * mean, 1e3 * std, 1e3 * rms, int(ok.sum()))
        labels.append(label)
        residuals.append(res)
        stats.append((mean, std, rms, int(ok.sum())))
    stats = np.array(stats, dtype=float)
    ds = xr.Dataset(
        {"residual_m": (("solution", "time"), np.array(residuals), {
            "units": "m", "long_name": "baseline length minus inter-satellite range"}),
         "mean_m": ("solution", stats[:, 0], {"units": "m", "long_name": "mean residual"}),
         "std_m": ("solution", stats[:, 1], {"units": "m", "long_name": "STD of the residuals"}),
         "rms_m": ("solution", stats[:, 2], {"units": "m", "long_name": "RMS of the residuals"}),
         "count": ("solution", stats[:, 3].astype(int), {"units": "1",
                                                        "long_name": "epochs compared"})},
        coords={"solution": labels, "time": times},
        attrs={"range_file": str(range_path)})
    inputs = [range_path, dynamic_path] + ([kinematic_path] if kinematic_path else [])
    write_netcdf(ds, nc_path, step="range_check", inputs=inputs, time_system="GPS",
                 title=f"range check {title}")
    plot_range_check(ds, figure_path, title=title)


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    main(sm.input.range, sm.input.dynamic, getattr(sm.input, "kinematic", None),
         sm.output.nc, sm.output.figure, date=sm.wildcards.date,
         title=f"{sm.params.title} {sm.wildcards.date}")


if __name__ == "__main__":
    run(snakemake)  # noqa: F821 (injected by Snakemake)
