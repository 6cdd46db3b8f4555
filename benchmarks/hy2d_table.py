"""The results table of Jiang et al. (2023) for finished simulated HY-2D-like campaigns (issue 20).

For every POD line of each run (the satellite's solution and its variants,
leopod.workflow.variants) and each solution (float, fixed): RMS of orbit minus the simulated
truth in 3D/R/T/N, the 3D RMS of the 6-h overlaps, the STD of the SLR residuals, the share of
single differences with the WL and the NL fixed (per system for a combined line), the wrong
fixes against the simulator's integers (per system, each with its own phase pair), and the
estimated PCO-Z correction (truth 0: the simulator flies the a-priori offsets of the campaign)
as mean +- STD over the days. Everything comes from the campaign summaries
(``results/<campaign>/summary/<line>.csv``: mean and std rows; counts summed over the days;
wrong fixes counted by the summary against the simulator's integers, each system with its own phase
pair).

    .venv/bin/python benchmarks/hy2d_table.py RUN:CONFIG [RUN:CONFIG ...]

e.g. the GPS period, the BDS-3 period and the combined receiver:

    .venv/bin/python benchmarks/hy2d_table.py ../hy2d-gps:config/hy2d-sim-gps.yaml \\
        ../hy2d-bds:config/hy2d-sim.yaml ../hy2d-gc:config/hy2d-sim-gc.yaml
"""

from __future__ import annotations

import csv
import re
import sys
from pathlib import Path

from leopod.workflow.config import load_campaign
from leopod.workflow.layout import Layout
from leopod.workflow.variants import pod_lines

SOLUTIONS = ("float_pod", "fixed_pod")


def summary_rows(results: Path, line: str) -> dict:
    """``{(date, solution): row}`` of a line's campaign summary CSV (strings) in the campaign's
    results folder."""
    with open(results / "summary" / f"{line}.csv") as f:
        return {(r["date"], r["solution"]): r for r in csv.DictReader(f)}


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
    for line in pod_lines(cfg):
        rows = summary_rows(run / Layout.of(cfg).results, line)
        for solution in SOLUTIONS:
            m, s = rows[("mean", solution)], rows.get(("std", solution), {})
            text = (f"{line:14s} {solution[:5]:9s} "
                    + " ".join(f"{_f(m, f'reference_{c}_rms_cm'):5.2f}"
                               for c in ("3d", "r", "t", "n"))
                    + f" {_f(m, 'overlap_3d_rms_cm'):5.2f} {_f(m, 'slr_std_cm'):5.2f} "
                    + f"{_f(m, 'pco_z_cm'):6.3f}+-{_f(s, 'pco_z_cm'):5.3f}")
            if solution == "fixed_pod":
                systems = [x["s"] for name in m if (x := re.fullmatch(r"n_sd_(?P<s>[A-Z])", name))]
                text += "   " + "; ".join(
                    f"{x} {_f(m, f'n_sd_{x}'):.0f}: {_f(m, f'wl_sd_fixed_{x}_pct'):.1f} / "
                    f"{_f(m, f'nl_sd_fixed_{x}_pct'):.1f}, "
                    f"{sum(_f(m, f'{k}_wrong_{x}') for k in ('wl', 'nl', 'constrained')):.0f}"
                    for x in systems)
            print(text)


def main(argv: list[str]) -> None:
    if not argv:
        sys.exit(__doc__)
    for arg in argv:
        run, _, config = arg.partition(":")
        print_run(Path(run), Path(config))


if __name__ == "__main__":
    main(sys.argv[1:])
