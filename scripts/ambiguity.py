"""Snakemake script of rule ambiguity: see leopod.ambiguity.resolve."""

import xarray as xr

from leopod.ambiguity.products import ar_product
from leopod.ambiguity.resolve import ArSettings, resolve_arc
from leopod.codebias.apply import correct_codes
from leopod.io.netcdf import merge_days, write_netcdf
from leopod.plots.ambiguity import plot_fractional_parts
from leopod.workflow.log import configure_logging


def _directions(path):
    """Antenna-frame angles of a quality output (all that the code correction needs)."""
    with xr.open_dataset(path) as ds:
        return ds[["el_deg", "az_deg"]].load()


def main(inp, out, params, date, log):
    amb = xr.load_dataset(inp.ambiguities)
    residuals = xr.load_dataset(inp.residuals)
    obs = [xr.load_dataset(p) for p in inp.obs]
    cb = params.code_bias
    if inp.get("code_bias") and cb.get("apply"):
        maps = xr.load_dataset(inp.code_bias)
        obs = [correct_codes(o, _directions(q), maps, cb["apply"],
                             empty_cells=cb["empty_cells"], yaw_flips=params.yaw_flips)[0]
               for o, q in zip(obs, inp.quality, strict=True)]
    system = params.pod["system"]
    sig = params.signals[system]
    epoch = residuals.time.values[residuals.sizes["time"] // 2]  # biases at the arc centre
    product = ar_product(epoch, amb.sv.values, sig["phase"], sig["pod_code"],
                         wl_bias_path=inp.get("wl_bias"), osb_path=inp.get("osb"))
    log.info("AR product: %s", product.label)
    res = resolve_arc(amb, residuals, merge_days(obs), system, sig["phase"],
                      sig["pod_code"], product.wl_sat_cyc, ArSettings.from_config(params.settings),
                      sat_if_bias_m=product.per_ambiguity(amb.sv.values))
    res.table.attrs["ar_product"] = product.label
    write_netcdf(res.table, out.table, step="ambiguity", inputs=[inp.ambiguities, inp.residuals],
                 time_system="GPS", title=f"single-difference ambiguities {params.title}")
    plot_fractional_parts(res.table, out.histogram, title=params.title)


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    sm = snakemake  # noqa: F821
    main(sm.input, sm.output, sm.params, sm.wildcards.date, log)
