"""Rule kinematic_baseline: epoch-wise baseline of a formation pair from receiver single
differences, float and with the fixed DDs of the baseline step, per system
(leopod.estimation.kinematic_baseline), against the reduced-dynamic baseline and the truth."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging
from collections.abc import Mapping

import numpy as np
import xarray as xr

from leopod.estimation.arc import ArcData, setup_arc
from leopod.estimation.fixed_arc import FloatSolution
from leopod.estimation.kinematic import KinematicSettings
from leopod.estimation.kinematic_baseline import KinematicBaseline, baseline_dataset
from leopod.estimation.outputs import pod_start
from leopod.io.attitude import load_leo_attitude
from leopod.io.netcdf import load_netcdf, write_netcdf
from leopod.plots.kinematic import plot_baseline_differences
from leopod.time.calendar import parse_date_id
from leopod.validation.formation import difference_rtn, rms_rtn, truth_baseline_itrf
from leopod.workflow.boundary import leo_antenna_of, plain
from leopod.workflow.log import configure_logging
from leopod.workflow.settings import pod_settings

log = logging.getLogger(__name__)

KINDS = ("float", "fixed")


def _receiver(date, files: Mapping, p: Mapping, signals, arc, forces, code_correction):
    """The arc problem of one satellite linearised at its float orbit, with its float POD's
    receiver clocks, and that orbit."""
    data = ArcData.read(files, signal_bias=p["signal_bias"], sampling_s=arc.sampling_s)
    fs = FloatSolution.read(parameters=files["float_parameters"],
                            ambiguities=files["float_ambiguities"],
                            residuals=files["float_residuals"], orbit=files["float_orbit"])
    problem = setup_arc(date, data, signals, arc, forces, leo_antenna_of(p["pco_body_m"], p["antenna"], files),
                        code_correction=code_correction, yaw_flips=p["yaw_flips"],
                        apriori_orbit=fs.orbit.pos_itrf_m,
                        attitude=load_leo_attitude(p["attitude"], files.get("attitude", ())))
    start = pod_start(fs.parameters, fs.ambiguities, fs.residuals, problem.observations)
    problem.observations.clk_rx_m = np.where(np.isfinite(start.clk_rx_m), start.clk_rx_m,
                                             problem.observations.clk_rx_m)
    return problem, fs.orbit, data.files


def main(date: str, inputs: Mapping, outputs: Mapping, *, pair: list, signals, arc, pod,
         forces, code_correction, kinematic: KinematicSettings,
         constraint_sigma_m: float) -> None:
    """Kinematic baselines of the day ``date``; ``inputs``: those of the baseline rule
    (``a_*``, ``b_*``) plus ``dd`` (its DD table) and ``dynamic`` (its baseline)."""
    split = [{k[2:]: v for k, v in inputs.items() if k.startswith(f"{key}_")}
             for key in ("a", "b")]
    (pa, orbit_a, files_a), (pb, orbit_b, files_b) = (
        _receiver(date, f, p, signals, arc, forces, code_correction)
        for f, p in zip(split, pair, strict=True))
    table = load_netcdf(inputs["dd"])
    dynamic = load_netcdf(inputs["dynamic"])
    day = np.datetime64(parse_date_id(date), "ns")
    times = pb.observations.times
    in_day = (times >= day) & (times < day + np.timedelta64(1, "D"))
    pair_solver = KinematicBaseline(pa.observations, pb.observations, pa.products, orbit_a,
                                    orbit_b, pa.t_ref, pod, kinematic, eop=pa.eop,
                                    antennas_a=pa.antennas, antennas_b=pb.antennas)
    leader = pair_solver.leader_state
    parts = []
    for system in kinematic.baseline_systems:
        by_kind = []
        for kind in KINDS:
            result = pair_solver.solve(system, table if kind == "fixed" else None,
                                       constraint_sigma_m)
            ds = baseline_dataset(result, leader, eop=pa.eop)
            stats = {"sigma0": (ds.attrs["sigma0"], "1", "a-posteriori sigma of unit weight"),
                     "dd_constraints": (ds.attrs["dd_constraints"], "1",
                                        "DD constraints in the solution"),
                     "epochs_solved": (int(ds.solved.values[in_day].sum()), "1",
                                       "epochs solved (the day)"),
                     "epochs": (int(in_day.sum()), "1", "epochs of the day"),
                     "isb_m": (ds.attrs["isb_m"][0] if ds.attrs["isb_m"].size else np.nan, "m",
                               "differential code inter-system bias of the second system")}
            by_kind.append(ds.drop_attrs(deep=False).assign(
                {k: ((), v, {"units": u, "long_name": n}) for k, (v, u, n) in stats.items()}))
        parts.append(xr.concat(by_kind, dim="ambiguities"))
    out = xr.concat(parts, dim="system").assign_coords(
        system=list(kinematic.baseline_systems), ambiguities=list(KINDS))
    out["in_day"] = ("time", in_day.astype("i1"), {
        "units": "1", "long_name": "1: epoch of the day (statistics), 0: rest of the arc"})
    t = out.time.values
    references = {"dynamic": dynamic.baseline_itrf_m.reindex(time=t).values}
    if "a_truth" in inputs and "b_truth" in inputs:
        truth = np.full((t.size, 3), np.nan)
        truth[in_day] = truth_baseline_itrf(inputs["a_truth"], inputs["b_truth"], t[in_day])
        references["truth"] = truth
    for name, ref in references.items():
        diff = np.full(out.baseline_itrf_m.shape[:3] + (3,), np.nan)
        rms = np.full(out.baseline_itrf_m.shape[:2] + (4,), np.nan)
        for i, system in enumerate(out.system.values):
            for j, kind in enumerate(KINDS):
                base = out.baseline_itrf_m.values[i, j]
                ok = (out.solved.values[i, j] == 1) & np.isfinite(ref).all(axis=1)
                diff[i, j, ok] = difference_rtn(base[ok], ref[ok], t[ok], leader[ok])
                r = rms_rtn(diff[i, j][in_day])
                rms[i, j] = [r["R"], r["T"], r["N"], r["3D"]]
                log.info("%s %s kinematic minus %s baseline: RMS R %.1f T %.1f N %.1f 3D %.1f "
                         "mm (%d epochs)", system, kind, name, *(1e3 * rms[i, j]), r["n"])
        out[f"minus_{name}_rtn_m"] = (("system", "ambiguities", "time", "rtn"), diff, {
            "units": "m", "long_name": f"kinematic minus {name} baseline, leader RTN"})
        out[f"rms_minus_{name}_m"] = (("system", "ambiguities", "component"), rms, {
            "units": "m", "long_name": f"RMS of kinematic minus {name} baseline (the day)"})
    out = out.assign_coords(component=["R", "T", "N", "3D"])
    names = tuple(p["sat"] for p in pair)
    out.attrs.update({"leader": names[0], "follower": names[1]})
    files = [*files_a, *files_b, inputs["dd"], inputs["dynamic"]]
    write_netcdf(out, outputs["nc"], step="kinematic_baseline", inputs=files,
                 time_system="GPS", title=f"kinematic baseline {names[1]} - {names[0]} {date}")
    plot_baseline_differences(out, outputs["figure"],
                              title=f"{pair[1]['title']} - {pair[0]['title']} {date}")


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    p = sm.params
    main(sm.wildcards.date, plain(sm.input), plain(sm.output), pair=list(p.pair),
         **pod_settings(p.signals, p.pod, p.code_bias),
         kinematic=KinematicSettings.from_config(p.kinematic),
         constraint_sigma_m=p.settings["constraint_sigma_m"])


if __name__ == "__main__":
    run(snakemake)  # noqa: F821 (injected by Snakemake)
