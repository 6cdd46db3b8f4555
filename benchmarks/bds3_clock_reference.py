"""BDS-3 B1C/B2a POD with BDS clocks referring to B1I/B3I or to B1C/B2a, with and without the
code OSBs (issue 20, done-when), and the table of an HY-2D-like campaign run.

``arc``: the simulated arc of tests/estimation/_bds3_arc.py (config/hy2d-sim.yaml, first day,
hours 1-5, no code-bias maps): float POD, single-difference WL/NL fixing with the Bias-SINEX
OSBs (leopod.gnss.signal_bias, mode ``absolute``) and fixed POD, for the two clock references
(simulate.biases.clock_reference, same seed), each with all OSBs and with the phase OSBs
only. Prints the float and fixed 3D RMS against the truth, the product guard's verdict,
fixes and wrong fixes (leopod.simulate.ambiguity_truth.wrong_fixes), and the RMS of the IF
code residuals. About 20 s of one core.

``campaign <directory> ...``: a table like Jiang et al. (2023)'s results for finished runs of
config/hy2d-sim.yaml (``snakemake --directory <directory> --configfile
config/hy2d-sim.yaml``): float and fixed 3D/R/T/N RMS against the simulated truth, 6-h
overlaps (3D RMS), SLR residual STD, the share of single differences fixed (WL, NL), wrong
fixes against the simulator's integers, and the estimated PCO-Z correction (truth: 0, the
simulator flies the a-priori offsets of the campaign).

    .venv/bin/python benchmarks/bds3_clock_reference.py arc
    .venv/bin/python benchmarks/bds3_clock_reference.py campaign /work/hy2d_run
"""

from __future__ import annotations

import csv
import sys
import tempfile
from pathlib import Path

import numpy as np
import xarray as xr

REPO = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(REPO / "tests" / "estimation")]

REFERENCES = {"B1C/B2a clocks": ("C1P", "C5P"), "B1I/B3I clocks": ("C2I", "C6I")}


def arc_case() -> None:
    """The library-level comparison (the inputs of test_bds3_clock_reference.py)."""
    from _bds3_arc import simulate_day, solve  # noqa: PLC0415

    print(f"{'case':38s} {'float 3D':>9s} {'fixed 3D':>9s} {'guard':>9s} {'WL fix':>6s} "
          f"{'NL fix':>6s} {'constr':>6s} {'wrong':>5s} {'IF code':>8s}")
    for label, reference in REFERENCES.items():
        world = simulate_day(Path(tempfile.mkdtemp()), reference)
        for code_osb in (True, False):
            r = solve(world, code_osb=code_osb)
            w = r["wrong"]
            wrong = w["wl_wrong"] + w["nl_wrong"] + w["constrained_wrong"]
            name = f"{label}, {'code+phase OSBs' if code_osb else 'phase OSBs only'}"
            print(f"{name:38s} {r['float_3d_m'] * 1e3:7.1f}mm {r['fixed_3d_m'] * 1e3:7.1f}mm "
                  f"{r['guard']:>9s} {w['wl_fixed']:6d} {w['nl_fixed']:6d} "
                  f"{w['constrained']:6d} {wrong:5d} {r['code_rms_m']:7.2f}m", flush=True)


def _summary_means(run: Path, campaign: str) -> dict:
    with open(run / "results" / "summary" / f"{campaign}.csv") as f:
        return {row["solution"]: row for row in csv.DictReader(f) if row["date"] == "mean"}


def _fixing(run: Path, sat: str) -> dict:
    """Shares of SDs fixed and wrong fixes over the campaign's ambiguity tables."""
    from leopod.simulate.ambiguity_truth import true_single_differences, wrong_fixes

    truth_files = sorted((run / "resources" / "simulate" / sat).glob("*_truth.nc"))
    truths = [xr.load_dataset(p) for p in truth_files]
    phases = [v[4:-4] for v in truths[0].data_vars if v.startswith("amb_")]
    totals = {"n_sd": 0, "wl_fixed": 0, "nl_fixed": 0, "constrained": 0, "wrong": 0}
    for path in sorted((run / "results" / "ambiguity" / sat).glob("*.nc")):
        table = xr.load_dataset(path)
        residuals = xr.load_dataset(run / "results" / "float_pod" / sat
                                    / f"{path.stem}_residuals.nc")
        w = wrong_fixes(table, *true_single_differences(table, residuals, truths, phases))
        totals["n_sd"] += table.sizes[table.wl_fixed.dims[0]]
        totals["wl_fixed"] += w["wl_fixed"]
        totals["nl_fixed"] += w["nl_fixed"]
        totals["constrained"] += w["constrained"]
        totals["wrong"] += w["wl_wrong"] + w["nl_wrong"] + w["constrained_wrong"]
    return totals


def _pco_z(run: Path, sat: str, step: str) -> tuple[float, float]:
    """Mean and STD over the days of the estimated PCO-Z correction [m], NaN if none."""
    values = []
    for path in sorted((run / "results" / step / sat).glob("*_parameters.nc")):
        p = xr.load_dataset(path)
        if "pco_z_m" in p.parameter.values:
            values.append(float(p.estimate.sel(parameter="pco_z_m")))
    return (float(np.mean(values)), float(np.std(values))) if values else (np.nan, np.nan)


def campaign_case(runs: list[Path]) -> None:
    """The campaign table of each finished run."""
    from leopod.workflow.config import load_campaign  # noqa: PLC0415

    for run in runs:
        cfg = load_campaign(REPO / "config" / "hy2d-sim.yaml")
        campaign, sat = cfg["campaign"], next(iter(cfg["satellites"]))
        means = _summary_means(run, campaign)
        fix = _fixing(run, sat)
        print(f"\n{run}: {campaign} {cfg['start_date']}..{cfg['end_date']}")
        print(f"{'solution':10s} {'3D':>6s} {'R':>6s} {'T':>6s} {'N':>6s} {'overlap':>8s} "
              f"{'SLR STD':>8s} {'PCO-Z':>14s}   [cm]")
        for solution in ("float_pod", "fixed_pod"):
            m = means[solution]
            mean, std = _pco_z(run, sat, solution)
            print(f"{solution:10s} {float(m['reference_3d_rms_cm']):6.2f} "
                  f"{float(m['reference_r_rms_cm']):6.2f} {float(m['reference_t_rms_cm']):6.2f} "
                  f"{float(m['reference_n_rms_cm']):6.2f} {float(m['overlap_3d_rms_cm']):8.2f} "
                  f"{float(m['slr_std_cm']):8.2f} {mean * 100:6.3f}+-{std * 100:5.3f}")
        n = fix["n_sd"]
        print(f"single differences {n}: WL fixed {fix['wl_fixed'] / n:.1%}, NL fixed "
              f"{fix['nl_fixed'] / n:.1%}, constraints {fix['constrained']}, wrong fixes "
              f"{fix['wrong']}")


if __name__ == "__main__":
    if sys.argv[1:2] == ["campaign"]:
        campaign_case([Path(p) for p in sys.argv[2:]])
    else:
        arc_case()
