"""C1-based ambiguity resolution on the default campaign, without and with the P1−C1 DCB
(issue 19, part 3, done-when).

The default campaign (config/config.yaml) reduced to its first day (2019-001, as the
end-to-end test of tests/workflow/test_snakemake.py) with the POD and HMW codes C1C/C2W
instead of C1W/C2W: the simulated receiver's C1C differs from C1W by the simulated satellite
P1−C1 DCB (1 ns spread, simulate.biases.dcb_other_sigma_ns), while the clocks and the
CNES/CLS WL product refer to C1W/C2W. Cases:

* ``nodcb``: ``products.dcb_p1c1: null`` (leopod before issue 19, part 3);
* ``dcb``: ``products.dcb_p1c1`` = the simulator's P1−C1 file (C1C + DCB in every step);

each with the product guard (default) and without it (``ambiguity.product_guard: false`` and
no NL float screen, the fixing before issue 19). The simulation of the first case is copied
to the others. Wrong fixes are counted against the simulator's integers
(:func:`leopod.simulate.ambiguity_truth.wrong_fixes`). About 5 min of one core per case
(simulation 2 min once).

    .venv/bin/python benchmarks/c1c_dcb.py <scratch directory> [case ...]
"""

from __future__ import annotations

import copy
import shutil
import subprocess
import sys
from pathlib import Path

import xarray as xr
import yaml

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
DAY = "2019-001"
CASES = {"nodcb_guard": (False, True), "dcb_guard": (True, True),
         "nodcb_noguard": (False, False), "dcb_noguard": (True, False)}


def campaign(dcb: bool, guard: bool) -> dict:
    """The default campaign on its first day with C1C-based POD and AR."""
    config = yaml.safe_load((REPO / "config/config.yaml").read_text())
    config = copy.deepcopy(config)
    config["start_date"] = config["end_date"] = "2019-01-01"
    config["signals"]["G"]["pod_code"] = ["C1C", "C2W"]
    config["products"]["dcb_p1c1"] = ("resources/{campaign}/simulate/gnss/{date}_p1c1.dcb"
                                      if dcb else None)
    if not guard:
        config["ambiguity"]["product_guard"] = False
        config["ambiguity"]["nl_max_shift_sigma"] = 1e9
    return config


def run_case(root: Path, name: str, first: Path | None) -> Path:
    """Run the case up to its ambiguity table in ``root/name`` (simulation copied from
    ``first``); return the directory."""
    work = root / name
    work.mkdir(parents=True, exist_ok=True)
    (work / "campaign.yaml").write_text(yaml.safe_dump(campaign(*CASES[name]), sort_keys=False))
    if first is not None and not (work / "resources").exists():
        shutil.copytree(first / "resources", work / "resources", symlinks=True)
    target = f"results/hy2b-sim/ambiguity/hy2b-sim/{DAY}.nc"
    subprocess.run([SNAKEMAKE, "--snakefile", str(REPO / "Snakefile"), "--cores", "1",
                    "--directory", str(work), target, "--configfile",
                    str(work / "campaign.yaml")], check=True, cwd=work)
    return work


def count(work: Path) -> dict:
    """Fixing rates and wrong fixes of the case's ambiguity table."""
    from leopod.simulate.ambiguity_truth import true_single_differences, wrong_fixes

    table = xr.load_dataset(work / f"results/hy2b-sim/ambiguity/hy2b-sim/{DAY}.nc")
    residuals = xr.load_dataset(work / f"results/hy2b-sim/float_pod/hy2b-sim/{DAY}_residuals.nc")
    truth = xr.load_dataset(work / f"resources/hy2b-sim/simulate/hy2b-sim/{DAY}_truth.nc")
    out = wrong_fixes(table, *true_single_differences(table, residuals, [truth]))
    out.update(wl_rate=round(float(table.attrs["wl_fixing_rate"]), 4),
               nl_rate=round(float(table.attrs["nl_fixing_rate"]), 4),
               guard=table.attrs.get("product_guard", ""))
    return out


if __name__ == "__main__":
    root = Path(sys.argv[1]).resolve()
    names = sys.argv[2:] or list(CASES)
    first = None
    for case in names:
        work = run_case(root, case, first)
        first = first or work
        print(case, count(work), flush=True)
