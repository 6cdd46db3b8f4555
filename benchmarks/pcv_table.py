"""Table 4 of Wang et al. (2024) on simulated data: fixed orbits and PCV maps of the direct and
the residual method against the truth (leopod.antenna.pcv_direct, leopod.antenna.pcv).

A simulated day with the real GOCE pattern (../shared/data/antex/GOCE_MAIN_0001.ATX), POD
without it (tests/antenna/_pcv_fixed.py): fixed-orbit R/T/N/3D RMS against the truth for no
PCV, the true PCV, the direct method at each ``--step`` (one solve) and the residual method at
each step (``--iterations`` POD <-> map rounds, Wang et al. 2024: three), and the map RMS
against the true PCV fitted on the nodes (bilinear least squares at the used phase directions)
over the nodes with ``--min-count`` phase observations and over those above 10° elevation,
the mean removed (with ``--pco-z`` a cos z term too). For the direct method also the map that
the same normal equations give from the true PCV alone (no noise, no orbit error): the
estimate minus it is what noise and orbit mismodelling do, it minus the node fit the weighting.
``--pco-z-error-mm`` shifts the POD's phase centres along body +Z (a PCO-Z error to recover).

    .venv/bin/python benchmarks/pcv_table.py [--hours 0 24] [--step 10 5] [--iterations 3]
        [--min-count 30] [--pco-z] [--pco-z-error-mm 0]
"""

from __future__ import annotations

import argparse
import resource
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests" / "antenna"))

import numpy as np  # noqa: E402
from _pcv_fixed import goce_day, table4  # noqa: E402

from leopod.antenna.pcv import map_rms_m  # noqa: E402


def _above_10deg(ds):
    """The map with the counts of its lowest ring (elevation < 10°) set to 0."""
    out = ds.copy()
    out["count"] = out["count"].where(out.zenith_deg < 80.0, 0)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hours", type=float, nargs=2, default=(0.0, 24.0))
    parser.add_argument("--step", type=float, nargs="+", default=(10.0, 5.0),
                        help="grid steps [deg] (azimuth = zenith)")
    parser.add_argument("--iterations", type=int, default=3)
    parser.add_argument("--min-count", type=int, default=30)
    parser.add_argument("--pco-z", action="store_true", help="direct method with PCO-Z")
    parser.add_argument("--pco-z-error-mm", type=float, default=0.0)
    args = parser.parse_args()
    clock = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        world = goce_day(Path(tmp))
        apriori = {band: [x, y, z + 1e-3 * args.pco_z_error_mm]
                   for band, (x, y, z) in world.pco_only.items()}
        rows = table4(world, apriori, hours=tuple(args.hours), steps=tuple(args.step),
                      iterations=args.iterations, min_count=args.min_count, pco_z=args.pco_z)
    print(f"GOCE pattern simulated, arc {args.hours[0]:g}-{args.hours[1]:g} h, fixed POD, "
          f"PCO-Z error {args.pco_z_error_mm:g} mm, min_count {args.min_count}"
          + (", direct with PCO-Z" if args.pco_z else ""))
    print(f"{'solution':36s} {'R':>6s} {'T':>6s} {'N':>6s} {'3D':>6s} [cm]  map RMS [mm]: "
          "all, >10 deg, >10 deg without horizontal-offset terms   PCO-Z [mm]")
    for row in rows:
        o = row["orbit"]
        line = (f"{row['solution']:36s} {100 * o['R']:6.2f} {100 * o['T']:6.2f} "
                f"{100 * o['N']:6.2f} {100 * o['3D']:6.2f}")
        if "map" in row:
            truth = row["truth"].pcv_if_m.values
            high = map_rms_m(_above_10deg(row["map"]), truth, min_count=args.min_count,
                             pco_z=args.pco_z)
            flat = map_rms_m(_above_10deg(row["map"]), truth, min_count=args.min_count,
                             pco_z=args.pco_z, horizontal=True)
            line += f"       {1e3 * row['map_rms_m']:6.2f} {1e3 * high:6.2f} {1e3 * flat:6.2f}"
            if np.isfinite(row["pco_z_m"]):
                line += f"   {1e3 * row['pco_z_m']:7.2f}"
        print(line)
        if "direct_truth" in row:
            ideal = row["direct_truth"]
            noise = map_rms_m(row["map"], ideal.pcv_if_m.values, min_count=args.min_count)
            noise_high = map_rms_m(_above_10deg(row["map"]), ideal.pcv_if_m.values,
                                   min_count=args.min_count)
            fit = map_rms_m(ideal, row["truth"].pcv_if_m.values, min_count=args.min_count)
            fit_high = map_rms_m(_above_10deg(ideal), row["truth"].pcv_if_m.values,
                                 min_count=args.min_count)
            print(f"{'':36s}   estimate - noise-free direct map {1e3 * noise:.2f} "
                  f"({1e3 * noise_high:.2f} > 10 deg) mm; noise-free direct map - node fit "
                  f"{1e3 * fit:.2f} ({1e3 * fit_high:.2f}) mm")
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"wall time {time.perf_counter() - clock:.0f} s, peak memory {peak_mb:.0f} MB")


if __name__ == "__main__":
    main()
