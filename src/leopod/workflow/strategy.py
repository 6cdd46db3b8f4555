"""Pulse and empirical-acceleration strategy study: a grid of POD settings run as solution
variants of one campaign, tabulated like Table 3 of Xu et al. (2023, paper 001).

Xu et al. (2023, sec. 3.2, Table 3) solve one HY-2A day with pseudo-stochastic pulses every 6,
15, 30 and 60 min and a-priori sigmas from 1e-4 to 1e-9 m/s and compare each orbit with the
CNES science orbit (R/T/N/3D RMS); the best was 15 min and 1e-8. The trade-off is physics: few
or tight pulses cannot follow the unmodelled forces (the orbit stays as far from the truth as
the force model's errors make it; an independent check reported in the project's issue 22
found ~3 mm for 15-min pulses even with perfect data), many or loose ones let the orbit follow
the noise of the data. Here each
cell of the grid is one solution variant (:mod:`leopod.workflow.variants`: its own float and
fixed POD, overlaps, reference and SLR validation and campaign summary), so the study runs as
one Snakemake campaign and every figure of the summary is available per cell; on a simulated
campaign the reference is the truth.

Run (writes ``<directory>/strategy.yaml``, the campaign overlay with the grid as variants,
runs it, and writes ``<directory>/strategy_<sat>.csv`` and ``.png``)::

    .venv/bin/python -m leopod.workflow.strategy config/config.yaml --directory ../study \\
        --intervals 360 900 1800 3600 --sigmas 1e-4 1e-5 1e-6 1e-7 1e-8 1e-9 [--days 1]

``--empirical-sigmas`` adds a grid axis of the empirical accelerations' sigma
(``pod.forces.empirical.sigma`` [m/s²]). The campaign's own solution stays as the reference line.
"""

from __future__ import annotations

import argparse
import copy
import itertools
import subprocess
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pandas as pd
import yaml

__all__ = ["GridCell", "strategy_table", "strategy_variants", "variant_name"]

#: Figures of the campaign summary tabulated per cell (unit in the name).
FIGURES = ("reference_r_rms_cm", "reference_t_rms_cm", "reference_n_rms_cm",
           "reference_3d_rms_cm", "overlap_3d_rms_cm", "phase_rms_mm", "slr_std_cm")


class GridCell(NamedTuple):
    """One cell of the grid: pulse interval [s], pulse sigma (R = T = N) [m/s] and the
    empirical accelerations' sigma [m/s²] (None: the campaign's)."""

    interval_s: float
    sigma_m_s: float
    empirical_sigma_m_s2: float | None


def _code(value: float) -> str:
    """``1e-08`` -> ``1em08`` (variant names are letters and digits)."""
    mantissa, exponent = f"{value:.0e}".split("e")
    return f"{mantissa}e{'m' if exponent.startswith('-') else 'p'}{exponent[1:]}"


def variant_name(cell: GridCell) -> str:
    """Variant name of a cell, e.g. ``i900s1em08`` (900-s pulses of 1e-8 m/s) or
    ``i900s1em08e1em09`` (empirical sigma 1e-9 m/s²)."""
    name = f"i{int(round(cell.interval_s))}s{_code(cell.sigma_m_s)}"
    if cell.empirical_sigma_m_s2 is not None:
        name += f"e{_code(cell.empirical_sigma_m_s2)}"
    return name


def strategy_variants(pod: Mapping, intervals_s: Sequence[float], sigmas_m_s: Sequence[float],
                      empirical_sigmas_m_s2: Sequence[float] | None = None
                      ) -> dict[str, tuple[GridCell, dict]]:
    """The grid as solution variants: ``{name: (cell, {"pod": keys})}``.

    Parameters
    ----------
    pod : mapping
        The campaign's ``pod`` section (the empirical sigma is replaced inside a copy of its
        ``forces``: a variant replaces whole keys).
    intervals_s : sequence of float
        Pulse intervals [s].
    sigmas_m_s : sequence of float
        Pulse sigmas, the same in R, T and N [m/s].
    empirical_sigmas_m_s2 : sequence of float, optional
        Sigmas of the empirical accelerations [m/s²]; None: the campaign's.

    Raises
    ------
    ValueError
        If an empirical sigma is asked for but the campaign estimates no empirical
        accelerations.
    """
    if empirical_sigmas_m_s2 and not (pod.get("forces") or {}).get("empirical"):
        raise ValueError("--empirical-sigmas: the campaign's pod.forces has no 'empirical'")
    out = {}
    for interval, sigma, emp in itertools.product(intervals_s, sigmas_m_s,
                                                  empirical_sigmas_m_s2 or [None]):
        cell = GridCell(float(interval), float(sigma), None if emp is None else float(emp))
        keys = {"pulse_interval_s": cell.interval_s, "pulse_sigma_m_s": [cell.sigma_m_s] * 3}
        if emp is not None:
            forces = copy.deepcopy(dict(pod["forces"]))
            forces["empirical"] = {**forces["empirical"], "sigma": cell.empirical_sigma_m_s2}
            keys["forces"] = forces
        out[variant_name(cell)] = (cell, {"pod": keys})
    return out


def strategy_table(comparison: pd.DataFrame, sat: str, cells: Mapping[str, GridCell],
                   solution: str, figures: Sequence[str] = FIGURES) -> pd.DataFrame:
    """Campaign means of each cell in the layout of Xu et al. (2023, Table 3).

    Parameters
    ----------
    comparison : pandas.DataFrame
        The variant comparison of the satellite (rule variant_comparison, its CSV read with
        ``header=[0, 1, 2], index_col=0``): rows the summary figures, columns ``(line,
        solution, statistic)``.
    sat : str
        The satellite (its lines are ``<sat>_<variant>``).
    cells : mapping
        ``{variant name: GridCell}``.
    solution : str
        ``float_pod`` or ``fixed_pod``.
    figures : sequence of str
        Summary rows to tabulate (those the comparison lacks are left out).

    Returns
    -------
    pandas.DataFrame
        Index ``(sigma_m_s, empirical_sigma_m_s2, figure)``, columns the pulse intervals in
        minutes; NaN where a cell has no value.
    """
    rows = {}
    for name, cell in cells.items():
        key = (f"{sat}_{name}", solution, "mean")
        if key not in comparison.columns:
            continue
        for figure in figures:
            if figure in comparison.index:
                emp = np.nan if cell.empirical_sigma_m_s2 is None else cell.empirical_sigma_m_s2
                rows[(cell.sigma_m_s, emp, figure, cell.interval_s / 60.0)] = float(
                    comparison.loc[figure, key])
    if not rows:
        raise ValueError(f"no line of {sat} with the solution {solution} in the comparison")
    series = pd.Series(rows)
    series.index.names = ["sigma_m_s", "empirical_sigma_m_s2", "figure", "interval_min"]
    table = series.unstack("interval_min")
    order = {f: i for i, f in enumerate(figures)}
    return table.sort_index(level=["sigma_m_s", "empirical_sigma_m_s2", "figure"],
                            key=lambda idx: idx.map(order) if idx.name == "figure" else idx,
                            ascending=[False, False, True])


def main(argv: Sequence[str] | None = None) -> None:
    """Command line of the study (module docstring)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("campaign", type=Path, help="campaign file (YAML)")
    parser.add_argument("--directory", type=Path, required=True,
                        help="Snakemake working directory of the study")
    parser.add_argument("--intervals", type=float, nargs="+", default=[360, 900, 1800, 3600],
                        help="pulse intervals [s]")
    parser.add_argument("--sigmas", type=float, nargs="+",
                        default=[1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9],
                        help="pulse sigmas [m/s] (R = T = N)")
    parser.add_argument("--empirical-sigmas", type=float, nargs="*", default=None,
                        help="sigmas of the empirical accelerations [m/s2]")
    parser.add_argument("--days", type=int, default=None,
                        help="only the first N days of the campaign")
    parser.add_argument("--solution", default=None, choices=["float_pod", "fixed_pod"],
                        help="solution tabulated (default: fixed if the campaign fixes)")
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--dry-run", action="store_true",
                        help="write the overlay and show the jobs (snakemake -n), no table")
    args = parser.parse_args(argv)

    from leopod.plots.validation import plot_strategy
    from leopod.settings import read_yaml
    from leopod.time.calendar import parse_date_id
    from leopod.validation.summary import column_meta
    from leopod.workflow.campaign import campaign_days, satellite_ids
    from leopod.workflow.config import validated

    raw = read_yaml(args.campaign)
    campaign = validated(copy.deepcopy(raw))
    grid = strategy_variants(campaign["pod"], args.intervals, args.sigmas,
                             args.empirical_sigmas)
    overlay = {"variants": {name: keys for name, (_, keys) in grid.items()}}
    if args.days:
        days = campaign_days(campaign)[:args.days]
        overlay["end_date"] = str(parse_date_id(days[-1]))
    args.directory.mkdir(parents=True, exist_ok=True)
    overlay_path = args.directory / "strategy.yaml"
    overlay_path.write_text(yaml.safe_dump(overlay, sort_keys=False))
    repo = Path(__file__).resolve().parents[3]
    cmd = [str(Path(sys.executable).with_name("snakemake")), "--cores", str(args.cores),
           "--snakefile", str(repo / "Snakefile"), "--directory", str(args.directory),
           "--configfile", str(args.campaign.resolve()), str(overlay_path.resolve())]
    if args.dry_run:
        cmd.append("-n")
    print(" ".join(cmd), flush=True)
    subprocess.run(cmd, check=True)
    if args.dry_run:
        return
    solution = args.solution or ("fixed_pod" if campaign["ambiguity"]["enabled"]
                                 else "float_pod")
    cells = {name: cell for name, (cell, _) in grid.items()}
    for sat in satellite_ids(campaign):
        path = args.directory / "results" / "summary" / f"{sat}_variants.csv"
        comparison = pd.read_csv(path, header=[0, 1, 2], index_col=0)
        table = strategy_table(comparison, sat, cells, solution)
        out = args.directory / f"strategy_{sat}.csv"
        table.to_csv(out, float_format="%.6g")
        unit, text = column_meta("reference_3d_rms_cm")
        plot_strategy(table, out.with_suffix(".png"), f"{sat} {solution}: pulse strategy",
                      ylabel=f"{text} [{unit}]")
        with pd.option_context("display.width", 160, "display.max_rows", 500):
            print(f"\n{sat} {solution} (campaign means; columns: pulse interval [min])")
            print(table.to_string(float_format=lambda v: f"{v:.3f}"))
        print(f"written: {out} and {out.with_suffix('.png')}")


if __name__ == "__main__":
    main()
