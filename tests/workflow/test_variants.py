"""Solution variants (leopod.workflow.variants): POD lines and each variant's campaign."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from leopod.settings import read_yaml
from leopod.workflow.config import validated
from leopod.workflow.variants import formation_pairs, pod_lines, variant_config

REPO = Path(__file__).resolve().parents[2]
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
GC = REPO / "config" / "hy2d-sim-gc.yaml"


def test_each_satellite_has_its_line_then_one_per_variant():
    raw = read_yaml(GC)
    raw["satellites"]["other-sat"] = raw["satellites"]["hy2d-sim"]
    lines = pod_lines(validated(raw))
    assert list(lines) == ["hy2d-sim", "other-sat", "hy2d-sim_G", "hy2d-sim_C",
                           "other-sat_G", "other-sat_C"]
    assert lines["other-sat_C"] == ("other-sat", "C")
    assert lines["hy2d-sim"] == ("hy2d-sim", None)


def test_a_variant_replaces_its_keys_and_keeps_the_rest():
    raw = read_yaml(GC)
    campaign = validated(raw)
    gps = variant_config(raw, "G")
    assert campaign["pod"]["system"] == ["G", "C"] and campaign["pod"]["vce"] is True
    assert gps["pod"]["system"] == "G" and gps["pod"]["vce"] is False
    # every other key as in the campaign, defaults filled in as for the campaign
    for key in set(campaign["pod"]) - {"system", "vce"}:
        assert gps["pod"][key] == campaign["pod"][key], key
    assert gps["ambiguity"] == campaign["ambiguity"]


def test_a_variant_key_is_checked_like_the_section_it_replaces():
    raw = read_yaml(GC)
    raw["variants"]["G"]["pod"]["sampling"] = 30.0      # not a pod key
    with pytest.raises(Exception, match="sampling"):
        variant_config(raw, "G")
    raw["variants"]["G"]["pod"] = {"system": "R"}         # GLONASS: not in the schema's enum
    with pytest.raises(Exception, match="system"):
        variant_config(raw, "G")


def test_a_variant_cannot_switch_ambiguity_resolution():
    raw = read_yaml(GC)
    raw["variants"]["G"]["ambiguity"] = {"enabled": False}
    with pytest.raises(ValueError, match="variants.G.ambiguity.enabled"):
        variant_config(raw, "G")


@pytest.mark.parametrize("variants", [{"G+C": {"pod": {"system": "G"}}},
                                      {"G": {"quality": {"max_gap_s": 10.0}}},
                                      {"G": {}}])
def test_the_schema_refuses_bad_variants(variants):
    raw = read_yaml(GC)
    raw["variants"] = variants
    with pytest.raises(Exception, match="variants|G"):
        validated(raw)


def test_the_dag_runs_the_pod_per_line_and_the_upstream_steps_per_satellite(tmp_path):
    # config/hy2d-sim-gc.yaml: one satellite, three days, the combined solution and the
    # variants G and C
    proc = subprocess.run([SNAKEMAKE, "-n", "--snakefile", str(REPO / "Snakefile"),
                           "--directory", str(tmp_path), "--configfile", str(GC)],
                          capture_output=True, text=True, timeout=600, cwd=REPO)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    stats = dict(re.findall(r"^(\w+)\s+(\d+)$", proc.stdout, flags=re.M))
    assert stats["simulate"] == stats["ingest"] == stats["quality"] == "3"
    assert stats["code_bias"] == "1"
    assert stats["float_pod"] == stats["ambiguity"] == stats["fixed_pod"] == "9"
    assert stats["campaign_summary"] == "3" and stats["variant_comparison"] == "1"
    for line in ("hy2d-sim", "hy2d-sim_G", "hy2d-sim_C"):
        assert f"results/hy2d-sim-gc/fixed_pod/{line}/2021-193.sp3" in proc.stdout
    assert "results/hy2d-sim-gc/quality/hy2d-sim_G" not in proc.stdout
    # a campaign without variants plans no comparison
    raw = read_yaml(GC)
    raw.pop("variants")
    (tmp_path / "plain.yaml").write_text(yaml.safe_dump(raw))
    proc = subprocess.run([SNAKEMAKE, "-n", "--snakefile", str(REPO / "Snakefile"),
                           "--directory", str(tmp_path), "--configfile",
                           str(tmp_path / "plain.yaml")],
                          capture_output=True, text=True, timeout=600, cwd=REPO)
    assert proc.returncode == 0 and "variant_comparison" not in proc.stdout


LT1 = REPO / "config" / "lt1-sim.yaml"


def test_a_formation_pair_has_one_pair_line_per_solution():
    # config/lt1-sim.yaml: LT-1 B follows LT-1 A; variants G and C beside the G+C solution
    campaign = validated(read_yaml(LT1))
    pairs = formation_pairs(campaign, ["lt1-a", "lt1-b"])
    assert list(pairs) == ["lt1-a-lt1-b", "lt1-a-lt1-b_G", "lt1-a-lt1-b_C"]
    assert pairs["lt1-a-lt1-b"] == ("lt1-a", "lt1-b", "lt1-a-lt1-b", None)
    assert pairs["lt1-a-lt1-b_C"] == ("lt1-a_C", "lt1-b_C", "lt1-a-lt1-b", "C")
    # a pair needs both satellites
    assert formation_pairs(campaign, ["lt1-b"]) == {}


def test_the_dag_solves_each_pair_line_and_compares_them_in_the_pair_summary(tmp_path):
    proc = subprocess.run([SNAKEMAKE, "-n", "-p", "--snakefile", str(REPO / "Snakefile"),
                           "--directory", str(tmp_path), "--configfile", str(LT1)],
                          capture_output=True, text=True, timeout=600, cwd=REPO)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    stats = dict(re.findall(r"^(\w+)\s+(\d+)$", proc.stdout, flags=re.M))
    # the satellites' files once (2 satellites x 3 days), the POD per line (x 3 solutions)
    assert stats["simulate"] == stats["ingest"] == "6" and stats["float_pod"] == "18"
    # a baseline, range check and summary per pair line; one range series and one kinematic
    # baseline job per pair-day (the kinematic job solves G, C and G+C itself)
    assert stats["baseline"] == stats["range_check"] == "9"
    assert stats["simulate_range"] == stats["kinematic_baseline"] == "3"
    assert stats["formation_summary"] == "3" and stats["baseline_overlap"] == "6"
    out = proc.stdout
    assert "results/lt1-sim/baseline/lt1-a-lt1-b_G/2022-196.nc" in out
    assert "results/lt1-sim/kinematic_baseline/lt1-a-lt1-b_G" not in out
    assert "resources/lt1-sim/simulate/lt1-a_G" not in out
    # the G+C pair summary reads the G and C baselines (their mutual differences)
    summary = next(block for block in out.split("\n\n")
                   if "rule formation_summary:" in block
                   and "results/lt1-sim/summary/lt1-a-lt1-b_formation.csv" in block)
    assert "results/lt1-sim/baseline/lt1-a-lt1-b_C/2022-197.nc" in summary
