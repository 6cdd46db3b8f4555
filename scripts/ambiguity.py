"""Rule ambiguity: single-difference WL/NL fixing of one float arc (leopod.ambiguity.resolve)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging
from collections.abc import Mapping

import xarray as xr

from leopod.ambiguity.products import ar_product
from leopod.ambiguity.resolve import ArSettings, resolve_arc, resolve_systems
from leopod.codebias.apply import CodeCorrection, correct_codes
from leopod.codebias.scb import NADIR_VARIABLE, correct_bds2_scb
from leopod.gnss.signal_bias import SignalBiases, correct_signal_biases, read_signal_biases
from leopod.io.netcdf import load_netcdf, merge_days, write_netcdf
from leopod.plots.ambiguity import plot_fractional_parts
from leopod.signals import SystemSignals, signal_settings
from leopod.workflow.boundary import plain
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


def _directions(path):
    """Antenna-frame angles, the nadir angle at the GNSS satellites and the antenna range
    terms per band of a quality output (all that the code corrections and the HMW need;
    older outputs have no nadir angle and no antenna terms)."""
    with xr.open_dataset(path) as ds:
        names = [v for v in ds.data_vars
                 if v in ("el_deg", "az_deg", NADIR_VARIABLE) or v.startswith("antenna_range_")]
        return ds[names].load()


def main(inputs: Mapping, table_path, histogram_path, *, system: str | list[str],
         signals: SystemSignals | Mapping[str, SystemSignals],
         settings: ArSettings, code_correction: CodeCorrection, yaw_flips, title: str,
         signal_biases: SignalBiases | None = None) -> None:
    """Fix the ambiguities of a float arc. ``inputs``: ``ambiguities``, ``residuals`` (float
    POD), lists ``obs`` and ``quality`` (its days), optional ``code_bias`` (maps), ``wl_bias``
    or ``osb`` (AR product); writes the table (netCDF) and the histogram (PNG). The satellite
    signal biases (``signal_biases``, as in the POD) are removed from the observations; when
    they include the OSBs of the AR product (``absolute`` mode) the product is not applied a
    second time. ``system`` is a letter with ``signals`` its SystemSignals, or a list of
    letters of a combined POD with ``signals`` a dict of them: each system is then resolved
    with its own signals and product (leopod.ambiguity.resolve.resolve_systems)."""
    combined = not isinstance(system, str)
    observed = ([o for x in system for o in signals[x].observations] if combined
                else signals.observations)
    amb = load_netcdf(inputs["ambiguities"], "float POD ambiguities")
    residuals = load_netcdf(inputs["residuals"], "float POD residuals")
    obs = [correct_signal_biases(load_netcdf(p, "ingest observation"), signal_biases, observed)[0]
           for p in inputs["obs"]]
    directions = [_directions(q) for q in inputs["quality"]]
    if code_correction.bds2_scb:
        obs = [correct_bds2_scb(o, d)[0] for o, d in zip(obs, directions, strict=True)]
    if inputs.get("code_bias") and code_correction.apply:
        maps = load_netcdf(inputs["code_bias"], "code-bias map")
        obs = [correct_codes(o, d, maps, code_correction.apply,
                             empty_cells=code_correction.empty_cells, yaw_flips=yaw_flips)[0]
               for o, d in zip(obs, directions, strict=True)]
    epoch = residuals.time.values[residuals.sizes["time"] // 2]  # biases at the arc centre
    antenna = _antenna(directions)
    if combined:
        res = _resolve_combined(amb, residuals, merge_days(obs), system, signals, settings,
                                epoch, inputs, signal_biases, antenna)
        _write(res, inputs, table_path, histogram_path, title)
        return
    product = ar_product(epoch, amb.sv.values, signals.phase, signals.pod_code,
                         wl_bias_path=inputs.get("wl_bias"), osb_path=inputs.get("osb"),
                         osb_applied=signal_biases is not None and signal_biases.osb_applied)
    log.info("AR product: %s", product.label)
    res = resolve_arc(amb, residuals, merge_days(obs), system, signals.phase, signals.pod_code,
                      product.wl_sat_cyc, settings,
                      sat_if_bias_m=product.per_ambiguity(amb.sv.values), antenna=antenna)
    res.table.attrs["ar_product"] = product.label
    res.table.attrs["convention_integers_refer_to"] = product.label
    _write(res, inputs, table_path, histogram_path, title)


def _antenna(directions):
    """Antenna range terms of the days (None, with a warning, if a quality output lacks them)."""
    if all(any(v.startswith("antenna_range_") for v in d.data_vars) for d in directions):
        antenna = merge_days([d[[v for v in d.data_vars if v.startswith("antenna_range_")]]
                              for d in directions])
        antenna.attrs = {k: v for k, v in directions[0].attrs.items()
                         if k.startswith("antenna_")}
        return antenna
    log.warning("quality outputs without antenna range terms: HMW of raw observations")
    return None


def _resolve_combined(amb, residuals, obs, systems, signals, settings, epoch, inputs,
                      signal_biases, antenna):
    """Each system of a combined arc with its own signals and AR product."""
    sv = amb.sv.values.astype(str)
    wl, ifb = {}, {}
    for x in systems:
        mine = sv[[s.startswith(x) for s in sv]]
        product = ar_product(epoch, mine, signals[x].phase, signals[x].pod_code,
                             wl_bias_path=inputs.get("wl_bias"), osb_path=inputs.get("osb"),
                             osb_applied=signal_biases is not None and signal_biases.osb_applied)
        log.info("AR product %s: %s", x, product.label)
        wl[x], ifb[x] = product.wl_sat_cyc, product.per_ambiguity(mine)
    return resolve_systems(amb, residuals, obs, {x: signals[x] for x in systems}, wl,
                           settings, sat_if_bias_m=ifb, antenna=antenna)


def _write(res, inputs, table_path, histogram_path, title) -> None:
    write_netcdf(res.table, table_path, step="ambiguity",
                 inputs=[inputs["ambiguities"], inputs["residuals"]], time_system="GPS",
                 title=f"single-difference ambiguities {title}")
    plot_fractional_parts(res.table, histogram_path, title=title)


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    p = sm.params
    system = p.pod["system"]
    by_system = signal_settings(p.signals)
    main(plain(sm.input), sm.output.table, sm.output.histogram, system=system,
         signals=by_system[system] if isinstance(system, str) else by_system,
         settings=ArSettings.from_config(p.settings),
         code_correction=CodeCorrection.from_config(p.code_bias), yaw_flips=p.yaw_flips,
         title=p.title,
         signal_biases=read_signal_biases(plain(sm.input), getattr(p, "signal_bias", None)))


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("ambiguity", sat="hy2b-sim", date="2019-002")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
