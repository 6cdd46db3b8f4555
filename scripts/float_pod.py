"""Snakemake script of rule float_pod: see leopod.estimation.arc."""

import xarray as xr

from leopod.estimation.arc import merge_days, run_arc
from leopod.estimation.write import log_arc, write_arc
from leopod.io.antex import read_antex
from leopod.io.clock import read_rinex_clock
from leopod.io.sp3 import read_sp3
from leopod.workflow import configure_logging


def main(inp, out, params, date, log):
    obs = [xr.load_dataset(p) for p in inp.obs]
    quality = [xr.load_dataset(p) for p in inp.quality]
    leo = [xr.load_dataset(p) for p in inp.leo]
    orbit = merge_days([read_sp3(p) for p in inp.orbit])
    clock = merge_days([read_rinex_clock(p) for p in inp.clock])
    antex = read_antex(inp.antex) if inp.get("antex") else None
    code_maps = xr.load_dataset(inp.code_bias) if inp.get("code_bias") else None
    arc = run_arc(date, obs, quality, leo, orbit, clock, antex, params.signals, params.pod,
                  params.pco_body_m, code_maps=code_maps, code_bias_cfg=params.code_bias,
                  yaw_flips=params.yaw_flips)
    log_arc(arc, f"float POD {date}")
    write_arc(arc, out, step="float_pod", kind="float", title=params.title,
              sp3_id=params.sp3_id,
              inputs=[*inp.obs, *inp.quality, *inp.leo, *inp.orbit, *inp.clock])


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    sm = snakemake  # noqa: F821
    main(sm.input, sm.output, sm.params, sm.wildcards.date, log)
