"""Mutation fuzzing of every leopod reader (issue 24): crash / hang / suspect counts.

Builds a small valid seed file per reader from ../shared/data (see ``tests/io/_fuzz.py``),
runs ``--cases`` deterministic mutations of it through the reader (case ``i`` of a reader is
the same on every run and every machine) and prints, per reader, how many were accepted,
refused with a FormatError naming the file, crashed (any other exception, or a FormatError
without the file name), hung (longer than ``--timeout`` s) or were suspect (a returned value
that is not finite, far out of range, a time label outside 1900-2199, or a value of a file
cut short that differs from the seed's). The first examples of each failure are listed.
The address space of the process is limited (``--memory-gb``) so that a reader asking for
hundreds of GiB fails fast (counted as a crash) instead of swapping.

    .venv/bin/python benchmarks/fuzz_readers.py --cases 10000 [--readers sp3 clock]
        [--accepted] [--json out.json]

Exit status 1 if any reader crashed, hung or returned a suspect value.
"""

from __future__ import annotations

import argparse
import json
import resource
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests" / "io"))

import _fuzz  # noqa: E402  (tests/io/_fuzz.py)


def main() -> int:
    """Run the fuzzer and print the table; returns the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=10_000, help="cases per reader")
    parser.add_argument("--first", type=int, default=0, help="index of the first case")
    parser.add_argument("--readers", nargs="*", help="reader names (default: all)")
    parser.add_argument("--timeout", type=float, default=5.0, help="seconds per case")
    parser.add_argument("--memory-gb", type=float, default=6.0, help="address-space limit")
    parser.add_argument("--examples", type=int, default=3, help="failures listed per kind")
    parser.add_argument("--accepted", action="store_true",
                        help="count the accepted cases by mutation kind")
    parser.add_argument("--json", type=Path, help="write every non-accepted-or-refused case")
    parser.add_argument("--shared", type=Path, default=REPO.parent / "shared" / "data")
    args = parser.parse_args()
    if not (args.shared / "MANIFEST.md").exists():
        print(f"no real data at {args.shared}: cannot build the seeds")
        return 2
    limit = int(args.memory_gb * 2**30)
    resource.setrlimit(resource.RLIMIT_AS, (limit, resource.getrlimit(resource.RLIMIT_AS)[1]))
    report: dict = {}
    bad = 0
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        seeds = _fuzz.build_seeds(args.shared, folder, args.readers)
        print(f"{'reader':<17}{'cases':>7}{'accepted':>10}{'refused':>9}{'crash':>7}"
              f"{'hang':>6}{'suspect':>9}{'s':>7}")
        for name, seed in seeds.items():
            t0 = time.perf_counter()
            res = _fuzz.fuzz_reader(seed, range(args.first, args.first + args.cases), folder,
                                    args.timeout)
            dt = time.perf_counter() - t0
            n = {k: len(v) for k, v in res.items()}
            bad += n["crash"] + n["hang"] + n["suspect"]
            print(f"{name:<17}{args.cases:>7}{n['accepted']:>10}{n['refused']:>9}"
                  f"{n['crash']:>7}{n['hang']:>6}{n['suspect']:>9}{dt:>7.0f}", flush=True)
            for kind in ("crash", "hang", "suspect"):
                for i, detail in res[kind][:args.examples]:
                    print(f"    {kind} #{i}: {detail}")
            if args.accepted:
                kinds = Counter(k for _, detail in res["accepted"] for k in detail.split("+"))
                print("    accepted mutations by kind: " + ", ".join(
                    f"{k} {n}" for k, n in kinds.most_common()))
            report[name] = {"counts": n, **{k: res[k] for k in ("crash", "hang", "suspect")}}
    if args.json:
        args.json.write_text(json.dumps(report, indent=1))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
