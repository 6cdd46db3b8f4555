"""Snakemake script of rule float_pod: see leopod.estimation.arc."""

from leopod.estimation.arc import run_arc
from leopod.estimation.write import ArcInputs, log_arc, write_arc
from leopod.workflow.log import configure_logging


def main(inp, out, params, date, log):
    a = ArcInputs(inp)
    arc = run_arc(date, a.obs, a.quality, a.leo, a.orbit, a.clock, a.antex, params.signals,
                  params.pod, params.pco_body_m, code_maps=a.code_maps,
                  code_bias_cfg=params.code_bias, yaw_flips=params.yaw_flips)
    log_arc(arc, f"float POD {date}")
    write_arc(arc, out, step="float_pod", kind="float", title=params.title,
              sp3_id=params.sp3_id, inputs=a.files)


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    sm = snakemake  # noqa: F821
    main(sm.input, sm.output, sm.params, sm.wildcards.date, log)
