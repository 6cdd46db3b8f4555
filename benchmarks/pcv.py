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
"""

from __future__ import annotations

import argparse
import resource
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests" / "antenna"))

from _pcv_loop import pcv_loop  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hours", type=float, nargs=2, default=(0.0, 24.0))
    parser.add_argument("--step", type=float, nargs=2, default=(10.0, 10.0),
                        help="azimuth and zenith step [deg]")
    parser.add_argument("--iterations", type=int, default=3)
    parser.add_argument("--min-count", type=int, default=30)
    parser.add_argument("--estimator", choices=("mean", "bilinear"), default="bilinear")
    args = parser.parse_args()
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
