"""The ANTEX file of a LEO antenna reaches every step that models the antenna (common.smk:
sat_antenna, antenna_inputs; leopod.workflow.boundary.leo_antenna_of).

Authority: the design rule that a step's files are its inputs (a changed ANTEX file reruns
exactly the steps that read it, through the locate step) and its settings its params.
"""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml
from _campaign_config import default_config

from leopod.gnss.leo_antenna import LeoAntenna
from leopod.workflow.boundary import leo_antenna_of, mock_snakemake, plain
from leopod.workflow.campaign import input_templates, locate_inputs

SAT = "hy2b-sim"
GOCE = Path(__file__).resolve().parents[3] / "shared" / "data" / "antex" / "GOCE_MAIN_0001.ATX"
LOCATED = f"resources/hy2b-sim/locate/satellites.{SAT}.antenna/GOCE_MAIN_0001.ATX"


def _config(**changes) -> dict:
    cfg = default_config(**changes)
    cfg["satellites"][SAT].pop("antenna_pco_body_m", None)
    cfg["satellites"][SAT]["antenna"] = {"antex": str(GOCE), "type": "GOCE",
                                         "arp_body_m": [0.0, 0.0, -0.4]}
    return cfg


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    path = tmp_path_factory.mktemp("ant") / "campaign.yaml"
    path.write_text(yaml.safe_dump(_config()))
    return path


def test_the_antex_file_is_located():
    located, entries = locate_inputs(_config())
    assert entries[f"satellites.{SAT}.antenna"] == str(GOCE)
    assert input_templates(located)[f"satellites.{SAT}.antenna"] == LOCATED


@pytest.mark.parametrize("rule", ["simulate", "ingest", "quality", "float_pod", "fixed_pod",
                                  "kinematic_pod"])
def test_the_antex_file_is_an_input_and_the_antenna_a_param(campaign, monkeypatch, rule):
    monkeypatch.chdir(Path.cwd())
    sm = mock_snakemake(rule, configfiles=[campaign], sat=SAT, date="2019-002")
    assert plain(sm.input)["leo_antex"] == LOCATED
    params = dict(sm.params.leo_antenna)
    assert params["type"] == "GOCE" and params["arp_body_m"] == [0.0, 0.0, -0.4]
    assert params["up_body"] == [0.0, 0.0, -1.0]          # schema default
    if GOCE.exists():       # the located link stands for the file: read the original here
        antenna = leo_antenna_of(sm.params.pco_body_m, params, {"leo_antex": str(GOCE)})
        assert isinstance(antenna, LeoAntenna) and antenna.has_pcv


def test_no_antex_no_input(monkeypatch):
    monkeypatch.chdir(Path.cwd())
    sm = mock_snakemake("float_pod", sat=SAT, date="2019-002")
    assert "leo_antex" not in plain(sm.input)
    assert leo_antenna_of(sm.params.pco_body_m, sm.params.leo_antenna, plain(sm.input)) \
        == sm.params.pco_body_m


def test_both_antenna_definitions_stop_the_campaign(tmp_path, monkeypatch):
    cfg = _config()
    cfg["satellites"][SAT]["antenna_pco_body_m"] = {"L1": [0, 0, -0.3], "L2": [0, 0, -0.3]}
    path = tmp_path / "both.yaml"
    path.write_text(yaml.safe_dump(cfg))
    monkeypatch.chdir(Path.cwd())
    with pytest.raises(Exception, match="either antenna_pco_body_m"):
        mock_snakemake("float_pod", configfiles=[path], sat=SAT, date="2019-002")


@pytest.fixture(scope="module")
def truth_campaign(tmp_path_factory):
    """The simulator with the GOCE pattern (simulate_antenna), the POD with a PCO table, and
    the PCV map on (the truth set-up of an in-flight PCV estimation, rule pcv)."""
    cfg = default_config()
    cfg["satellites"][SAT]["simulate_antenna"] = {"antex": str(GOCE), "type": "GOCE"}
    cfg["pcv"] = {"enabled": True}
    path = tmp_path_factory.mktemp("sim_ant") / "campaign.yaml"
    path.write_text(yaml.safe_dump(cfg))
    return path


def test_the_simulate_antenna_reaches_the_simulator_only(truth_campaign, monkeypatch):
    monkeypatch.chdir(Path.cwd())
    located = f"resources/hy2b-sim/locate/satellites.{SAT}.simulate_antenna/GOCE_MAIN_0001.ATX"
    sim = mock_snakemake("simulate", configfiles=[truth_campaign], sat=SAT, date="2019-002")
    assert plain(sim.input)["leo_antex"] == located
    assert sim.params.leo_antenna["type"] == "GOCE" and not sim.params.pco_body_m
    pod = mock_snakemake("float_pod", configfiles=[truth_campaign], sat=SAT, date="2019-002")
    assert "leo_antex" not in plain(pod.input) and pod.params.pco_body_m
    pcv = mock_snakemake("pcv", configfiles=[truth_campaign], sat=SAT, period="2019-01")
    files = plain(pcv.input)
    assert files["residuals"] == [f"results/hy2b-sim/fixed_pod/{SAT}/2019-00{d}_residuals.nc"
                                  for d in (1, 2, 3)]
    assert "leo_antex" not in files and pcv.params.solution == "fixed_pod"


def test_the_direct_method_reads_the_day_normal_equations(truth_campaign, tmp_path,
                                                          monkeypatch):
    """pcv.method direct: rule pcv reads the pcv_neq files of the period's days, and
    pcv_neq the fixed POD's inputs (float solution and ambiguity table) with the PCV
    settings."""
    cfg = yaml.safe_load(truth_campaign.read_text())
    cfg["pcv"] = {"enabled": True, "method": "direct", "estimate_pco_z": True}
    path = tmp_path / "direct.yaml"
    path.write_text(yaml.safe_dump(cfg))
    monkeypatch.chdir(Path.cwd())
    pcv = mock_snakemake("pcv", configfiles=[path], sat=SAT, period="2019-01")
    files = plain(pcv.input)
    assert files["neq"] == [f"results/hy2b-sim/pcv_neq/{SAT}/2019-00{d}.nc" for d in (1, 2, 3)]
    assert "residuals" not in files
    neq = mock_snakemake("pcv_neq", configfiles=[path], sat=SAT, date="2019-002")
    inputs = plain(neq.input)
    assert inputs["table"] == f"results/hy2b-sim/ambiguity/{SAT}/2019-002.nc"
    assert inputs["float_parameters"] == f"results/hy2b-sim/float_pod/{SAT}/2019-002_parameters.nc"
    assert neq.params.pcv["method"] == "direct" and neq.params.pcv["estimate_pco_z"]
    assert plain(neq.output)["neq"] == f"results/hy2b-sim/pcv_neq/{SAT}/2019-002.nc"
