"""The baseline stage of a simulated formation campaign against its truth (issue 21).

For every formation pair and day of a run directory (``results/baseline/<pair>/<date>.nc``):
DD WL/NL fixing rates in both definitions (graph rank of the fixed DDs over that of all DDs,
Jiang et al. 2023; share of the DD candidates), wrong fixes against the simulator's integers
(:mod:`leopod.simulate.dd_truth`), float and DD-fixed baseline RMS (R/T/N/3D, leader RTN) vs
the truth baseline, the same within ±30 min of the follower's burns (its manoeuvre file) and
elsewhere, the DD-fixed minus float baseline, the residuals of the DD constraints after the
joint solve, and wall time and peak memory of the baseline job (Snakemake benchmark).

    .venv/bin/python benchmarks/baseline.py /work/scratch-base [--configfile config/lt1-sim.yaml]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import xarray as xr
from _jobs import benchmark_folder, job_figures

from leopod.io.manoeuvre import read_manoeuvres
from leopod.simulate.dd_truth import true_double_differences, wrong_dd_fixes
from leopod.validation.formation import burn_windows
from leopod.workflow.campaign import arc_days
from leopod.workflow.config import load_campaign
from leopod.workflow.layout import Layout
from leopod.workflow.variants import SEPARATOR

REPO = Path(__file__).resolve().parents[1]


def day_report(run: Path, config: dict, pair: str, date: str) -> str:
    """One line of figures of a pair-day."""
    layout = Layout.of(config)
    results, resources = run / layout.results, run / layout.resources
    base = xr.load_dataset(results / "baseline" / pair / f"{date}.nc")
    table = xr.load_dataset(results / "baseline" / pair / f"{date}_dd.nc")
    # POD lines (<sat> or <sat>_<variant>) and their satellites
    a, b = base.attrs["leader"], base.attrs["follower"]
    sats = [line.split(SEPARATOR)[0] for line in (a, b)]
    days = arc_days(config, date)
    truth = [[xr.load_dataset(resources / "simulate" / s / f"{d}_truth.nc")
              for d in days] for s in sats]
    res = [xr.load_dataset(results / "float_pod" / s / f"{date}_residuals.nc")
           for s in (a, b)]
    phases = {x: config["signals"][x]["phase"] for x in base.attrs["systems"].split()}
    wl, nl = true_double_differences(table, res[0], res[1], truth[0], truth[1], phases)
    wrong = wrong_dd_fixes(table, wl, nl)
    wall, peak = job_figures(run, benchmark_folder(run, layout.campaign) / "baseline" / pair
                             / f"{date}.tsv")
    t = base.attrs
    parts = [f"{pair} {date}: DD WL {100 * t['wl_fixing_rate']:.1f} % / "
             f"NL {100 * t['nl_fixing_rate']:.1f} % (graph rank), share "
             f"{100 * t['wl_dd_fixed_share']:.1f} / {100 * t['nl_dd_fixed_share']:.1f} %"]
    for x in ["all", *[s for s in wrong if s != "all"]]:
        w = wrong[x]
        parts.append(f"  {x}: WL fixed {w['wl_fixed']} wrong {w['wl_wrong']}; NL fixed "
                     f"{w['nl_fixed']} wrong {w['nl_wrong']}; constrained {w['constrained']} "
                     f"wrong {w['constrained_wrong']}")
        if x != "all":
            parts[-1] += (f"; rates WL {100 * t[f'{x}_wl_fixing_rate']:.1f} % NL "
                          f"{100 * t[f'{x}_nl_fixing_rate']:.1f} %")
    for label in ("float", "fixed"):
        parts.append(f"  {label} baseline vs truth RMS R/T/N/3D: " + " / ".join(
            f"{1e3 * t[f'{label}_rms_{c}_m']:.2f}" for c in ("r", "t", "n", "3d")) + " mm")
    parts.append(_burn_windows(resources, sats[1], base))
    if "fixed_minus_float_rms_3d_m" in t:
        parts.append(f"  DD-fixed minus float baseline 3D RMS "
                     f"{1e3 * t['fixed_minus_float_rms_3d_m']:.2f} mm; DD constraint residuals "
                     f"RMS {1e3 * t['dd_constraint_residual_rms_m']:.4f} mm, max "
                     f"{1e3 * t['dd_constraint_residual_max_m']:.4f} mm; mode "
                     f"{t.get('baseline_mode', 'joint')}, dynamics "
                     f"{t.get('baseline_dynamics', 'independent')}")
    parts.append(f"  DD constraints used {t['n_dd_constraints_used']} of "
                 f"{t['n_dd_candidates']} candidates; job {wall:.0f} s, peak RSS {peak:.0f} MB")
    return "\n".join(parts)


def _burn_windows(resources: Path, follower: str, base: xr.Dataset,
                  half_s: float = 1800.0) -> str:
    """DD-fixed baseline vs truth RMS R/T/N/3D within ±``half_s`` of any burn of the
    follower and elsewhere (``resources``: the campaign's resources folder)."""
    path = resources / "simulate" / follower / "manoeuvres.txt"
    t = base.time.values
    near = burn_windows(t, read_manoeuvres(path)[0] if path.exists() else (), half_s)
    err = 1e3 * base["error_rtn_m"].values
    day = base["in_day"].values == 1 if "in_day" in base else np.ones(t.size, bool)
    out = []
    for label, sel in (("within 30 min of a burn", near & day), ("elsewhere", ~near & day)):
        if not sel.any():
            out.append(f"{label}: no epochs")
            continue
        rms = np.sqrt(np.mean(err[sel] ** 2, axis=0))
        out.append(f"{label} " + " / ".join(f"{v:.2f}" for v in rms)
                   + f" / {np.sqrt(np.sum(rms**2)):.2f} mm ({int(sel.sum())} epochs)")
    return "  fixed baseline vs truth RMS R/T/N/3D " + "; ".join(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="Snakemake working directory of the campaign")
    parser.add_argument("--configfile", default=str(REPO / "config" / "lt1-sim.yaml"))
    args = parser.parse_args()
    config = load_campaign(args.configfile)
    for path in sorted((args.run / Layout.of(config).results / "baseline").glob("*/*_dd.nc")):
        print(day_report(args.run, config, path.parent.name, path.name.removesuffix("_dd.nc")))


if __name__ == "__main__":
    main()
