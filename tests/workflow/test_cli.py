"""The leopod command (leopod.cli): check, run and report over Snakemake.

Authorities: the campaign schema (what conforms), the files on disk (what is missing), and the
workflow's own dry run (what a run plans).
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from leopod.cli import main, missing_inputs
from leopod.workflow.config import load_campaign

REPO = Path(__file__).resolve().parents[2]
DEFAULT = REPO / "config" / "config.yaml"
GRACE = REPO / "config" / "grace-a-2007.yaml"


def _leopod(*args, cwd):
    return subprocess.run([sys.executable, "-m", "leopod.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=600, cwd=cwd)


def test_check_passes_a_simulated_campaign_and_names_what_the_workflow_writes(tmp_path):
    proc = _leopod("check", DEFAULT, cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "conforms to the schema" in proc.stdout
    assert "satellites.hy2b-sim.observations: simulated by the workflow" in proc.stdout


def test_check_lists_missing_inputs_per_entry(tmp_path):
    # the GRACE-A campaign names ../shared/... relative to the working directory: from an
    # empty folder every one of its four files is missing (one day)
    missing, produced = missing_inputs(load_campaign(GRACE), tmp_path)
    assert produced == {}
    assert set(missing) == {"products.gnss_orbit", "products.gnss_clock", "products.antex",
                            "satellites.grace-a.observations"}
    assert missing["satellites.grace-a.observations"] == [
        "../shared/data/grace-a_2007-080/graa0800.07o.gz"]
    assert main(["check", str(GRACE), "--directory", str(tmp_path)]) == 1


@pytest.mark.shared
def test_check_finds_the_real_inputs_from_the_checkout(shared):
    if Path(shared).resolve() != (REPO.parent / "shared").resolve():
        pytest.skip("the campaign names ../shared relative to the checkout")
    assert missing_inputs(load_campaign(GRACE), REPO)[0] == {}


def test_check_stops_at_schema_problems_with_one_line_each(tmp_path, capsys):
    raw = yaml.safe_load(DEFAULT.read_text())
    raw["quality"]["elevation_mask"] = raw["quality"].pop("elevation_mask_deg")
    (tmp_path / "bad.yaml").write_text(yaml.safe_dump(raw))
    assert main(["check", str(tmp_path / "bad.yaml"), "-d", str(tmp_path)]) == 2
    out = capsys.readouterr().out
    assert "quality.elevation_mask: unknown key; did you mean 'elevation_mask_deg'?" in out
    assert len(out.splitlines()) <= 3


def test_run_passes_snakemake_options_after_the_double_dash(tmp_path):
    proc = _leopod("run", DEFAULT, "--directory", tmp_path, "--cores", "1", "--", "-n",
                   cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    stats = dict(re.findall(r"^(\w+)\s+(\d+)$", proc.stdout, flags=re.M))
    assert stats["float_pod"] == "3"          # the default campaign: one satellite, 3 days
    assert not (tmp_path / "results").exists()
