"""Ambiguity resolution and fixed POD of the simulated default campaign against its truth (issue 7).

Run ``make run`` first (or ``snakemake --cores 2``). For every day this prints the fixing rates
(Jiang et al. 2023: fixed independent / all independent) and the share of fixed pairs, the wrong
fixes counted against the simulated integers, float and fixed RMS errors (R/T/N/3D over the day)
against the truth orbit, and the wall times of the float_pod, ambiguity and fixed_pod jobs from
Snakemake's benchmark files (logs/<campaign>/benchmarks/). With ``--codes`` it re-solves the arc
of one day in-process with P1 (C1W) with and without the code-bias map and with C1 (C1C/C2W)
instead, and prints the same figures for each (issue 6 and 7: the effect of the map on the
fixing rates). With ``--wrong K`` it re-solves the fixed POD of one day with K of its
constraints deliberately wrong by one narrow-lane cycle and reports whether the residual
screening of the fixed POD (:mod:`leopod.ambiguity.screening`) finds the passes involved.

    .venv/bin/python benchmarks/ambiguity.py [--codes [--day 2019-002]]

``--configfile``/``--directory`` evaluate another simulated campaign run in its own working
directory, e.g. the real WHU product set (config/whu-2008.yaml)::

    .venv/bin/snakemake --cores 2 --directory ../whu-run --configfile config/whu-2008.yaml
    .venv/bin/python benchmarks/ambiguity.py --configfile config/whu-2008.yaml \
        --directory ../whu-run
"""

from __future__ import annotations

import argparse
import dataclasses
import logging
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.ambiguity.products import ar_product
from leopod.ambiguity.resolve import ArSettings, resolve_arc
from leopod.codebias.apply import CodeCorrection, correct_codes
from leopod.estimation.arc import ArcData, run_arc
from leopod.estimation.fixed_arc import FloatSolution, run_fixed_arc
from leopod.io.clock import read_rinex_clock
from leopod.io.netcdf import merge_days
from leopod.io.sp3 import read_sp3
from leopod.simulate.ambiguity_truth import true_single_differences, wrong_fixes
from leopod.validation.compare import difference_rtn, rms_rtn
from leopod.workflow.campaign import arc_days, campaign_days
from leopod.workflow.config import load_campaign
from leopod.workflow.layout import Layout
from leopod.workflow.settings import pod_settings

REPO = Path(__file__).resolve().parents[1]
SAT = "hy2b-sim"
#: The default campaign's products and simulated files in the checkout (campaign hy2b-sim).
RESULTS = REPO / "results" / "hy2b-sim"
SIM = REPO / "resources" / "hy2b-sim" / "simulate"


def _day_slice(date: str) -> slice:
    start = np.datetime64(f"{date[:4]}-01-01") + np.timedelta64(int(date[5:]) - 1, "D")
    return slice(start, start + np.timedelta64(86399, "s"))


def _rms_cm(orbit: xr.Dataset, truth: xr.Dataset, date: str) -> str:
    r = rms_rtn(difference_rtn(orbit.sel(time=_day_slice(date)), truth))
    return " ".join(f"{k} {100 * v:.2f}" for k, v in r.items()) + " cm"


def _summary(label, table, residuals, truth_days) -> None:
    wrong = wrong_fixes(table, *true_single_differences(table, residuals, truth_days))
    n = table.sizes["pair"]
    print(f"  {label}: {n} pairs; rates WL {100 * table.attrs['wl_fixing_rate']:.1f} % "
          f"NL {100 * table.attrs['nl_fixing_rate']:.1f} %; fixed pairs WL "
          f"{wrong['wl_fixed']} ({100 * wrong['wl_fixed'] / n:.1f} %) NL {wrong['nl_fixed']} "
          f"({100 * wrong['nl_fixed'] / n:.1f} %); wrong WL {wrong['wl_wrong']} NL "
          f"{wrong['nl_wrong']}; constrained {wrong['constrained']} "
          f"(wrong {wrong['constrained_wrong']})")


def _seconds(benchmarks: Path, step: str, date: str) -> float:
    path = benchmarks / step / SAT / f"{date}.tsv"
    return float(path.read_text().splitlines()[1].split("\t")[0]) if path.exists() else np.nan


def campaign(cfg: dict, workdir: Path) -> None:
    layout = Layout.of(cfg)
    res = workdir / layout.results
    sim = workdir / layout.resources / "simulate"
    truth = xr.load_dataset(sim / SAT / "truth_orbit.nc")
    label = "+".join(cfg["signals"]["G"]["pod_code"]) + (
        " + map on " + "+".join(cfg["code_bias"]["apply"]) if cfg["code_bias"].get("apply")
        else "")
    for date in campaign_days(cfg):
        table = xr.load_dataset(res / "ambiguity" / SAT / f"{date}.nc")
        residuals = xr.load_dataset(res / "float_pod" / SAT / f"{date}_residuals.nc")
        truth_days = [xr.load_dataset(sim / SAT / f"{d}_truth.nc") for d in arc_days(cfg, date)]
        print(f"{date} (AR product: {table.attrs.get('ar_product')}):")
        _summary(label, table, residuals, truth_days)
        for kind in ("float", "fixed"):
            orbit = xr.load_dataset(res / f"{kind}_pod" / SAT / f"{date}_orbit.nc")
            print(f"  {kind} vs truth: {_rms_cm(orbit, truth, date)}")
        times = {step: _seconds(workdir / layout.benchmarks, step, date)
                 for step in ("float_pod", "ambiguity", "fixed_pod")}
        print("  wall time: " + ", ".join(f"{k} {v:.1f} s" for k, v in times.items()))


def _arc_inputs(days: list[str]):
    """Ingest/quality files, GNSS products and the code-bias map of an arc's days."""
    res = RESULTS
    obs = [xr.load_dataset(res / "ingest" / SAT / f"{d}_obs.nc") for d in days]
    quality = [xr.load_dataset(res / "quality" / SAT / f"{d}.nc") for d in days]
    leo = [xr.load_dataset(res / "ingest" / SAT / f"{d}_leo.nc") for d in days]
    orbit = merge_days([read_sp3(SIM / "gnss" / f"{d}.sp3") for d in days])
    clock = merge_days([read_rinex_clock(SIM / "gnss" / f"{d}_int.clk") for d in days])
    maps = xr.load_dataset(res / "code_bias" / SAT / "2019-01.nc")
    return ArcData(obs=obs, quality=quality, leo=leo, orbit=orbit, clock=clock, code_maps=maps)


def code_variants(cfg: dict, date: str) -> None:
    truth = xr.load_dataset(SIM / SAT / "truth_orbit.nc")
    days = arc_days(cfg, date)
    data = _arc_inputs(days)
    truth_days = [xr.load_dataset(SIM / SAT / f"{d}_truth.nc") for d in days]
    pco = cfg["satellites"][SAT]["antenna_pco_body_m"]
    settings = pod_settings(cfg["signals"], cfg["pod"], cfg["code_bias"])
    for label, codes, apply in (("P1 + map", ("C1W", "C2W"), ("C1W",)),
                                ("P1 without map", ("C1W", "C2W"), ()),
                                ("C1 (C1C, C2W)", ("C1C", "C2W"), ())):
        settings["signals"] = dataclasses.replace(settings["signals"], pod_code=codes)
        settings["code_correction"] = CodeCorrection(apply=apply, empty_cells="drop",
                                                     bds2_scb=True)
        arc = run_arc(date, data, **settings, pco_body_m=pco)
        o = [correct_codes(a, q, data.code_maps, apply, empty_cells="drop")[0] if apply else a
             for a, q in zip(data.obs, data.quality, strict=True)]
        epoch = arc.residuals.time.values[arc.residuals.sizes["time"] // 2]
        product = ar_product(epoch, arc.ambiguities.sv.values, ["L1C", "L2W"], codes,
                             wl_bias_path=SIM / "gnss" / f"{date}.wsb")
        r = resolve_arc(arc.ambiguities, arc.residuals, merge_days(o), "G",
                        ["L1C", "L2W"], codes, product.wl_sat_cyc,
                        ArSettings.from_config(cfg["ambiguity"]))
        _summary(label, r.table, arc.residuals, truth_days)
        fixed = run_fixed_arc(date, data, **settings, pco_body_m=pco, table=r.table,
                              float_solution=FloatSolution(arc.parameters, arc.ambiguities,
                                                           arc.residuals, arc.orbit),
                              settings=ArSettings.from_config(cfg["ambiguity"])).arc
        print(f"    float {_rms_cm(arc.orbit, truth, date)}; fixed "
              f"{_rms_cm(fixed.orbit, truth, date)}")


def wrong_fix_screening(cfg: dict, date: str, k: int) -> None:
    days = arc_days(cfg, date)
    res = RESULTS
    data = _arc_inputs(days)
    settings = pod_settings(cfg["signals"], cfg["pod"], cfg["code_bias"])
    base = res / "float_pod" / SAT / date
    float_solution = FloatSolution.read(**{n: f"{base}_{n}.nc" for n in
                                           ("parameters", "ambiguities", "residuals", "orbit")})
    table = xr.load_dataset(res / "ambiguity" / SAT / f"{date}.nc")
    constrained = np.flatnonzero(table.constrained.values == 1)
    rng = np.random.default_rng(7)
    wrong = rng.choice(constrained, k, replace=False)
    value = table.fixed_if_m.values.copy()
    value[wrong] += rng.choice([-1.0, 1.0], k) * float_solution.ambiguities.attrs["nl_wavelength_m"]
    table["fixed_if_m"] = (table.fixed_if_m.dims, value)
    ar = dataclasses.replace(ArSettings.from_config(cfg["ambiguity"]), constraint_sigma_m=1e-3)
    fixed = run_fixed_arc(date, data, **settings,
                          pco_body_m=cfg["satellites"][SAT]["antenna_pco_body_m"], table=table,
                          float_solution=float_solution, settings=ar)
    pairs = {(int(i), int(j)) for i, j in zip(*fixed.constraints[:2], strict=True)}
    kept_wrong = sum((int(table.pass_i.values[w]), int(table.pass_j.values[w])) in pairs
                     for w in wrong)
    print(f"{date}: {constrained.size} constraints, {k} wrong by one NL cycle; after "
          f"{fixed.dropped_rounds} screening rounds {fixed.constraints[0].size} kept, "
          f"{kept_wrong} of them wrong")
    truth = xr.load_dataset(SIM / SAT / "truth_orbit.nc")
    print(f"  fixed orbit vs truth: {_rms_cm(fixed.arc.orbit, truth, date)}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--codes", action="store_true")
    parser.add_argument("--day", default="2019-002")
    parser.add_argument("--wrong", type=int, default=0)
    parser.add_argument("--configfile", type=Path, default=REPO / "config" / "config.yaml")
    parser.add_argument("--directory", type=Path, default=REPO)
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    cfg = load_campaign(args.configfile)
    if args.wrong:
        wrong_fix_screening(cfg, args.day, args.wrong)
    elif args.codes:
        print(f"{args.day}, arc of {' '.join(arc_days(cfg, args.day))}:")
        code_variants(cfg, args.day)
    else:
        campaign(cfg, args.directory)


if __name__ == "__main__":
    main()
