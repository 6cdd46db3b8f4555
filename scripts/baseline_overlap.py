"""Rule baseline_overlap: the baseline solutions of two consecutive days over their common span
(leopod.validation.formation.baseline_overlap)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging

import numpy as np
import xarray as xr

from leopod.estimation.kinematic import orbit_state
from leopod.io.netcdf import load_netcdf, write_netcdf
from leopod.validation.formation import baseline_overlap, rms_rtn
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


def _solutions(a: xr.Dataset, b: xr.Dataset, kind: str) -> dict:
    """``{label: (times_a, base_a, times_b, base_b)}`` of the dynamic or kinematic files."""
    if kind == "dynamic":
        return {f"dynamic {name}": (a.time.values, a[var].values, b.time.values, b[var].values)
                for name, var in (("float", "float_baseline_itrf_m"),
                                  ("DD-fixed", "baseline_itrf_m"))}
    out = {}
    for x in a.system.values:
        for amb in a.ambiguities.values:
            name = "DD-fixed" if amb == "fixed" else str(amb)
            sel = {"system": x, "ambiguities": amb}
            out[f"kinematic {x} {name}"] = (a.time.values, a.baseline_itrf_m.sel(sel).values,
                                            b.time.values, b.baseline_itrf_m.sel(sel).values)
    return out


def main(inputs: dict, nc_path) -> None:
    """RMS R/T/N/3D of the differences of every solution over the common span."""
    leader = load_netcdf(inputs["leader"])
    labels, rms, counts = [], [], []
    for kind in ("dynamic", "kinematic"):
        if f"{kind}_a" not in inputs:
            continue
        a, b = load_netcdf(inputs[f"{kind}_a"]), load_netcdf(inputs[f"{kind}_b"])
        state = orbit_state(leader, a.time.values, a.time.values[0])    # the RTN axes
        for label, (ta, ba, tb, bb) in _solutions(a, b, kind).items():
            times, diff = baseline_overlap(ta, ba, tb, bb, state)
            r = rms_rtn(diff)
            if r["n"] == 0:
                log.warning("%s: the two solutions have no common epoch (baselines of the "
                            "day only?)", label)
            else:
                log.info("%s overlap %s to %s: RMS R %.2f T %.2f N %.2f 3D %.2f mm (%d epochs)",
                         label, times[0], times[-1], *(1e3 * np.array(
                             [r["R"], r["T"], r["N"], r["3D"]])), r["n"])
            labels.append(label)
            rms.append([r["R"], r["T"], r["N"], r["3D"]])
            counts.append(r["n"])
    ds = xr.Dataset(
        {"rms_m": (("solution", "component"), np.array(rms, dtype=float).reshape(-1, 4), {
            "units": "m", "long_name": "RMS of earlier minus later solution over the common "
            "span, leader RTN"}),
         "n_epochs": ("solution", np.array(counts, dtype=int), {
             "units": "1", "long_name": "common epochs"})},
        coords={"solution": labels, "component": ["R", "T", "N", "3D"]})
    write_netcdf(ds, nc_path, step="baseline_overlap", inputs=list(inputs.values()),
                 time_system="GPS", title="baseline overlap")


def run(sm) -> None:
    """Call :func:`main` with the job's files."""
    configure_logging(sm)
    main({k: v for k, v in sm.input.items() if k != "code"}, sm.output.nc)


if __name__ == "__main__":
    run(snakemake)  # noqa: F821 (injected by Snakemake)
