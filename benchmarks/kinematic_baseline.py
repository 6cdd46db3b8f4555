"""Kinematic baselines of a formation campaign (issue 21): per pair, day and GNSS solution,
kinematic minus truth and minus the reduced-dynamic baseline (R/T/N/3D RMS, leader RTN), float
and DD-fixed, epochs solved, differential ISB, and wall time and peak memory of the job
(Snakemake benchmark file).

    .venv/bin/python benchmarks/kinematic_baseline.py /work/scratch-kb
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pandas as pd
import xarray as xr


def day_report(nc: Path, bench: Path) -> str:
    """Lines of one pair-day."""
    ds = xr.load_dataset(nc)
    lines = [f"{nc.parent.name} {nc.stem}"]
    for system in ds.system.values:
        for kind in ds.ambiguities.values:
            d = ds.sel(system=system, ambiguities=kind)
            parts = [f"  {system:>2} {kind:5}: solved {int(d.epochs_solved)}/{int(d.epochs)}"]
            for ref in ("truth", "dynamic"):
                name = f"rms_minus_{ref}_m"
                if name in d:
                    parts.append(f"- {ref} " + "/".join(
                        f"{1e3 * float(d[name].sel(component=c)):.1f}"
                        for c in ("R", "T", "N", "3D")) + " mm")
            if np.isfinite(float(d.isb_m)):
                parts.append(f"ISB {float(d.isb_m):+.4f} m")
            parts.append(f"sigma0 {float(d.sigma0):.3f}, {int(d.dd_constraints)} DD constraints")
            lines.append(", ".join(parts))
    if bench.exists():
        b = pd.read_csv(bench, sep="\t")
        lines.append(f"  job {b.s.iloc[0]:.1f} s, peak RSS {b.max_rss.iloc[0]:.0f} MB")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="Snakemake working directory of the campaign")
    args = parser.parse_args()
    for nc in sorted((args.run / "results" / "kinematic_baseline").glob("*/*.nc")):
        bench = (args.run / "logs" / "benchmarks" / "kinematic_baseline" / nc.parent.name
                 / f"{nc.stem}.tsv")
        print(day_report(nc, bench))


if __name__ == "__main__":
    main()
