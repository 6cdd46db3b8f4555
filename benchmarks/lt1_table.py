"""The results table of Zhang et al. (2024, paper 003) for finished simulated Lutan-1-like
formation campaigns (issue 21).

For each run (a label and the results folder of a campaign,
``<directory>/results/<campaign>``) and pair line (the pair's G+C solution and, with
``variants``, its G and C solutions ``<pair>_G``, ``<pair>_C``), as mean ± STD over the days,
from the campaign outputs: DD WL/NL fixing rates (graph rank; per system) and wrong DD fixes
against the simulator's integers; the fixed-POD phase and code residual RMS per system of each
satellite and the receiver-SD residual RMS per system of the baseline (paper Fig. 3); the
reduced-dynamic baseline float and DD-fixed against the truth (3D and R/T/N); its 6-h overlaps;
the mutual differences of the G, C and G+C baselines (Fig. 5); the kinematic baselines (float,
DD-fixed) against the truth and minus the reduced-dynamic one; the STD of baseline length minus
the inter-satellite range. Everything comes from ``summary/<pair>_formation.csv`` (rule
formation_summary) and ``summary/<sat>.csv`` (campaign_summary) of that folder.

    .venv/bin/python benchmarks/lt1_table.py LABEL:RUN [LABEL:RUN ...]

e.g.  .venv/bin/python benchmarks/lt1_table.py lt1-sim:../scratch-lt1/results/lt1-sim
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import xarray as xr


def _rows(path: Path) -> dict:
    with open(path) as f:
        return {r["date"]: r for r in csv.DictReader(f)}


def _cell(rows: dict, key: str, scale: float = 1.0) -> str:
    m, s = rows["mean"].get(key, ""), rows["std"].get(key, "")
    if m in ("", None):
        return "–"
    text = f"{scale * float(m):.2f}"
    return text + (f" ± {scale * float(s):.2f}" if s not in ("", None) else "")


def print_run(label: str, run: Path) -> None:
    """The table of every formation pair of one finished run."""
    for path in sorted((run / "summary").glob("*_formation.csv")):
        pair = path.name.removesuffix("_formation.csv")
        f = _rows(path)
        cols = list(next(iter(f.values())).keys())
        print(f"\n{label} ({run}) {pair}, mean ± STD over {len(f) - 2} days")
        print("  DD fixing rate WL / NL [%]: " + _cell(f, "dd_wl_rate") + " / "
              + _cell(f, "dd_nl_rate") + "; per system NL: " + ", ".join(
                  f"{c.rsplit('_', 1)[1]} {_cell(f, c)}" for c in cols
                  if c.startswith("dd_nl_rate_")))
        if "dd_nl_wrong" in cols:
            print("  wrong DD fixes WL / NL / constrained (sum): " + " / ".join(
                f"{float(f['mean'][f'dd_{k}_wrong']):.0f}" for k in ("wl", "nl", "constrained")))
        first = sorted((run / "baseline" / pair).glob("*_dd.nc"))
        if first:
            with xr.open_dataset(str(first[0]).replace("_dd.nc", ".nc")) as ds:
                for sat in (ds.attrs["leader"], ds.attrs["follower"]):
                    _residuals(run, sat)
        for c in cols:
            if c.startswith("sd_"):
                unit = "mm" if c.startswith("sd_phase") else "m"
                print(f"  baseline {c:32s} [{unit}]: {_cell(f, c)}")
        for kind in ("float", "fixed"):
            print(f"  reduced-dynamic {kind:5s} vs truth R/T/N/3D [mm]: " + " / ".join(
                _cell(f, f"dynamic_{kind}_vs_truth_{c}") for c in ("r", "t", "n", "3d")))
        for c in cols:
            if c.startswith("overlap_3d_"):
                print(f"  overlap 3D {c[len('overlap_3d_'):]:22s} [mm]: {_cell(f, c)}")
        for c in cols:
            if c.startswith("mutual_") and c.endswith("_3d"):
                print(f"  {c:44s} [mm]: {_cell(f, c)}")
        for c in cols:
            if c.startswith("kinematic_"):
                print(f"  {c:44s} [mm]: {_cell(f, c)}")
        for c in cols:
            if c.startswith("range_std_"):
                print(f"  STD |baseline| - range {c[len('range_std_'):]:22s} [mm]: "
                      f"{_cell(f, c)}")


def _residuals(run: Path, sat: str) -> None:
    """Fixed-POD phase [mm] and code [m] residual RMS per system of one satellite."""
    path = run / "summary" / f"{sat}.csv"
    if not path.exists():
        return
    with open(path) as f:
        rows = {(r["date"], r["solution"]): r for r in csv.DictReader(f)}
    m = rows.get(("mean", "fixed_pod"))
    if m is None:
        return
    parts = [f"{k[len('phase_rms_'):-3] or 'all'} phase {float(v):.2f} mm"
             for k, v in m.items() if k.startswith("phase_rms_") and k.endswith("_mm") and v]
    parts += [f"{k[len('code_rms_'):-2] or 'all'} code {float(v):.3f} m"
              for k, v in m.items() if k.startswith("code_rms_") and k.endswith("_m") and v]
    print(f"  {sat} fixed-POD residual RMS: " + ", ".join(parts))


def main() -> None:
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for arg in sys.argv[1:]:
        label, run = arg.split(":", 1)
        print_run(label, Path(run))


if __name__ == "__main__":
    main()
