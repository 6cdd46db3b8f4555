"""Wrong fixes with a faulty AR product, without and with the product guard (issue 19).

Two simulated cases, each with the consistent product and the simulator's faults
(:mod:`leopod.simulate.product_faults`):

* ``scenario``: the synthetic SD scenario of tests/ambiguity (10 h, 10 GPS satellites) with
  its CNES/CLS WL records + integer clocks and its Bias-SINEX OSBs + ordinary clocks; wrong
  constraints are those off the true float SD by more than 1 mm;
* ``arc``: the simulated HY-2B float POD arc of tests/estimation (4 h, CNES/CLS path, codes
  without the P1 map); wrong fixes counted against the simulator's integers
  (:func:`leopod.simulate.ambiguity_truth.wrong_fixes`).

"Without the guard" is ``ambiguity.product_guard: false`` with no NL float screen, i.e. the
fixing of leopod before issue 19.

    .venv/bin/python benchmarks/product_guard.py [scenario] [arc]
"""

from __future__ import annotations

import dataclasses
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(REPO / "tests" / "ambiguity"), str(REPO / "tests" / "estimation")]

FAULTS = ("none", "flipped_sign", "other_centre")


def _settings(ar, guard: bool):
    return dataclasses.replace(ar, product_guard=guard,
                               nl_max_shift_sigma=ar.nl_max_shift_sigma if guard else 1e9)


def scenario_case() -> None:
    """The synthetic scenario, both product kinds (test_ambiguity_guard.py's inputs)."""
    from test_ambiguity_guard import KINDS, _run, _wrong  # noqa: PLC0415

    for fault in FAULTS:
        for kind in KINDS:
            for guard in (False, True):
                extra = {} if guard else {"nl_max_shift_sigma": 1e9}
                s, res = _run(Path(tempfile.mkdtemp()), fault, kind, guard, **extra)
                print(f"scenario {fault:13s} {kind:3s} {'guard' if guard else 'no guard':8s}",
                      _wrong(s, res), res.table.attrs["product_guard"],
                      res.table.attrs["product_guard_reason"])


def arc_case() -> None:
    """The simulated float POD arc (about 40 s per fault)."""
    from _simulated_arc import simulated_arc  # noqa: PLC0415

    from leopod.ambiguity.resolve import resolve_arc
    from leopod.simulate.ambiguity_truth import true_single_differences, wrong_fixes

    for fault in FAULTS:
        arc = simulated_arc(Path(tempfile.mkdtemp()), ar_fault=fault)
        res = arc.float.residuals
        wl_t, nl_t = true_single_differences(arc.table, res, [arc.truth])
        for guard in (False, True):
            t = resolve_arc(arc.float.ambiguities, res, arc.obs, "G", arc.signals.phase,
                            arc.signals.pod_code, arc.product.wl_sat_cyc,
                            _settings(arc.ar, guard)).table
            print(f"arc {fault:13s} {'guard' if guard else 'no guard':8s}",
                  wrong_fixes(t, wl_t, nl_t), t.attrs["product_guard"],
                  t.attrs["product_guard_reason"])


if __name__ == "__main__":
    cases = sys.argv[1:] or ["scenario", "arc"]
    for case in cases:
        {"scenario": scenario_case, "arc": arc_case}[case]()
