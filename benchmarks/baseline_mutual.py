"""Mutual differences of the reduced-dynamic DD-fixed baselines of one formation pair solved
by different campaigns (issue 21; Zhang et al. 2024 compare G, C and G+C): RMS R/T/N/3D of
the differences in the leader's RTN over each day's common epochs.

    .venv/bin/python benchmarks/baseline_mutual.py PAIR LABEL:RUN LABEL:RUN [LABEL:RUN ...]

e.g. the G+C campaign and its G-only and C-only counterparts (``pod: {system: G|C, vce: false}``)
    .venv/bin/python benchmarks/baseline_mutual.py lt1-a-lt1-b G+C:../scratch-lt1 \\
        G:../scratch-lt1-g C:../scratch-lt1-c
"""

from __future__ import annotations

import itertools
import sys
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.validation.formation import rms_rtn


def _day(ds: xr.Dataset) -> xr.Dataset:
    """The day's epochs of a baseline file (all of them in files without ``in_day``)."""
    return ds.isel(time=ds.in_day.values == 1) if "in_day" in ds else ds


def main() -> None:
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    pair = sys.argv[1]
    runs = dict(arg.split(":", 1) for arg in sys.argv[2:])
    days = sorted(set.intersection(*(
        {p.stem for p in (Path(r) / "results" / "baseline" / pair).glob("????-???.nc")}
        for r in runs.values())))
    for (la, ra), (lb, rb) in itertools.combinations(runs.items(), 2):
        out = []
        for day in days:
            a = _day(xr.load_dataset(Path(ra) / "results" / "baseline" / pair / f"{day}.nc"))
            b = _day(xr.load_dataset(Path(rb) / "results" / "baseline" / pair / f"{day}.nc"))
            t, ia, ib = np.intersect1d(a.time.values, b.time.values, return_indices=True)
            # the difference of the RTN components: the leader orbits of two runs differ by mm,
            # their axes by < 1e-9 rad, i.e. < 5 um on a 5-km baseline
            d = a.baseline_rtn_m.values[ia] - b.baseline_rtn_m.values[ib]
            r = rms_rtn(d)
            out.append(f"{day} {1e3 * r['3D']:.2f} (R/T/N {1e3 * r['R']:.2f} / "
                       f"{1e3 * r['T']:.2f} / {1e3 * r['N']:.2f}, {r['n']} epochs)")
        print(f"{la} - {lb} [mm]: " + "; ".join(out))


if __name__ == "__main__":
    main()
