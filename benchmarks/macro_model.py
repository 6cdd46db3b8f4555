"""Cannonball against the GRACE macro model (+ Earth radiation) on the real GRACE-A day.

Runs the float POD step's library call (:func:`leopod.estimation.arc.run_arc`) of
config/grace-a-2007.yaml on 2007-03-21 twice: as configured (cannonball drag and SRP, no
Earth radiation) and with ``satellites.grace-a.macro_model: {builtin: grace}`` and
``plates: true`` for drag, SRP and Earth radiation (Knocke et al. 1988; not estimated).
For each it prints the post-fit phase residual RMS, the drag / SRP / empirical estimates with
their formal sigmas, the sub-arc overlap (00-14 h against 10-24 h, RTN RMS over 10-14 h and
its central 11-13 h) and, between the two, the RTN difference (RMS and mean) of the 24-h
orbits (``--split``: also the plates without Earth radiation and Earth radiation on the
cannonball, each against the cannonball; ``--fixed-srp``: both with the SRP scale fixed at 1,
against their estimated-scale orbits). The ingest and quality outputs come from a workflow run of the campaign in
``--results`` (made there if missing):

    snakemake results/quality/grace-a/2007-080.nc --cores 1 --snakefile <repo>/Snakefile \\
        --directory <scratch> --configfile <repo>/config/grace-a-2007.yaml
    .venv/bin/python benchmarks/macro_model.py --results <scratch>/results [--no-overlap] \\
        [--split] [--fixed-srp]
"""

from __future__ import annotations

import argparse
import copy
import logging
import sys
from pathlib import Path

import numpy as np
import yaml
from float_pod import CONFIG, DATA, DATE, _inputs

from leopod.estimation.arc import ArcData, run_arc
from leopod.frames.leo_attitude import LeoAttitude
from leopod.validation.compare import difference_rtn, rms_rtn
from leopod.workflow.config import validated
from leopod.workflow.settings import pod_settings

MASS_KG = 480.0            # the campaign's cannonball mass


def _macro(cfg: dict, plates: bool = True, erp: bool = True) -> dict:
    """The campaign with the GRACE plates for drag and SRP (``plates``) and Earth radiation
    (``erp``: on the plates, or on the campaign's SRP cannonball without them)."""
    cfg = copy.deepcopy(cfg)
    forces = cfg["pod"]["forces"]
    if plates:
        cfg["satellites"]["grace-a"]["macro_model"] = {"builtin": "grace", "mass_kg": MASS_KG}
        forces["drag"]["plates"] = True
        forces["srp"]["plates"] = True
    if erp:
        srp = forces["srp"]
        forces["earth_radiation"] = ({"plates": True} if plates else
                                     {k: srp[k] for k in ("area_m2", "mass_kg",
                                                          "reflectivity_coefficient")})
    return cfg


def _report(label: str, arc) -> None:
    r = arc.result
    rms = 1e3 * np.sqrt(np.nanmean(r.phase_residual_m**2))
    print(f"{label}: phase RMS {rms:.2f} mm ({int(r.phase_used.sum())} obs), sigma0 "
          f"{r.sigma0:.3f}, iterations {r.iterations}")
    par = arc.parameters
    for name in par.parameter.values:
        if name.startswith(("drag_scale", "srp_scale", "erp_scale", "emp_")):
            est, sig = float(par.estimate.sel(parameter=name)), float(par.sigma.sel(
                parameter=name))
            scale = 1e9 if name.startswith("emp_") else 1.0
            unit = " nm/s2" if name.startswith("emp_") else ""
            print(f"    {name:14s} {scale * est:+9.3f} +- {scale * sig:7.3f}{unit}")


def _rtn(label: str, a, b, start=None, end=None) -> None:
    d = difference_rtn(a, b, start=start, end=end)
    rms = rms_rtn(d)
    rows = d.diff_rtn_m.values
    mean = 100 * np.nanmean(rows[np.isfinite(rows).all(axis=1)], axis=0)
    print(f"{label} [cm]: RMS R {100 * rms['R']:.2f} T {100 * rms['T']:.2f} "
          f"N {100 * rms['N']:.2f} 3D {100 * rms['3D']:.2f}; mean R {mean[0]:+.2f} "
          f"T {mean[1]:+.2f} N {mean[2]:+.2f}")


def _solve(label: str, cfg: dict, data: ArcData, overlap: bool):
    cfg = validated(cfg)
    sat = cfg["satellites"]["grace-a"]
    settings = pod_settings(cfg["signals"], cfg["pod"], cfg["code_bias"], sat["macro_model"])
    del settings["code_correction"]
    common = (data, *settings.values(), sat["antenna_pco_body_m"])
    attitude = LeoAttitude.of(sat)
    arc = run_arc(DATE, *common, attitude=attitude)
    _report(f"{label}, 00-24 h", arc)
    if overlap:
        day = np.datetime64("2007-03-21T00:00", "ns")
        hour = np.timedelta64(3600, "s")
        a = run_arc(DATE, *common, limits=(day, day + 14 * hour), attitude=attitude)
        b = run_arc(DATE, *common, limits=(day + 10 * hour, day + 24 * hour),
                    attitude=attitude)
        for lo, hi in ((10, 14), (11, 13)):
            _rtn(f"{label} overlap {lo:02d}-{hi:02d} h", a.orbit, b.orbit,
                 start=day + lo * hour, end=day + hi * hour)
    sys.stdout.flush()
    return arc


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--results", type=Path, required=True,
                        help="results/ of a workflow run of the campaign (ingest, quality)")
    parser.add_argument("--no-overlap", action="store_true", help="skip the sub-arcs")
    parser.add_argument("--save", type=Path, help="write both orbits here (netCDF prefix)")
    parser.add_argument("--split", action="store_true",
                        help="also the macro model without ERP and the cannonball with ERP")
    parser.add_argument("--fixed-srp", action="store_true",
                        help="also both models with the SRP scale fixed at 1 (not estimated)")
    args = parser.parse_args()
    if not DATA.exists():
        sys.exit(f"{DATA} is absent: this benchmark needs the real GRACE-A day")
    logging.basicConfig(level=logging.WARNING, format="%(asctime)s %(name)s %(message)s")
    cfg = yaml.safe_load(CONFIG.read_text())
    data = _inputs(args.results)
    ball = _solve("cannonball", cfg, data, not args.no_overlap)
    plates = _solve("GRACE macro model + ERP", _macro(cfg), data, not args.no_overlap)
    _rtn("macro model - cannonball, 00-24 h", plates.orbit, ball.orbit)
    if args.fixed_srp:
        for label, variant, estimated in (("cannonball", cfg, ball),
                                          ("GRACE macro model + ERP", _macro(cfg), plates)):
            variant = copy.deepcopy(variant)
            variant["pod"]["forces"]["srp"]["estimate"] = False
            arc = _solve(f"{label}, SRP scale fixed at 1", variant, data, False)
            _rtn(f"{label}: SRP fixed - SRP estimated, 00-24 h", arc.orbit, estimated.orbit)
    if args.split:
        for label, variant in (("macro model without ERP", _macro(cfg, erp=False)),
                               ("cannonball + ERP", _macro(cfg, plates=False))):
            arc = _solve(label, variant, data, False)
            _rtn(f"{label} - cannonball, 00-24 h", arc.orbit, ball.orbit)
    if args.save:
        ball.orbit.to_netcdf(f"{args.save}_cannonball.nc")
        plates.orbit.to_netcdf(f"{args.save}_macro.nc")


if __name__ == "__main__":
    main()
