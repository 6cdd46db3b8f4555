"""Snakemake script of rule fixed_pod: the float POD re-solved with the fixed ambiguities."""

import numpy as np
import xarray as xr

from leopod.ambiguity.screening import degraded_passes, drop_constraints
from leopod.estimation.arc import run_arc
from leopod.estimation.write import ArcInputs, log_arc, write_arc
from leopod.workflow.log import configure_logging


def constraints_of(table: xr.Dataset, sigma_m: float):
    """``(pass_i, pass_j, value_m, sigma_m)`` of the constrained single differences."""
    sel = table.constrained.values == 1
    value = table.fixed_if_m.values[sel]
    return (table.pass_i.values[sel].astype(int), table.pass_j.values[sel].astype(int), value,
            np.full(value.shape, sigma_m))


def main(inp, out, params, date, log):
    table = xr.load_dataset(inp.table)
    constraints = constraints_of(table, params.settings["constraint_sigma_m"])
    log.info("%d fixed single differences constrain the solution (AR product: %s)",
             constraints[0].size, table.attrs.get("ar_product"))
    if constraints[0].size == 0:
        log.warning("no fixed ambiguity: the fixed solution equals the float one")
    a = ArcInputs(inp)
    # continue from the float solution; its orbit is the reference of the RTN figure
    float_solution = tuple(xr.load_dataset(p) for p in (inp.float_parameters,
                                                         inp.float_ambiguities,
                                                         inp.float_residuals))
    float_orbit = xr.load_dataset(inp.float_orbit).pos_itrf_m

    def solve(fixes):
        return run_arc(date, a.obs, a.quality, a.leo, a.orbit, a.clock, a.antex,
                       params.signals, params.pod, params.pco_body_m, code_maps=a.code_maps,
                       code_bias_cfg=params.code_bias, yaw_flips=params.yaw_flips,
                       ambiguity_constraints=fixes if fixes[0].size else None,
                       apriori_orbit=float_orbit,
                       continue_from=float_solution)

    arc = solve(constraints)
    # fixes that raise the phase residuals of their passes are dropped and the arc re-solved
    for _ in range(params.settings["max_rejection_rounds"]):
        bad = degraded_passes(float_solution[2], arc.residuals,
                              ratio=params.settings["max_residual_ratio"])
        if bad.size == 0:
            break
        before = constraints[0].size
        constraints = drop_constraints(constraints, bad)
        log.warning("phase residuals of %d passes grew by more than x%.1f with the fixes: "
                    "%d of %d constraints dropped, solving again", bad.size,
                    params.settings["max_residual_ratio"], before - constraints[0].size, before)
        arc = solve(constraints)
    log.info("%d constraints in the fixed solution", constraints[0].size)
    log_arc(arc, f"fixed POD {date}")
    write_arc(arc, out, step="fixed_pod", kind="ambiguity-fixed", title=params.title,
              sp3_id=params.sp3_id,
              inputs=[inp.table, inp.float_orbit, inp.float_parameters, *a.files])


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    sm = snakemake  # noqa: F821
    main(sm.input, sm.output, sm.params, sm.wildcards.date, log)
