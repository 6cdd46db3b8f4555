"""Benchmark and truth figures of the residual-method PCV (leopod.antenna.pcv; issue 22 item 2a).

Runs the closed loop of tests/antenna/_pcv_loop.py: a simulated day with the real GOCE pattern
(../shared/data/antex/GOCE_MAIN_0001.ATX), float POD without PCV, the stacked residual map, and
the POD again with the estimated ANTEX antenna, ``--iterations`` times. Prints the orbit 3D RMS
against the truth without PCV / with the true PCV / with the estimated map of each iteration,
the map RMS against the truth (the true pattern at the residual directions stacked as the
residuals are, and the pattern at the nodes; the mean over the nodes with ``--min-count`` residuals removed from
both; also with a PCO-Z-like cos z removed), the wall time and the peak memory.

    .venv/bin/python benchmarks/pcv.py [--hours 0 24] [--step 10 10] [--iterations 3]
        [--estimator bilinear|mean]
    .venv/bin/python benchmarks/pcv.py --campaign <directory of a run of
        config/hy2b-sim-pcv.yaml or of its iterations> [--configfile <its campaign files>]

``--campaign`` compares the map that a workflow run wrote
(results/hy2b-sim-pcv/pcv/hy2b-sim/2019-01.atx:
the POD's PCV plus the map) with the GOCE truth stacked at the run's fixed-POD residual
directions, over all nodes and above 10° elevation. For a direct-method run, ``--configfile``
(its campaign files) also splits the error: the map against the map of the same normal
equations with the true PCV as the only misclosure (noise and orbit errors), and that map
against the node fit of the truth (what the grid cannot represent, fitted as the POD weights).

Measured 2026-11-27 (one day 0-24 h, 10° x 10°, 301 nodes with >= 30 residuals, float POD,
another job sharing the 2 cores): orbit 3D RMS against the truth: no PCV 45.30 mm, true PCV
23.42 mm; bilinear estimator, iterations 1-6: 32.14, 27.53, 25.96, 25.43, 25.27, 25.21 mm;
map RMS against the truth 4.74, 4.15, 3.93, 3.88, 3.89, 3.91 mm (the pattern at the nodes:
7.2-7.1 mm; removing a PCO-Z-like cos z changes nothing); 216-274 s for 5-8 PODs, 0.8-1.0 GB.
The cell-mean estimator: orbit 32.13, 27.01, 25.51 mm, map 3.66, 3.55, 3.90 mm (it sharpens
the map's noise from one iteration to the next). With float ambiguities the loop stalls at
~4 mm and ~2 mm above the true-PCV orbit; the fixed-POD residuals of the workflow (rule pcv,
config/hy2b-sim-pcv.yaml, 3 days) give maps 3.4, 2.1, 1.7 mm RMS from the truth and fixed
orbits of 2.78 (no PCV), 0.55, 0.44 cm (maps 1, 2) against 0.36 cm with the true PCV.
"""

from __future__ import annotations

import argparse
import dataclasses
import resource
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests" / "antenna"))

import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from _pcv_fixed import noise_free_normals  # noqa: E402
from _pcv_loop import pcv_loop  # noqa: E402
from _simulated_arc import GOCE  # noqa: E402

from leopod.ambiguity.resolve import ArSettings  # noqa: E402
from leopod.antenna.pcv import PcvSettings, map_rms_m, stack_residuals  # noqa: E402
from leopod.antenna.pcv_direct import solve_normals  # noqa: E402
from leopod.estimation.arc import ArcData  # noqa: E402
from leopod.estimation.fixed_arc import FloatSolution, run_fixed_arc  # noqa: E402
from leopod.gnss.leo_antenna import leo_antenna, receiver_pcv_if  # noqa: E402
from leopod.io.antex import read_antex  # noqa: E402
from leopod.io.antex_write import write_antex  # noqa: E402
from leopod.io.attitude import load_leo_attitude  # noqa: E402
from leopod.workflow.boundary import (  # noqa: E402
    attitude_files,
    leo_antenna_of,
    mock_snakemake,
    plain,
)
from leopod.workflow.config import read_campaign, with_defaults  # noqa: E402
from leopod.workflow.layout import Layout  # noqa: E402
from leopod.workflow.settings import pod_settings  # noqa: E402

SAT, PERIOD, DAYS = "hy2b-sim", "2019-01", ("2019-001", "2019-002", "2019-003")
#: The products folder of config/hy2b-sim-pcv.yaml in its working directory.
RESULTS = Layout.of(read_campaign(REPO / "config" / "hy2b-sim-pcv.yaml")).results
TRUTH_ANTENNA = leo_antenna(None, {"antex": str(GOCE), "type": "GOCE"})
#: Antenna type of the synthetic pattern file (:func:`write_synthetic_antex`).
SYNTHETIC_TYPE = "LEOPOD SYNTHETIC"


def synthetic_pcv_m(zenith_deg, az_deg):
    """A smooth ±1 cm receiver PCV (issue 22: "a synthetic ±1 cm pattern") [m].

    ``7 mm sin²z cos 2(α − 20°) + 5 mm sin 2z sin 3α`` (z zenith angle, α azimuth from the
    ANTEX north = body +X): only azimuthal orders 2 and 3, so that the pattern has no part
    like a constant, a PCO-Z (cos z) or a horizontal offset (orders 0 and 1), which the
    clock, the radial orbit and the along-/cross-track orbit would take; zero at the
    zenith, its bilinear interpolant on a 10° grid within 0.4 mm of it.
    """
    z, a = np.radians(zenith_deg), np.radians(az_deg)
    return 7e-3 * np.sin(z) ** 2 * np.cos(2 * (a - np.radians(20.0))) \
        + 5e-3 * np.sin(2 * z) * np.sin(3 * a)


def write_synthetic_antex(path: Path, pco_z_error_m: float = 0.0) -> Path:
    """The GOCE antenna of ../shared (its PCO, its 1° grid) with :func:`synthetic_pcv_m` as
    the PCV of both frequencies and the phase centres moved up (along the boresight, body
    −Z) by ``pco_z_error_m`` [m]: a truth the POD's GOCE PCO table gets wrong by that much.
    Written as ANTEX 1.4 (type :data:`SYNTHETIC_TYPE`)."""
    goce = read_antex(GOCE).antennas[0]
    zz, aa = np.meshgrid(goce.zenith_deg, np.arange(0.0, 360.0 + goce.dazi_deg / 2,
                                                    goce.dazi_deg))
    pattern = dataclasses.replace(
        goce, antenna_type=SYNTHETIC_TYPE,
        pco={f: v + np.array([0.0, 0.0, pco_z_error_m]) for f, v in goce.pco.items()},
        noazi={f: np.zeros_like(goce.zenith_deg) for f in goce.frequencies},
        grid={f: synthetic_pcv_m(zz, aa) for f in goce.frequencies})
    return write_antex(path, [pattern], comments=[
        "synthetic +-1 cm PCV (benchmarks/pcv.py synthetic_pcv_m)",
        f"GOCE_MAIN_0001 PCO, up by {pco_z_error_m * 1e3:g} mm"], method="SYNTHETIC")


def campaign_map(folder: Path, configfiles=(), days=DAYS,
                 truth_antenna=TRUTH_ANTENNA) -> dict[str, float]:
    """Print the RMS of a workflow run's map against the truth (module docstring; the GOCE
    pattern unless ``truth_antenna``) over the POD ``days`` of its period; return them [m]
    (keys ``all``, ``above_10deg``, and the same with the parts like a constant, a PCO-Z and
    a horizontal offset removed from the difference, ``datum_all``, ``datum_above_10deg``)."""
    pair = ("L1C", "L2W")
    truth_if = receiver_pcv_if(truth_antenna, "G", pair)
    est = xr.load_dataset(folder / RESULTS / f"pcv/{SAT}/{PERIOD}.nc")
    settings = PcvSettings.from_config(with_defaults("pcv", {
        "az_step_deg": float(est.attrs["az_step_deg"]),
        "zenith_step_deg": float(est.attrs["zenith_step_deg"]),
        "min_count": int(est.attrs["min_count"]), "datum": str(est.attrs["datum"]),
        # the truth is stacked as the residual method's estimator does; a direct-method map
        # is compared with the bilinear fit (its nodes are those of the interpolation)
        "estimator": ("bilinear" if est.attrs["estimator"] == "direct"
                      else str(est.attrs["estimator"]))}))
    stacked = []
    for day in days:
        res = xr.load_dataset(folder / RESULTS / f"fixed_pod/{SAT}/{day}_residuals.nc")
        ok = np.isfinite(res.phase_residual_m.values) & (res.phase_rejected.values == 0)
        true = np.full(ok.shape, np.nan)
        true[ok] = truth_if(res.el_deg.values[ok], res.az_deg.values[ok])
        res["phase_residual_m"] = (("time", "sv"), true)
        stacked.append(res)
    truth = stack_residuals(stacked, settings)
    zz, aa = np.meshgrid(est.zenith_deg.values, est.azimuth_deg.values)
    total = receiver_pcv_if(leo_antenna(None, {"antex": str(folder / RESULTS / f"pcv/{SAT}/"
                                                          f"{PERIOD}.atx"),
                                               "type": "LEOPOD PCV"}), "G", pair)
    est["pcv_if_m"] = (est.pcv_if_m.dims, total(90.0 - zz, aa))
    rms = map_rms_m(est, truth.pcv_if_m.values, min_count=settings.min_count)
    full = est.copy()
    est["count"] = est["count"].where(est.zenith_deg < 80.0, 0)
    rms_10 = map_rms_m(est, truth.pcv_if_m.values, min_count=settings.min_count)
    print(f"{folder}: map (POD's PCV + estimate) RMS vs truth {rms * 1e3:.2f} mm, above 10 deg "
          f"elevation {rms_10 * 1e3:.2f} mm; truth RMS {np.nanstd(truth.pcv_if_m) * 1e3:.2f} mm")
    # the parts no map can take from the POD (pcv_direct's datum): constant, cos z, offset
    datum = {f"datum_{k}": map_rms_m(e, truth.pcv_if_m.values, min_count=settings.min_count,
                                     pco_z=True, horizontal=True)
             for k, e in (("all", full), ("above_10deg", est))}
    print(f"  with the parts like a constant, a PCO-Z and a horizontal offset removed: "
          f"{datum['datum_all'] * 1e3:.2f} mm, above 10 deg "
          f"{datum['datum_above_10deg'] * 1e3:.2f} mm")
    if est.attrs["estimator"] == "direct" and configfiles:
        direct_split(folder, configfiles, settings, truth, days, truth_antenna)
    return {"all": rms, "above_10deg": rms_10, **datum}


def direct_split(folder: Path, configfiles, settings: PcvSettings, truth: xr.Dataset,
                 days=DAYS, truth_antenna=TRUTH_ANTENNA) -> None:
    """A direct-method run: its map against the map of the same normal equations with the
    true PCV as the only misclosure (the fixed POD of each day linearised again from the
    run's files, as rule pcv_neq does), and that noise-free map against the node fit."""
    noise_free, normals = [], []
    for day in days:
        job = mock_snakemake("pcv_neq", configfiles=configfiles, root=folder,
                             snakefile=REPO / "Snakefile", sat=SAT, date=day)
        p, files = job.params, plain(job.input)
        pod = pod_settings(p.signals, p.pod, p.code_bias)
        data = ArcData.read(files, signal_bias=getattr(p, "signal_bias", None),
                            sampling_s=pod["arc"].sampling_s)
        start = FloatSolution.read(**{k: files[f"float_{k}"] for k in
                                      ("parameters", "ambiguities", "residuals", "orbit")})
        fixed = run_fixed_arc(day, data, pod["signals"], pod["arc"], pod["pod"], pod["forces"],
                              leo_antenna_of(p.pco_body_m, p.leo_antenna, files),
                              xr.load_dataset(files["table"]), start,
                              ArSettings.from_config(p.settings),
                              code_correction=pod["code_correction"], yaw_flips=p.yaw_flips,
                              attitude=load_leo_attitude(p.attitude, attitude_files(job)))
        neq = xr.load_dataset(folder / RESULTS / f"pcv_neq/{SAT}/{day}.nc")
        normals.append(neq)
        noise_free.append(noise_free_normals(truth_antenna, fixed, neq, settings))
    direct = PcvSettings.from_config({**p.pcv, "min_count": settings.min_count})
    est, ideal = solve_normals(normals, direct), solve_normals(noise_free, direct)
    for name, a, b in (("estimate - noise-free direct map", est, ideal.pcv_if_m.values),
                       ("noise-free direct map - node fit", ideal, truth.pcv_if_m.values)):
        high = a.copy()
        high["count"] = high["count"].where(high.zenith_deg < 80.0, 0)
        print(f"{name}: {1e3 * map_rms_m(a, b, min_count=settings.min_count):.2f} mm, above 10 "
              f"deg {1e3 * map_rms_m(high, b, min_count=settings.min_count):.2f} mm")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hours", type=float, nargs=2, default=(0.0, 24.0))
    parser.add_argument("--step", type=float, nargs=2, default=(10.0, 10.0),
                        help="azimuth and zenith step [deg]")
    parser.add_argument("--iterations", type=int, default=3)
    parser.add_argument("--min-count", type=int, default=30)
    parser.add_argument("--estimator", choices=("mean", "bilinear"), default="bilinear")
    parser.add_argument("--campaign", type=Path, help="compare this workflow run's map only")
    parser.add_argument("--configfile", nargs="*", default=(),
                        help="with --campaign of a direct-method run: its campaign files, to "
                        "split the map's error into noise and node fit")
    args = parser.parse_args()
    if args.campaign is not None:
        campaign_map(args.campaign, [str(Path(c).resolve()) for c in args.configfile])
        return
    with tempfile.TemporaryDirectory() as tmp:
        out = pcv_loop(Path(tmp), hours=tuple(args.hours), steps=tuple(args.step),
                       min_count=args.min_count, iterations=args.iterations,
                       estimator=args.estimator)
    truth = out["truth_map"]
    print(f"{args.estimator} estimator, arc {args.hours[0]:g}-{args.hours[1]:g} h, grid {args.step[0]:g} x "
          f"{args.step[1]:g} deg, {int((truth['count'].values >= args.min_count).sum())} "
          f"nodes with >= {args.min_count} residuals")
    print("orbit 3D RMS vs truth [mm]: " + ", ".join(
        f"{k} {v * 1e3:.2f}" for k, v in out["orbit_3d_m"].items()))
    for k, (a, b, c) in enumerate(zip(out["map_rms_m"], out["map_rms_nodes_m"],
                                      out["map_rms_pco_z_m"]), 1):
        print(f"iteration {k}: map RMS vs truth {a * 1e3:.2f} mm (truth stacked like the "
              f"residuals), {b * 1e3:.2f} mm (pattern at the nodes), {c * 1e3:.2f} mm (stacked, "
              "PCO-Z-like cos z removed too)")
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"wall time {out['seconds']:.1f} s, peak memory {peak_mb:.0f} MB")


if __name__ == "__main__":
    main()
