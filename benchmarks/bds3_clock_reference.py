"""BDS-3 B1C/B2a POD with BDS clocks referring to B1I/B3I or to B1C/B2a, with and without the
code OSBs (issue 20, done-when).

The simulated arc of tests/estimation/_bds3_arc.py (config/hy2d-sim.yaml, first day,
hours 1-5, no code-bias maps): float POD, single-difference WL/NL fixing with the Bias-SINEX
OSBs (leopod.gnss.signal_bias, mode ``absolute``) and fixed POD, for the two clock references
(simulate.biases.clock_reference, same seed), each with all OSBs and with the phase OSBs
only. Prints the float and fixed 3D RMS against the truth, the product guard's verdict,
fixes and wrong fixes (leopod.simulate.ambiguity_truth.wrong_fixes), and the RMS of the IF
code residuals. About 20 s of one core.

The campaign table of finished HY-2D-like runs: benchmarks/hy2d_table.py.

    .venv/bin/python benchmarks/bds3_clock_reference.py
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(REPO / "tests" / "estimation")]

REFERENCES = {"B1C/B2a clocks": ("C1P", "C5P"), "B1I/B3I clocks": ("C2I", "C6I")}


def arc_case() -> None:
    """The library-level comparison (the inputs of test_bds3_clock_reference.py)."""
    from _bds3_arc import simulate_day, solve  # noqa: PLC0415

    print(f"{'case':38s} {'float 3D':>9s} {'fixed 3D':>9s} {'guard':>9s} {'WL fix':>6s} "
          f"{'NL fix':>6s} {'constr':>6s} {'wrong':>5s} {'IF code':>8s}")
    for label, reference in REFERENCES.items():
        world = simulate_day(Path(tempfile.mkdtemp()), reference)
        for code_osb in (True, False):
            r = solve(world, code_osb=code_osb)
            w = r["wrong"]
            wrong = w["wl_wrong"] + w["nl_wrong"] + w["constrained_wrong"]
            name = f"{label}, {'code+phase OSBs' if code_osb else 'phase OSBs only'}"
            print(f"{name:38s} {r['float_3d_m'] * 1e3:7.1f}mm {r['fixed_3d_m'] * 1e3:7.1f}mm "
                  f"{r['guard']:>9s} {w['wl_fixed']:6d} {w['nl_fixed']:6d} "
                  f"{w['constrained']:6d} {wrong:5d} {r['code_rms_m']:7.2f}m", flush=True)


if __name__ == "__main__":
    arc_case()
