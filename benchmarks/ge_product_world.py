"""GPS + Galileo product-world campaign on CODE's real 2023-189 OSBs: fixing per system, wrong
fixes, guard verdicts and orbit errors of a finished run of config/cod-ge-2023.yaml.

The run (about 5 min of 2 cores; the scratch directory a sibling of ../shared)::

    snakemake --cores 2 --snakefile <checkout>/Snakefile --directory /work/scratch-ge \\
        --configfile <checkout>/config/cod-ge-2023.yaml
    .venv/bin/python benchmarks/ge_product_world.py /work/scratch-ge

Prints per day and system: single differences, the share with the WL and with the NL fixed,
wrong WL/NL/constrained fixes against the simulator's true integers (each system with its own
phase pair, :func:`leopod.simulate.ambiguity_truth.true_single_differences`), the RMS and the
largest magnitude of the fractional parts of the float WL and NL (what the rounding decision
sees), the product guard's verdict; then the float and fixed orbit RMS against the simulated
truth (3D, R, T, N; results/<campaign>/summary/<sat>.csv).
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.workflow.config import read_campaign
from leopod.workflow.layout import Layout

REPO = Path(__file__).resolve().parents[1]
CONFIG = REPO / "config" / "cod-ge-2023.yaml"
#: The campaign's folders in a working directory (results/<campaign>/...).
LAYOUT = Layout.of(read_campaign(CONFIG))


def _fraction_stats(values: np.ndarray) -> tuple[float, float]:
    """RMS and largest magnitude of the distance to the nearest integer [cycles]."""
    frac = values[np.isfinite(values)] - np.round(values[np.isfinite(values)])
    if not frac.size:
        return np.nan, np.nan
    return float(np.sqrt(np.mean(frac**2))), float(np.max(np.abs(frac)))


def fixing(run: Path, sat: str, pairs: dict) -> list[dict]:
    """Per day and system: counts, shares, wrong fixes, fractional parts and guard verdict."""
    from leopod.simulate.ambiguity_truth import wrong_fix_counts  # noqa: PLC0415

    rows = []
    for path in sorted((run / LAYOUT.results / "ambiguity" / sat).glob("*.nc")):
        if path.stem.count("-") != 1:
            continue
        day = path.stem
        table = xr.load_dataset(path)
        residuals = xr.load_dataset(run / LAYOUT.results / "float_pod" / sat
                                    / f"{day}_residuals.nc")
        truth = xr.load_dataset(run / LAYOUT.resources / "simulate" / sat / f"{day}_truth.nc")
        counts = wrong_fix_counts(table, residuals, [truth], pairs)
        systems = table.system.values.astype(str)
        for x in sorted(set(systems)):
            sub = table.isel(pair=np.flatnonzero(systems == x))
            rows.append({
                "day": day, "system": x, "n_sd": sub.sizes["pair"], **counts[x],
                "wl_frac": _fraction_stats(sub.wl_float_cyc.values),
                "nl_frac": _fraction_stats(sub.nl_float_cyc.values[sub.wl_fixed.values == 1]),
                "guard": table.attrs.get(f"{x}_product_guard", "-")})
    return rows


def orbits(run: Path, sat: str) -> list[dict]:
    """The daily float and fixed rows of the campaign summary."""
    with open(run / LAYOUT.results / "summary" / f"{sat}.csv") as f:
        return [r for r in csv.DictReader(f) if r["date"] not in ("mean", "std")]


def main(run: Path) -> None:
    from leopod.workflow.config import load_campaign  # noqa: PLC0415

    cfg = load_campaign(CONFIG)
    sat = next(iter(cfg["satellites"]))
    pairs = {x: tuple(s["phase"]) for x, s in cfg["signals"].items()}
    print(f"{run}: {cfg['campaign']} {cfg['start_date']}, {sat}, pairs {pairs}")
    print(f"{'day':9s} {'sys':3s} {'SDs':>5s} {'WL fix':>7s} {'NL fix':>7s} {'wrong':>9s} "
          f"{'WL frac rms/max':>16s} {'NL frac rms/max':>16s} {'guard':>9s}")
    for r in fixing(run, sat, pairs):
        n = r["n_sd"]
        wrong = f"{r['wl_wrong']}/{r['nl_wrong']}/{r['constrained_wrong']}"
        print(f"{r['day']:9s} {r['system']:3s} {n:5d} {r['wl_fixed'] / n:7.1%} "
              f"{r['nl_fixed'] / n:7.1%} {wrong:>9s} "
              f"{r['wl_frac'][0]:7.3f}/{r['wl_frac'][1]:7.3f}  "
              f"{r['nl_frac'][0]:7.3f}/{r['nl_frac'][1]:7.3f} {r['guard']:>9s}")
    print("(wrong: WL / NL / constrained fixes differing from the simulator's integers)")
    print(f"{'day':9s} {'solution':10s} {'3D':>6s} {'R':>6s} {'T':>6s} {'N':>6s}  [cm vs truth]")
    for r in orbits(run, sat):
        print(f"{r['date']:9s} {r['solution']:10s} "
              + " ".join(f"{float(r[f'reference_{c}_rms_cm']):6.2f}"
                         for c in ("3d", "r", "t", "n")))


if __name__ == "__main__":
    main(Path(sys.argv[1]))
