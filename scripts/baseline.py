"""Rule baseline: DD ambiguity resolution and the joint DD-fixed solution of a formation pair
(leopod.ambiguity.double_difference, leopod.estimation.baseline)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging
import textwrap
from collections.abc import Mapping

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from leopod.ambiguity.double_difference import ReceiverArc, resolve_dd_systems  # noqa: E402
from leopod.ambiguity.resolve import ArSettings  # noqa: E402
from leopod.estimation.arc import ArcData, arc_outputs  # noqa: E402
from leopod.estimation.baseline import (  # noqa: E402
    BaselineSettings,
    constraint_residuals,
    dd_rows,
    fixed_baseline,
    fixed_correction,
    float_baseline,
    joint_solve,
    reference_fixed_solve,
    relative_rows,
)
from leopod.estimation.fixed_arc import FixedSolutions, FloatSolution  # noqa: E402
from leopod.estimation.outputs import sp3_dataset  # noqa: E402
from leopod.io.attitude import load_leo_attitude  # noqa: E402
from leopod.io.netcdf import load_netcdf, merge_days, write_netcdf  # noqa: E402
from leopod.io.sp3_write import write_sp3  # noqa: E402
from leopod.plots.ambiguity import plot_fractional_parts  # noqa: E402
from leopod.time.calendar import parse_date_id  # noqa: E402
from leopod.validation.formation import (  # noqa: E402
    difference_rtn,
    rms_rtn,
    sd_residual_rms,
    truth_baseline_itrf,
)
from leopod.workflow.boundary import leo_antenna_of, plain  # noqa: E402
from leopod.workflow.log import configure_logging  # noqa: E402
from leopod.workflow.settings import pod_settings  # noqa: E402

log = logging.getLogger(__name__)


def _split(inputs: Mapping, key: str) -> dict:
    prefix = f"{key}_"
    return {k[len(prefix):]: v for k, v in inputs.items() if k.startswith(prefix)}


def _float_passes(fs: FloatSolution) -> xr.Dataset:
    """The float residuals with ``pass_index`` −1 for passes without a float ambiguity (too
    few phase observations, dropped by the POD): the DD nodes are formed of estimated
    ambiguities only, as the single differences of the ambiguity step."""
    res = fs.residuals.copy()
    pid = res.pass_index
    known = np.isin(pid.values, fs.ambiguities.pass_index.values)
    dropped = np.unique(pid.values[(pid.values >= 0) & ~known])
    if dropped.size:
        log.info("%d passes without a float ambiguity left out of the DDs", dropped.size)
    res["pass_index"] = pid.where(known | (pid < 0), -1)
    return res


def main(date: str, inputs: Mapping, outputs: Mapping, *, pair: list, signals, arc, pod,
         forces, code_correction, ambiguity: ArSettings,
         baseline: BaselineSettings | None = None) -> None:
    """Baseline of the day ``date`` of a pair; ``inputs``: float_pod's inputs and the float
    solution of the leader (``a_*``) and follower (``b_*``), optional ``*_truth`` (the
    simulator's daily truth netCDF)."""
    by_system = signals if isinstance(signals, Mapping) else {arc.systems[0]: signals}
    names = tuple(p["sat"] for p in pair)
    fixed, receivers, floats = [], [], []
    for key, p in zip(("a", "b"), pair, strict=True):
        files = _split(inputs, key)
        data = ArcData.read(files, signal_bias=p["signal_bias"])
        fs = FloatSolution.read(parameters=files["float_parameters"],
                                ambiguities=files["float_ambiguities"],
                                residuals=files["float_residuals"], orbit=files["float_orbit"])
        floats.append(fs)
        receivers.append(ReceiverArc(fs.ambiguities, _float_passes(fs), merge_days(data.obs)))
        fixed.append(FixedSolutions(date, data, signals, arc, pod, forces, leo_antenna_of(p["pco_body_m"], p["antenna"], files), fs,
                                    code_correction=code_correction, yaw_flips=p["yaw_flips"],
                                    attitude=load_leo_attitude(p["attitude"],
                                                                files.get("attitude", ()))))
    dd = resolve_dd_systems(*receivers, by_system, ambiguity, names=names)
    baseline = BaselineSettings.from_config({}) if baseline is None else baseline
    if baseline.dd_constraint_sigma_m is not None:
        dd = dd._replace(constraints=dd.constraints._replace(sigma_m=np.full_like(
            dd.constraints.sigma_m, baseline.dd_constraint_sigma_m)))
    normals = [f.pod.normals() for f in fixed]
    design, misclosure, weight = dd_rows(
        *normals, floats[0].ambiguities.pass_index.values,
        floats[1].ambiguities.pass_index.values, dd.constraints)
    n_dd = weight.size
    rel_counts = {}
    if baseline.dynamics == "relative":
        rel = relative_rows(*normals, baseline)
        rel_counts = rel[3]
        log.info("relative dynamics: %s rows tie the follower's parameters to the leader's",
                 rel_counts)
        design = np.vstack([design, rel[0]])
        misclosure = np.concatenate([misclosure, rel[1]])
        weight = np.concatenate([weight, rel[2]])
    if baseline.mode == "reference_fixed":
        dx_a = fixed_correction(normals[0], load_netcdf(inputs["a_fixed_parameters"]),
                                load_netcdf(inputs["a_fixed_ambiguities"]))
        joint = reference_fixed_solve(*normals, design, misclosure, weight, dx_a)
    else:
        joint = joint_solve(*normals, design, misclosure, weight)
    log.info("%s solution (%s dynamics): %d + %d parameters, %d DD constraints",
             baseline.mode, baseline.dynamics, joint.n_a, joint.dx_b.size, n_dd)
    resid = constraint_residuals(design, misclosure, joint.dx_a, joint.dx_b)
    dd_resid = resid[:n_dd]
    norm_rel = resid[n_dd:] * np.sqrt(weight[n_dd:])
    log.info("DD constraint residuals after the solve: RMS %.2e m, max %.2e m (sigma %.1e m)",
             np.sqrt(np.mean(dd_resid**2)) if n_dd else 0.0,
             np.max(np.abs(dd_resid), initial=0.0),
             1.0 / np.sqrt(weight[0]) if n_dd else np.nan)
    if norm_rel.size:
        log.info("relative-dynamics residuals / sigma: RMS %.2f, max %.2f",
                 np.sqrt(np.mean(norm_rel**2)), np.max(np.abs(norm_rel)))
    na = joint.n_a
    res = [fixed[0].pod.solution(normals[0], joint.dx_a, joint.covariance[:na, :na]),
           fixed[1].pod.solution(normals[1], joint.dx_b, joint.covariance[na:, na:])]
    outs = [arc_outputs(f.problem, r) for f, r in zip(fixed, res, strict=True)]
    day = np.datetime64(parse_date_id(date), "ns")
    # the whole common arc (30 h: overlaps with the neighbouring days); statistics over the day
    times = np.intersect1d(floats[0].orbit.time.values, floats[1].orbit.time.values)
    in_day = (times >= day) & (times < day + np.timedelta64(1, "D"))
    fix = fixed_baseline(times, *res, joint, label=(
        "DD-fixed, leader held at its fixed POD" if baseline.mode == "reference_fixed"
        else "DD-fixed joint solution"))
    flo = float_baseline(floats[0].orbit, floats[1].orbit, times)
    out = xr.merge([fix, flo.rename({v: f"float_{v}" for v in flo.data_vars})])
    out["in_day"] = ("time", in_day.astype("i1"), {
        "units": "1", "long_name": "1: epoch of the day (statistics), 0: rest of the arc"})
    attrs = {k: v for k, v in dd.table.attrs.items() if k.startswith(("wl_", "nl_", "systems"))
             or k.split("_", 1)[-1] in ("wl_fixing_rate", "nl_fixing_rate", "wl_dd_fixed_share",
                                         "nl_dd_fixed_share", "n_independent", "n_nodes")}
    attrs.update({"leader": names[0], "follower": names[1],
                  "baseline_mode": baseline.mode, "baseline_dynamics": baseline.dynamics,
                  **{f"n_relative_{k}": v for k, v in rel_counts.items()},
                  "dd_constraint_residual_rms_m": float(np.sqrt(np.mean(dd_resid**2)))
                  if n_dd else 0.0,
                  "dd_constraint_residual_max_m": float(np.max(np.abs(dd_resid), initial=0.0)),
                  "n_dd_constraints_used": n_dd,
                  "n_dd_candidates": int(dd.table.sizes["dd"])})
    # residuals of the receiver single differences per system (Zhang et al. 2024, Fig. 3)
    for label, pair_res in (("fixed", [o.residuals for o in outs]),
                            ("float", [f.residuals for f in floats])):
        for key, (rms, n) in sd_residual_rms(*pair_res).items():
            attrs[f"{label}_sd_{key}_rms_m"] = rms
            attrs[f"{label}_sd_{key}_count"] = n
    log.info("SD residual RMS, DD-fixed: %s", ", ".join(
        f"{k.split('_sd_')[1][:-6]} {1e3 * v:.2f} mm" for k, v in attrs.items()
        if k.startswith("fixed_sd_") and k.endswith("_rms_m")))
    if "a_truth" in inputs and "b_truth" in inputs:
        # the truth files of the day only
        truth = truth_baseline_itrf(inputs["a_truth"], inputs["b_truth"], times[in_day])
        leader = np.concatenate([floats[0].orbit.pos_gcrf_m.sel(time=times[in_day]).values,
                                 floats[0].orbit.vel_gcrf_m_s.sel(time=times[in_day]).values],
                                axis=1)
        for label, prefix in (("fixed", ""), ("float", "float_")):
            err = np.full((times.size, 3), np.nan)
            err[in_day] = difference_rtn(out[f"{prefix}baseline_itrf_m"].values[in_day], truth,
                                         times[in_day], leader)
            out[f"{prefix}error_rtn_m"] = (("time", "rtn"), err, {
                "units": "m", "long_name": f"{label} baseline minus truth, leader RTN"})
            r = rms_rtn(err)
            attrs.update({f"{label}_rms_{c.lower()}_m": r[c] for c in ("R", "T", "N", "3D")})
        log.info("baseline vs truth, 3D RMS: float %.2f mm, fixed %.2f mm",
                 1e3 * attrs["float_rms_3d_m"], 1e3 * attrs["fixed_rms_3d_m"])
    change = (out["baseline_rtn_m"].values - out["float_baseline_rtn_m"].values)[in_day]
    attrs["fixed_minus_float_rms_3d_m"] = float(np.sqrt(np.mean(np.sum(change**2, axis=1))))
    log.info("DD-fixed minus float baseline: 3D RMS %.2f mm",
             1e3 * attrs["fixed_minus_float_rms_3d_m"])
    out.attrs.update(attrs)
    files = [v for v in inputs.values() if isinstance(v, str)]
    write_netcdf(out, outputs["nc"], step="baseline", inputs=files, time_system="GPS",
                 title=f"baseline {names[1]} - {names[0]} {date}")
    write_netcdf(dd.table, outputs["dd"], step="baseline", inputs=files, time_system="GPS",
                 title=f"double-difference ambiguities {names[1]} - {names[0]} {date}")
    kind = ("DD-fixed baseline solution, leader held at its fixed POD"
            if baseline.mode == "reference_fixed" else "DD-fixed joint baseline solution")
    for role, o, p in zip(("leader", "follower"), outs, pair, strict=True):
        write_sp3(sp3_dataset(o.orbit, p["sp3_id"]), outputs[f"sp3_{role}"], orbit_type="FIT",
                  coordinate_system=data.coordinate_system,   # the pair's GNSS products
                  comments=tuple(textwrap.wrap(
                      f"leopod {kind} of {names[1]} - {names[0]}: {p['sat']} {date}", 77)))
    title = f"{pair[1]['title']} - {pair[0]['title']} {date}"
    plot_fractional_parts(dd.table, outputs["histogram"], title=f"DD {title}")
    _plot_rtn(out.isel(time=in_day), outputs["figure"], title)


def _plot_rtn(ds: xr.Dataset, path, title: str) -> None:
    fig, axes = plt.subplots(3, 1, figsize=(10, 7), sharex=True)
    truth = "error_rtn_m" in ds
    for i, (ax, comp) in enumerate(zip(axes, "RTN")):
        t = ds.time.values
        if truth:
            ax.plot(t, 1e3 * ds.float_error_rtn_m.values[:, i], lw=0.7, label="float - truth")
            ax.plot(t, 1e3 * ds.error_rtn_m.values[:, i], lw=0.7, label="DD-fixed - truth")
        else:
            ax.plot(t, 1e3 * (ds.baseline_rtn_m.values[:, i] - ds.float_baseline_rtn_m.values[:, i]),
                    lw=0.7, label="DD-fixed - float")
        s = 1e3 * ds.sigma_rtn_m.values[:, i]
        ax.fill_between(t, -s, s, color="0.8", label="fixed formal 1σ")
        ax.set_ylabel(f"{comp} [mm]")
        ax.legend(loc="upper right", fontsize=7)
    axes[0].set_title(f"baseline {title}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    p = sm.params
    main(sm.wildcards.date, plain(sm.input), plain(sm.output), pair=list(p.pair),
         **pod_settings(p.signals, p.pod, p.code_bias),
         ambiguity=ArSettings.from_config(p.settings),
         baseline=BaselineSettings.from_config(p.baseline))


if __name__ == "__main__":
    run(snakemake)  # noqa: F821 (injected by Snakemake)
