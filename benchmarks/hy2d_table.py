"""The results table of Jiang et al. (2023) for finished simulated HY-2D-like campaigns (issue 20).

For every POD line of each run (the satellite's solution and its variants,
leopod.workflow.variants) and each solution (float, fixed): RMS of orbit minus the simulated
truth in 3D/R/T/N, the 3D RMS of the 6-h overlaps, the STD of the SLR residuals, the share of
single differences with the WL and the NL fixed (per system for a combined line), the wrong
fixes against the simulator's integers (per system, each with its own phase pair), and the
estimated PCO-Z correction (truth 0: the simulator flies the a-priori offsets of the campaign)
as mean +- STD over the days. Everything but the wrong fixes comes from the campaign summaries
(``results/summary/<line>.csv``, mean and std rows).

    .venv/bin/python benchmarks/hy2d_table.py RUN:CONFIG [RUN:CONFIG ...]

e.g. the GPS period, the BDS-3 period and the combined receiver:

    .venv/bin/python benchmarks/hy2d_table.py ../hy2d-gps:config/hy2d-sim-gps.yaml \\
        ../hy2d-bds:config/hy2d-sim.yaml ../hy2d-gc:config/hy2d-sim-gc.yaml
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.simulate.ambiguity_truth import wrong_fix_counts
from leopod.validation.summary import system_of
from leopod.workflow.config import load_campaign
from leopod.workflow.variants import pod_lines

SOLUTIONS = ("float_pod", "fixed_pod")


def summary_rows(run: Path, line: str) -> dict:
    """``{(date, solution): row}`` of a line's campaign summary CSV (strings)."""
    with open(run / "results" / "summary" / f"{line}.csv") as f:
        return {(r["date"], r["solution"]): r for r in csv.DictReader(f)}


def fixes_per_system(run: Path, line: str, sat: str, signals: dict) -> dict:
    """``{system: {n_sd, wl_fixed, nl_fixed, constrained, wrong}}`` summed over the line's
    ambiguity tables (:func:`leopod.simulate.ambiguity_truth.wrong_fix_counts`: each system
    with its own phase pair)."""
    truths = [xr.load_dataset(p)
              for p in sorted((run / "resources" / "simulate" / sat).glob("*_truth.nc"))]
    phases = {system: block["phase"] for system, block in signals.items()}
    totals: dict = {}
    for path in sorted((run / "results" / "ambiguity" / line).glob("*.nc")):
        table = xr.load_dataset(path)
        residuals = xr.load_dataset(run / "results" / "float_pod" / line
                                    / f"{path.stem}_residuals.nc")
        systems = system_of(table.sv_i.values)
        counts = wrong_fix_counts(table, residuals, truths, phases)
        for system in np.unique(systems):
            w = counts[str(system)]
            t = totals.setdefault(str(system), dict.fromkeys(
                ("n_sd", "wl_fixed", "nl_fixed", "constrained", "wrong"), 0))
            t["n_sd"] += int((systems == system).sum())
            for key in ("wl_fixed", "nl_fixed", "constrained"):
                t[key] += w[key]
            t["wrong"] += w["wl_wrong"] + w["nl_wrong"] + w["constrained_wrong"]
    return totals


def _f(row: dict, key: str) -> float:
    value = row.get(key, "")
    return float(value) if value not in ("", None) else float("nan")


def print_run(run: Path, config: Path) -> None:
    """The table of every POD line of one finished run."""
    cfg = load_campaign(config)
    print(f"\n{run} ({config.name}): {cfg['campaign']} {cfg['start_date']}..{cfg['end_date']}")
    print(f"{'line':14s} {'solution':9s} {'3D':>5s} {'R':>5s} {'T':>5s} {'N':>5s} "
          f"{'ovl3D':>5s} {'SLR':>5s} {'PCO-Z corr.':>14s}  [cm]   "
          f"SDs: WL / NL fixed [%], wrong")
    for line, (sat, _) in pod_lines(cfg).items():
        rows = summary_rows(run, line)
        fixing = fixes_per_system(run, line, sat, cfg["signals"])
        for solution in SOLUTIONS:
            m, s = rows[("mean", solution)], rows.get(("std", solution), {})
            text = (f"{line:14s} {solution[:5]:9s} "
                    + " ".join(f"{_f(m, f'reference_{c}_rms_cm'):5.2f}"
                               for c in ("3d", "r", "t", "n"))
                    + f" {_f(m, 'overlap_3d_rms_cm'):5.2f} {_f(m, 'slr_std_cm'):5.2f} "
                    + f"{_f(m, 'pco_z_cm'):6.3f}+-{_f(s, 'pco_z_cm'):5.3f}")
            if solution == "fixed_pod":
                text += "   " + "; ".join(
                    f"{system} {t['n_sd']}: {100 * t['wl_fixed'] / t['n_sd']:.1f} / "
                    f"{100 * t['nl_fixed'] / t['n_sd']:.1f}, {t['wrong']}"
                    for system, t in fixing.items())
            print(text)


def main(argv: list[str]) -> None:
    if not argv:
        sys.exit(__doc__)
    for arg in argv:
        run, _, config = arg.partition(":")
        print_run(Path(run), Path(config))


if __name__ == "__main__":
    main(sys.argv[1:])
