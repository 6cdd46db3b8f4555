"""Attitude files reach every step that needs the LEO body frame (common.smk: sat_attitude,
attitude_inputs; leopod.workflow.boundary.attitude_files; leopod.io.attitude.load_leo_attitude).

Authority: the design rule that a step's files are its inputs (so that a changed file reruns
exactly the steps that read it) and its settings its params; the arc-day rule of
leopod.workflow.campaign.arc_days (the POD arc 21:00 of the previous day to 03:00 of the next).
"""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml
from _campaign_config import default_config

from leopod.io.attitude import load_leo_attitude
from leopod.workflow.boundary import attitude_files, mock_snakemake

SAT = "hy2b-sim"
LOCATED = "resources/hy2b-sim/locate/satellites.hy2b-sim.attitude_file"


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    cfg = default_config(**{
        f"satellites.{SAT}.attitude": "file",
        f"satellites.{SAT}.attitude_file": {"path": "attitude/HY2B_{yyyy}{doy}.csv",
                                             "max_gap_s": 60.0, "outside": "nominal"},
        f"satellites.{SAT}.attitude_offset": {"yaw_deg": 180.0}})
    path = tmp_path_factory.mktemp("att") / "campaign.yaml"
    path.write_text(yaml.safe_dump(cfg))
    return path


@pytest.mark.parametrize("rule,days", [
    ("simulate", ["2019-001", "2019-002", "2019-003"]),     # the neighbours: day edges
    ("ingest", ["2019-001", "2019-002", "2019-003"]),
    ("quality", ["2019-001", "2019-002", "2019-003"]),
    ("float_pod", ["2019-001", "2019-002", "2019-003"]),
    ("fixed_pod", ["2019-001", "2019-002", "2019-003"]),
])
def test_the_attitude_files_of_the_arc_are_inputs_and_the_law_is_a_param(
        campaign, monkeypatch, rule, days):
    monkeypatch.chdir(Path.cwd())
    sm = mock_snakemake(rule, configfiles=[campaign], sat=SAT, date="2019-002")
    files = attitude_files(sm)
    assert files == [f"{LOCATED}/{d}/HY2B_{{yyyy}}{{doy}}.csv".replace(
        "{yyyy}", d[:4]).replace("{doy}", d[5:]) for d in days]
    params = dict(sm.params.attitude)
    assert params["attitude"] == "file"
    assert params["attitude_file"]["max_gap_s"] == 60.0
    assert params["attitude_offset"]["yaw_deg"] == 180.0


def test_first_campaign_day_reads_the_days_inside_the_campaign(campaign, monkeypatch):
    monkeypatch.chdir(Path.cwd())
    sm = mock_snakemake("slr", configfiles=[campaign], sat=SAT, date="2019-001")
    assert [Path(f).parent.name for f in attitude_files(sm)] == ["2019-001", "2019-002"]


def test_modelled_laws_read_no_file(monkeypatch):
    monkeypatch.chdir(Path.cwd())
    sm = mock_snakemake("ingest", sat=SAT, date="2019-002")
    assert attitude_files(sm) == []
    law = load_leo_attitude(sm.params.attitude, attitude_files(sm))
    assert law.attitude == "nominal" and law.series is None
