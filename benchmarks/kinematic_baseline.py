"""Kinematic baselines of a formation campaign (issue 21): per pair, day and GNSS solution,
kinematic minus truth and minus the reduced-dynamic baseline (R/T/N/3D RMS, leader RTN), float
and DD-fixed, epochs solved, differential ISB, the DD-fixed minus truth 3D RMS within 30 min of
the follower's burns and elsewhere, and wall time and peak memory of the job (Snakemake
benchmark file).

    .venv/bin/python benchmarks/kinematic_baseline.py /work/scratch-kb
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import xarray as xr
from _jobs import benchmark_folder, job_figures

from leopod.io.manoeuvre import read_manoeuvres
from leopod.validation.formation import burn_windows, rms_rtn
from leopod.workflow.layout import Layout


def day_report(nc: Path, run: Path, bench: Path, burns: np.ndarray | None = None) -> str:
    """Lines of one pair-day; ``burns``: epochs near a burn (:func:`burn_windows`)."""
    ds = xr.load_dataset(nc)
    lines = [f"{nc.parent.name} {nc.stem}"]
    day = ds.in_day.values == 1 if "in_day" in ds else np.ones(ds.sizes["time"], bool)
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
            if burns is not None and kind == "fixed" and "minus_truth_rtn_m" in d:
                err = d.minus_truth_rtn_m.values
                parts.append("3D near burns / elsewhere " + " / ".join(
                    f"{1e3 * rms_rtn(err[sel & day])['3D']:.1f}" for sel in (burns, ~burns))
                    + " mm")
            lines.append(", ".join(parts))
    if bench.exists():
        wall, peak = job_figures(run, bench)
        lines.append(f"  job {wall:.1f} s, peak RSS {peak:.0f} MB")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="Snakemake working directory of the campaign")
    parser.add_argument("--campaign", default="lt1-sim", help="the campaign's name (config key)")
    args = parser.parse_args()
    layout = Layout(args.campaign)
    for nc in sorted((args.run / layout.results / "kinematic_baseline").glob("*/*.nc")):
        bench = (benchmark_folder(args.run, args.campaign) / "kinematic_baseline"
                 / nc.parent.name / f"{nc.stem}.tsv")
        with xr.open_dataset(nc) as ds:
            follower, times = ds.attrs["follower"], ds.time.values
        path = args.run / layout.resources / "simulate" / follower / "manoeuvres.txt"
        burns = burn_windows(times, read_manoeuvres(path)[0]) if path.exists() else None
        print(day_report(nc, args.run, bench, burns))


if __name__ == "__main__":
    main()
