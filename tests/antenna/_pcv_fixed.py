"""Fixed-POD closed loops of the PCV estimation: the direct and the residual method against
the simulation truth (the analogue of Wang et al. 2024, Table 4).

Observations simulated WITH the real GOCE pattern (../shared/data/antex/GOCE_MAIN_0001.ATX,
Jäggi et al. 2009) on the default HY-2B-like day of tests/estimation/_simulated_arc.py; the
POD (float, single-difference AR with the simulated WL biases, fixed) runs WITHOUT the PCV
(its PCO as a body-frame table, optionally with a PCO-Z error). A solution is the fixed orbit
of a POD with an antenna: none (the table), the truth, the direct-method map of the fixed POD
without PCV (leopod.antenna.pcv_direct: one solve, the problem is linear in the nodes), or
the residual-method map (leopod.antenna.pcv, bilinear estimator) iterated POD <-> map
``iterations`` times (Wang et al. 2024: three). Orbits are compared with the truth in R, T, N;
maps with the true ionosphere-free PCV fitted on the nodes as the map is (the bilinear
least-squares nodes at the directions of the used phase, what a perfect estimate gives), over
the nodes with ``min_count`` phase observations, the mean removed (and with a PCO-Z a cos z
term: the datum).
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import xarray as xr

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "estimation"))

from _simulated_arc import DAY, SAT, T0, goce_world, ingested_arc_data  # noqa: E402

from leopod.ambiguity.products import ar_product  # noqa: E402
from leopod.ambiguity.resolve import ArSettings, resolve_arc  # noqa: E402
from leopod.antenna.pcv import (  # noqa: E402
    PcvSettings,
    estimated_antenna,
    map_rms_m,
    stack_residuals,
)
from leopod.antenna.pcv_direct import (  # noqa: E402
    AntennaColumns,
    day_normals,
    reduce_normals,
    solve_normals,
)
from leopod.estimation.arc import run_arc  # noqa: E402
from leopod.estimation.fixed_arc import FloatSolution, run_fixed_arc  # noqa: E402
from leopod.estimation.normals import accumulate  # noqa: E402
from leopod.gnss.leo_antenna import receiver_pcv_if  # noqa: E402
from leopod.simulate.campaign import simulate_leo_day  # noqa: E402
from leopod.validation.compare import difference_rtn, rms_rtn  # noqa: E402
from leopod.workflow.config import with_defaults  # noqa: E402
from leopod.workflow.settings import pod_settings  # noqa: E402

PAIR = ("L1C", "L2W")


def goce_day(folder: Path) -> SimpleNamespace:
    """The GOCE world of _simulated_arc.goce_world with the day simulated WITH the GOCE
    antenna into ``folder`` (``pcv.rnx``) and its truth orbit (``truth_day``)."""
    world = goce_world(folder)
    simulate_leo_day(DAY, SAT, world.sim, DAY, DAY, world.truth, world.biases, world.antenna,
                     rinex3=folder / "pcv.rnx", truth_sp3=folder / "pcv.sp3",
                     truth_nc=folder / "pcv.nc")
    with xr.open_dataset(folder / "pcv.nc") as f:
        world.truth_day = f.load()
    world.folder = folder
    return world


def fixed_pod_arc(world: SimpleNamespace, antenna, hours: tuple[float, float]
                  ) -> SimpleNamespace:
    """Float POD, SD ambiguity resolution and fixed POD of ``hours`` of the day with the LEO
    ``antenna``, as scripts/float_pod.py, ambiguity.py and fixed_pod.py do: ``float``
    (ArcOutputs), ``fixed`` (FixedArc), ``ar`` (ArSettings)."""
    cfg = world.cfg
    ingested = ingested_arc_data(world.folder, cfg, "pcv.rnx", antenna)
    settings = pod_settings(cfg["signals"], cfg["pod"], cfg["code_bias"])
    settings.pop("code_correction")
    limits = tuple(T0 + np.timedelta64(round(3600 * h), "s") for h in hours)
    args = (DAY, ingested.data, settings["signals"], settings["arc"], settings["pod"],
            settings["forces"], antenna)
    arc = run_arc(*args, limits=limits)
    sig = ingested.signals
    product = ar_product(arc.residuals.time.values[arc.residuals.sizes["time"] // 2],
                         arc.ambiguities.sv.values, sig.phase, sig.pod_code,
                         wl_bias_path=world.folder / "g.wsb")
    ar = ArSettings.from_config(with_defaults("ambiguity", cfg["ambiguity"]))
    table = resolve_arc(arc.ambiguities, arc.residuals, ingested.obs, "G", sig.phase,
                        sig.pod_code, product.wl_sat_cyc, ar).table
    start = FloatSolution(arc.parameters, arc.ambiguities, arc.residuals, arc.orbit)
    fixed = run_fixed_arc(*args[:7], table, start, ar, limits=limits)
    return SimpleNamespace(float=arc, fixed=fixed, ar=ar, args=args, limits=limits,
                           start=start)


def orbit_rms_rtn_m(orbit: xr.Dataset, truth: xr.Dataset) -> dict[str, float]:
    """RMS of R, T, N and 3D [m] of a GCRF orbit against the truth."""
    return rms_rtn(difference_rtn(orbit, truth, pos="pos_gcrf_m", vel="vel_gcrf_m_s"))


def pcv_settings(step_deg: float, min_count: int, **kw) -> PcvSettings:
    """PCV settings of an ``step_deg`` × ``step_deg`` grid (schema defaults otherwise)."""
    return PcvSettings.from_config(with_defaults("pcv", {
        "az_step_deg": step_deg, "zenith_step_deg": step_deg, "min_count": min_count, **kw}))


def true_map(world: SimpleNamespace, residuals: xr.Dataset, settings: PcvSettings
             ) -> xr.Dataset:
    """The true ionosphere-free PCV at the directions of the used phase residuals fitted on
    the nodes (bilinear least squares, the map a perfect estimate gives)."""
    pcv_if = receiver_pcv_if(world.antenna, "G", PAIR)
    res = residuals.copy()
    used = np.isfinite(res.phase_residual_m.values) & (res.phase_rejected.values == 0)
    true = np.full(used.shape, np.nan)
    true[used] = pcv_if(res.el_deg.values[used], res.az_deg.values[used])
    res["phase_residual_m"] = (("time", "sv"), true)
    fit = PcvSettings.from_config(with_defaults("pcv", {
        "az_step_deg": settings.az_step_deg, "zenith_step_deg": settings.zenith_step_deg,
        "min_count": settings.min_count, "estimator": "bilinear"}))
    return stack_residuals([res], fit)


def direct_map(pod: SimpleNamespace, settings: PcvSettings) -> tuple[xr.Dataset, xr.Dataset]:
    """Direct-method map of one fixed POD (``pod`` of :func:`fixed_pod_arc`) and its day
    normal equations."""
    fixed = pod.fixed
    neq = day_normals(fixed.pod, settings.grid, constraints=fixed.constraints,
                      pco_z=settings.estimate_pco_z, sigma0=fixed.arc.result.sigma0,
                      date=DAY, satellite=SAT, solution="fixed_pod")
    return solve_normals([neq], settings, period=DAY, satellite=SAT,
                         solution="fixed_pod"), neq


def noise_free_normals(antenna, fixed, neq: xr.Dataset, settings: PcvSettings) -> xr.Dataset:
    """Day normal equations ``neq`` of the fixed POD ``fixed`` (a FixedArc) with the
    right-hand side of the true ionosphere-free PCV of ``antenna`` at each row as the only
    misclosure (same rows, weights, constraints and reduction): no noise, no orbit error.
    Without PCO-Z only."""
    columns = AntennaColumns(settings.grid, False)
    arc = fixed.pod.normals(fixed.constraints, columns=columns)
    pcv_if = receiver_pcv_if(antenna, "G", PAIR)
    rows = dataclasses.replace(arc.rows, misclosure=pcv_if(columns.el_deg, columns.az_deg))
    rhs = accumulate(rows, settings.grid.design(columns.az_deg, columns.el_deg)).rhs
    _, reduced = reduce_normals(arc.normals.matrix, rhs, settings.grid.n_nodes)
    out = neq.copy()
    out["rhs"] = (neq.rhs.dims, reduced, neq.rhs.attrs)
    return out


def direct_truth(world: SimpleNamespace, pod: SimpleNamespace, settings: PcvSettings
                 ) -> xr.Dataset:
    """The map the direct method gives from :func:`noise_free_normals` of the day. Its
    difference from the estimate is what noise and orbit mismodelling do; its difference from
    :func:`true_map` how the node values fit what the grid cannot represent."""
    _, neq = direct_map(pod, settings)
    return solve_normals([noise_free_normals(world.antenna, pod.fixed, neq, settings)],
                         settings)


def map_truth_rms_m(world, estimate: xr.Dataset, residuals: xr.Dataset,
                    settings: PcvSettings, pco_z: bool = False) -> float:
    """RMS of a map against :func:`true_map` over its well-observed nodes [m]."""
    truth = true_map(world, residuals, settings)
    return map_rms_m(estimate, truth.pcv_if_m.values, min_count=settings.min_count,
                     pco_z=pco_z)


def table4(world: SimpleNamespace, apriori, *, hours=(0.0, 24.0), steps=(10.0, 5.0),
           iterations: int = 3, min_count: int = 30, pco_z: bool = False) -> list[dict]:
    """Rows of the Table-4 analogue (module docstring): ``solution``, ``orbit`` (R, T, N,
    3D RMS [m]); rows of a method also ``map`` (the estimate, the pattern used for the
    residual method), ``truth`` (:func:`true_map` at the directions of the POD without PCV),
    ``map_rms_m`` and ``pco_z_m`` (NaN without); direct rows without PCO-Z also
    ``direct_truth`` (:func:`direct_truth`). The direct method at each step with the datum
    ``no_horizontal_offset`` and at the first step without it."""
    rows = []
    none = fixed_pod_arc(world, apriori, hours)
    true = fixed_pod_arc(world, world.antenna, hours)
    for name, pod in (("no PCV", none), ("true PCV", true)):
        rows.append({"solution": name,
                     "orbit": orbit_rms_rtn_m(pod.fixed.arc.orbit, world.truth_day)})
    residuals = none.fixed.arc.residuals
    cases = [("direct", step, True) for step in steps] + [("direct", steps[0], False)] + [
        ("residual", step, True) for step in steps]
    for method, step, horizontal_datum in cases:
        settings = pcv_settings(step, min_count, method=method,
                                estimate_pco_z=pco_z and method == "direct",
                                no_horizontal_offset=horizontal_datum)
        truth = true_map(world, residuals, settings)
        row = {"truth": truth, "pco_z_m": np.nan}
        if method == "direct":
            est, _ = direct_map(none, settings)
            after = fixed_pod_arc(world, estimated_antenna(apriori, est), hours)
            row.update(solution=f"direct {step:g} deg" + (
                "" if horizontal_datum else " (horiz. offset free)"),
                pco_z_m=est.attrs["pco_z_m"])
            if not pco_z:
                row["direct_truth"] = direct_truth(world, none, settings)
        else:
            antenna, after = apriori, none
            for _ in range(iterations):
                delta = stack_residuals([after.fixed.arc.residuals], settings, period=DAY,
                                        satellite=SAT, solution="fixed_pod")
                antenna = estimated_antenna(antenna, delta)
                after = fixed_pod_arc(world, antenna, hours)
            est = delta.copy()
            zz, aa = np.meshgrid(est.zenith_deg.values, est.azimuth_deg.values)
            est["pcv_if_m"] = (delta.pcv_if_m.dims,
                               receiver_pcv_if(antenna, "G", PAIR)(90.0 - zz, aa))
            est["count"] = truth["count"]
            row["solution"] = f"residual {step:g} deg ({iterations} it.)"
        row.update(map=est, orbit=orbit_rms_rtn_m(after.fixed.arc.orbit, world.truth_day),
                   map_rms_m=map_rms_m(est, truth.pcv_if_m.values, min_count=min_count,
                                       pco_z=pco_z))
        rows.append(row)
    return rows
