"""leopod.workflow.config: the schema as the one source of defaults (section_defaults,
with_defaults) and its agreement with the Snakefile's validation (snakemake.utils.validate)."""

from __future__ import annotations

import copy

import numpy as np
import pytest
import yaml
from snakemake.exceptions import WorkflowError

from leopod.workflow.config import (
    SCHEMA,
    load_campaign,
    section_defaults,
    validated,
    with_defaults,
)

REPO = SCHEMA.parents[2]
DEFINITIONS = sorted(yaml.safe_load(SCHEMA.read_text())["$defs"])


@pytest.mark.parametrize("name", DEFINITIONS)
def test_every_definition_has_valid_defaults(name):
    # the defaults of a section conform to its own schema (keys the schema requires and
    # does not default, such as pod.forces, aside)
    defaults = section_defaults(name)
    required = set(yaml.safe_load(SCHEMA.read_text())["$defs"][name].get("required", []))
    if not required:
        assert with_defaults(name, defaults) == defaults
        assert with_defaults(name, {}) == defaults


def test_section_defaults_are_what_the_campaign_validation_fills_in():
    # an empty simulate section in a campaign file gets exactly section_defaults("simulate")
    raw = yaml.safe_load((REPO / "config" / "config.yaml").read_text())
    raw["simulate"] = {}
    assert validated(raw)["simulate"] == section_defaults("simulate")
    del raw["simulate"]
    assert validated(raw)["simulate"] == section_defaults("simulate")
    assert validated(raw)["validation"] == section_defaults("validation")


def test_simulate_defaults_are_complete():
    d = section_defaults("simulate")
    assert d["seed"] == 2018 and d["marker"] == "SIML" and d["interval_s"] == 30.0
    assert d["orbit"]["inclination_deg"] is None          # computed: sun-synchronous
    assert d["truth"]["models"]["field"] == "satkit:ITU_GRACE16.gfc"
    assert d["gnss_products"] is None and d["slr"]["stations"] is None
    # list items and model-dependent keys are filled in too
    (m,) = d["code_bias_maps"]
    assert (m["model"], m["signal"], m["valley_m"]) == ("hy2b_p1", "C1W", -0.3)
    assert set(d["observations"]["noise_m"]) == {"C1C", "C1W", "C2W", "L1C", "L2W", "C1P",
                                                  "C5P", "L1P", "L5P", "E:C1C", "C5Q", "L5Q"}


def test_with_defaults_means_what_a_campaign_file_means():
    raw = yaml.safe_load((REPO / "config" / "config.yaml").read_text())
    partial = {"interval_s": 10.0, "systems": {"C": ["C1P", "C5P", "L1P", "L5P"]},
               "observations": {"noise_m": {"C1W": 0.0}},
               "orbit": {"altitude_km": 500.0},
               "code_bias_maps": [{"model": "bds3_patchy", "signal": "C1P", "seed": 3}],
               "gnss_products": {"orbit": ["a.sp3"], "clock": "b.clk", "osb": "c.bia"}}
    raw["simulate"] = copy.deepcopy(partial)
    got = with_defaults("simulate", partial)
    assert got == validated(raw)["simulate"]
    assert partial["orbit"] == {"altitude_km": 500.0}                 # the input is not changed
    assert got["systems"] == {"C": ["C1P", "C5P", "L1P", "L5P"]}      # a given mapping replaces
    assert got["observations"]["noise_m"]["C1W"] == 0.0               # per-code defaults kept
    assert got["observations"]["noise_m"]["C2W"] == 0.014142135623730949
    assert got["orbit"]["ltan_h"] == 18.0
    assert got["code_bias_maps"][0]["n_blobs"] == 15 and "valley_m" not in got["code_bias_maps"][0]
    assert got["gnss_products"]["dcb_p1c1"] is None
    # defaults are copies: filling one section does not change the next one
    got["orbit"]["ltan_h"] = 6.0
    got["code_bias_maps"][0]["seed"] = 99
    assert section_defaults("simulate")["orbit"]["ltan_h"] == 18.0
    assert with_defaults("simulate", {})["code_bias_maps"][0]["model"] == "hy2b_p1"


@pytest.mark.parametrize("section,named", [
    ({"sead": 1}, "'sead' was unexpected"),
    ({"orbit": {"altitude_km": 50.0}}, "50.0 is less than or equal to the minimum of 100"),
    ({"observations": {"noise_m": {"C1W": -1.0}}}, "less than the minimum"),
    ({"systems": {"R": ["C1C", "L1C"]}}, "'R' is not one of"),
    ({"gnss_products": {"orbit": "a", "clock": "b"}}, "'osb' is a required property"),
    ({"gnss_products": "a.sp3"}, "'a.sp3' is not of type 'null'"),
    ({"code_bias_maps": [{"model": "none", "plateau_m": 1.0}]}, "'plateau_m' was unexpected"),
    ({"slr": {"stations": ["YARL"]}}, "does not match"),
])
def test_with_defaults_rejects_with_a_message(section, named):
    with pytest.raises(WorkflowError, match=named):
        with_defaults("simulate", section)


def test_unknown_definition():
    with pytest.raises(KeyError, match="no definition 'simulation'"):
        section_defaults("simulation")


def test_yaw_flip_overlay_puts_the_flip_inside_the_campaign():
    """config/hy2d-sim-flip.yaml over hy2d-sim.yaml: one flip, inside the days, maps per mode.
    Authority: Jiang et al. (2023) - HY-2D flips once when beta crosses -1.5 deg; the epoch is
    that of leopod.frames.leo_attitude.yaw_flip_epochs on the simulated orbit (README)."""
    cfg = load_campaign(REPO / "config" / "hy2d-sim.yaml", REPO / "config" / "hy2d-sim-flip.yaml")
    (flip,) = cfg["satellites"]["hy2d-sim"]["yaw_flips"]
    start, end = np.datetime64(cfg["start_date"]), np.datetime64(cfg["end_date"]) + 1
    assert start + 1 < np.datetime64(flip) < end - 1    # whole days of data on both sides
    assert cfg["code_bias"]["attitude_modes"] is True
    assert cfg["satellites"]["hy2d-sim"]["attitude"] == "yaw_steering"


def test_satellite_orbit_overlay_is_checked_but_not_defaulted():
    cfg = load_campaign(REPO / "config" / "config.yaml", REPO / "config" / "two-satellites.yaml")
    assert cfg["satellites"]["leo2-sim"]["simulate_orbit"] == {"altitude_km": 500.0,
                                                                "ltan_h": 10.5}
    assert cfg["satellites"]["hy2b-sim"]["simulate_orbit"] == {}
    raw = yaml.safe_load((REPO / "config" / "config.yaml").read_text())
    raw["satellites"]["hy2b-sim"]["simulate_orbit"] = {"ltan_h": 25.0}
    with pytest.raises(WorkflowError, match="simulate_orbit.ltan_h: 25.0 is not <= 24"):
        validated(raw)
    raw["satellites"]["hy2b-sim"]["simulate_orbit"] = {"step_s": 5.0}
    with pytest.raises(WorkflowError, match="simulate_orbit.step_s: unknown key"):
        validated(raw)


def test_formation_block_of_the_lt1_campaign():
    # the schema (authority for the keys) accepts the Lutan-1-like campaign, leaves the
    # leader without a formation and gives the follower its settings; a wrong key is named
    from leopod.simulate.formation import FormationSettings

    cfg = load_campaign(REPO / "config" / "lt1-sim.yaml")
    assert cfg["satellites"]["lt1-a"]["formation"] is None
    follower = FormationSettings.from_config(cfg["satellites"]["lt1-b"]["formation"])
    assert follower.leader == "lt1-a" and follower.a_dlambda_m == -5000.0
    assert len(follower.manoeuvres) == 2 and follower.manoeuvres[0]["duration_s"] == 60.0
    raw = yaml.safe_load((REPO / "config" / "lt1-sim.yaml").read_text())
    raw["satellites"]["lt1-b"]["formation"]["a_dl_m"] = 1.0
    with pytest.raises(WorkflowError, match="a_dl_m"):
        validated(raw)
    raw = yaml.safe_load((REPO / "config" / "lt1-sim.yaml").read_text())
    raw["satellites"]["lt1-b"]["formation"]["manoeuvres"][0]["time_of_day"] = "12h"
    with pytest.raises(WorkflowError, match="12h"):
        validated(raw)


def test_baseline_section_of_the_lt1_campaign():
    # the schema (authority for keys and defaults) gives the follower its truth correlation
    # and the baseline its settings; a mode outside joint/reference_fixed is refused
    from leopod.estimation.baseline import BaselineSettings
    from leopod.simulate.formation import FormationSettings

    cfg = load_campaign(REPO / "config" / "lt1-sim.yaml")
    assert FormationSettings.from_config(
        cfg["satellites"]["lt1-b"]["formation"]).truth_correlation == 0.999
    settings = BaselineSettings.from_config(cfg["baseline"])
    assert (settings.mode, settings.dynamics) == ("joint", "relative")
    assert settings.dd_constraint_sigma_m == 1.0e-5
    default = BaselineSettings.from_config({})
    assert (default.mode, default.dynamics, default.dd_constraint_sigma_m) == (
        "joint", "independent", None)
    raw = yaml.safe_load((REPO / "config" / "lt1-sim.yaml").read_text())
    raw["baseline"]["mode"] = "leader_fixed"
    with pytest.raises(WorkflowError, match="leader_fixed"):
        validated(raw)


def test_a_misspelt_key_gets_one_line_with_a_did_you_mean():
    # authority: the campaign schema (quality.elevation_mask_deg is its key); issue 23 asks
    # for "did you mean `elevation_mask_deg`" instead of a dump of the schema section
    from leopod.workflow.config import campaign_problems

    raw = yaml.safe_load((REPO / "config" / "config.yaml").read_text())
    raw["quality"]["elevation_mask"] = raw["quality"].pop("elevation_mask_deg")
    raw["quallity"] = {}
    problems = campaign_problems(raw)
    assert "quality.elevation_mask: unknown key; did you mean 'elevation_mask_deg'?" in problems
    assert "quallity: unknown key; did you mean 'quality'?" in problems
    with pytest.raises(WorkflowError) as info:
        validated(raw)
    assert len(str(info.value).splitlines()) == 1 + len(problems) <= 4


def test_an_unquoted_date_and_a_bad_value_are_named_with_what_was_expected():
    import datetime

    from leopod.workflow.config import campaign_problems

    raw = yaml.safe_load((REPO / "config" / "config.yaml").read_text())
    raw["start_date"] = datetime.date(2019, 1, 1)       # YAML reads an unquoted date as a date
    raw["pod"]["system"] = "R"                          # GLONASS: not in the schema's enum
    problems = campaign_problems(raw)
    assert 'start_date: a date must be quoted in YAML, e.g. "2019-01-01"' in problems
    assert "pod.system: 'R' is not one of ['G', 'C', 'E']" in problems
    assert campaign_problems(yaml.safe_load((REPO / "config" / "config.yaml").read_text())) == []
