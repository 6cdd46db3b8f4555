"""Campaign helpers: day lists and file-name templates.

Authority for GPS week/day: GPS week 1419 day 3 is 2007-03-21 (data/MANIFEST.md: CODE product
cod14193 for GRACE-A DOY 080); GPS week 1500 day 0 is 2008-10-05 (products_2008-279_whu).
"""

from pathlib import Path

import pytest

import leopod
from leopod.time.calendar import days_between, gps_week_dow, parse_date_id
from leopod.workflow.campaign import (
    arc_days,
    campaign_days,
    campaign_inputs,
    code_bias_periods,
    excluded_days,
    expand_template,
    input_templates,
    library_root,
    locate_inputs,
    located_source,
    next_days,
    period_days,
    pod_days,
    produced_kind,
    script_library_files,
)
from leopod.workflow.layout import Layout


def test_gps_week_and_templates():
    assert gps_week_dow(parse_date_id("2007-080")) == (1419, 3)
    assert gps_week_dow(parse_date_id("2008-10-05")) == (1500, 0)
    assert expand_template("cod{gpsweek}{dow}.sp3.gz", "2007-080") == "cod14193.sp3.gz"
    assert expand_template("graa{doy}0.{yy}o.gz", "2007-080") == "graa0800.07o.gz"
    assert expand_template("x/{sat}/{date}", "2007-080", "grace-a") == "x/grace-a/2007-080"


def test_days_between_crosses_year_end():
    assert days_between("2007-12-30", "2008-01-02") == ["2007-364", "2007-365", "2008-001",
                                                        "2008-002"]


def test_excluded_days_leave_the_campaign_and_the_arcs_of_their_neighbours():
    # issue 24, item 5: a failed day left out (exclude_days) no longer holds back the arcs of
    # its neighbours, its code-bias period or an overlap with a day it does not touch
    cfg = {"start_date": "2019-01-30", "end_date": "2019-02-03",
           "exclude_days": {"2019-031": "ingest: truncated RINEX", "2019-02-03": "no products"},
           "pod": {"arc_before_s": 10800.0, "arc_after_s": 10800.0},
           "code_bias": {"period": "month"}}
    assert excluded_days(cfg) == {"2019-031": "ingest: truncated RINEX",
                                  "2019-034": "no products"}
    assert campaign_days(cfg) == ["2019-030", "2019-032", "2019-033"]
    assert arc_days(cfg, "2019-030") == ["2019-030"]
    assert arc_days(cfg, "2019-032") == ["2019-032", "2019-033"]
    assert arc_days(cfg, "2019-033") == ["2019-032", "2019-033"]
    assert next_days(cfg) == {"2019-032": "2019-033"}
    # a day whose POD failed on usable data: out of the PODs, its data serve its neighbours
    pod = {**cfg, "exclude_pod_days": {"2019-032": "float_pod: no convergence"}}
    assert campaign_days(pod) == ["2019-030", "2019-032", "2019-033"]
    assert pod_days(pod) == ["2019-030", "2019-033"]
    assert arc_days(pod, "2019-033") == ["2019-032", "2019-033"]
    assert next_days(pod) == {}
    assert list(excluded_days(pod)) == ["2019-031", "2019-032", "2019-034"]
    assert code_bias_periods(cfg) == ["2019-01", "2019-02"]
    assert period_days(cfg, "2019-01") == ["2019-030"]
    with pytest.raises(ValueError, match="exclude_days: 2019-040 is not a day of the campaign"):
        excluded_days({**cfg, "exclude_days": {"2019-040": "x"}})


def test_bad_inputs_name_the_problem():
    with pytest.raises(ValueError, match="unknown placeholder {doyy}"):
        expand_template("x{doyy}", "2007-080")
    with pytest.raises(ValueError, match="'2007-400'"):
        parse_date_id("2007-400")
    with pytest.raises(ValueError, match="before start"):
        days_between("2007-03-02", "2007-03-01")


def test_script_library_files_follow_imports_transitively(tmp_path):
    # Authority: Python's import semantics. Importing leopod.ambiguity.screening runs
    # leopod/__init__.py and leopod/ambiguity/__init__.py; "from leopod.io import sp3" imports
    # the module leopod/io/sp3.py; imports inside functions count; other packages do not.
    script = tmp_path / "step.py"
    script.write_text("import numpy\nfrom leopod.ambiguity.screening import degraded_passes\n"
                      "from leopod.io import (\n    bias_sinex,  # biases\n    antex as atx,\n)\n"
                      "import leopod.io.clock as clk\n"
                      "def main():\n    from leopod.io import sp3\n")
    files = {Path(f).relative_to(Path(leopod.__file__).parent).as_posix()
             for f in script_library_files(script)}
    assert {"__init__.py", "ambiguity/__init__.py", "ambiguity/screening.py", "io/__init__.py",
            "io/sp3.py", "io/bias_sinex.py", "io/antex.py", "io/clock.py"} <= files
    # transitive: sp3 reads its text through io/_text.py
    assert "io/_text.py" in files
    assert not any(f.startswith("dynamics/") for f in files)


def test_script_library_files_follow_a_copy_of_the_sources(tmp_path):
    # a workflow run from another checkout (or a copy of one) tracks that checkout's sources
    # (leopod.workflow.campaign.library_root), not those of the imported package
    package = tmp_path / "src/leopod"
    (package / "ambiguity").mkdir(parents=True)
    for name in ("__init__.py", "ambiguity/__init__.py"):
        (package / name).write_text("")
    (package / "ambiguity/screening.py").write_text("from leopod.io import sp3\n")
    script = tmp_path / "scripts/step.py"
    script.parent.mkdir()
    script.write_text("from leopod.ambiguity.screening import degraded_passes\n")
    assert library_root(tmp_path) == tmp_path / "src"
    files = script_library_files(script, library_root(tmp_path))
    # leopod/io/sp3.py is not in the copy: only files that exist below the root are listed
    assert files == [str(package.resolve() / name) for name in
                     ("__init__.py", "ambiguity/__init__.py", "ambiguity/screening.py")]
    assert library_root(tmp_path / "scripts") is None
    with pytest.raises(ValueError, match="holds no leopod package"):
        script_library_files(script, tmp_path / "scripts")


def test_locate_inputs_round_trip():
    # Authority: the file-name conventions of the templates (GPS week 1419 day 3 = 2007-080,
    # MANIFEST.md); inputs written by rules (resources/<campaign>/simulate, the shared
    # resources/download) stay; located links go to the campaign's resources/<campaign>/locate
    config = {
        "campaign": "c",
        "products": {"gnss_orbit": "../shared/data/grace-a_{yyyy}-{doy}/cod{gpsweek}{dow}.sp3.gz",
                     "antex": "/data/igs05_1402.atx", "gnss_clock": None,
                     "wl_bias": "resources/download/cnes_wl/{date}.wsb"},
        "satellites": {"grace-a": {"observations": "/obs/{sat}/{date}.rnx"},
                       "sim": {"observations": "resources/c/simulate/{sat}/{date}.rnx"}},
    }
    new, located = locate_inputs(config)
    assert config["products"]["antex"] == "/data/igs05_1402.atx"      # input not modified
    assert new["products"]["gnss_orbit"] == \
        "resources/c/locate/products.gnss_orbit/{date}/cod{gpsweek}{dow}.sp3.gz"
    assert new["products"]["antex"] == "resources/c/locate/products.antex/igs05_1402.atx"
    assert new["products"]["wl_bias"] == config["products"]["wl_bias"]
    assert new["satellites"]["sim"] == config["satellites"]["sim"]
    assert set(located) == {"products.gnss_orbit", "products.antex",
                            "satellites.grace-a.observations"}
    assert located_source(located, "products.gnss_orbit", "2007-080/cod14193.sp3.gz") == \
        "../shared/data/grace-a_2007-080/cod14193.sp3.gz"
    assert located_source(located, "products.antex", "igs05_1402.atx") == "/data/igs05_1402.atx"
    assert located_source(located, "satellites.grace-a.observations",
                          "2007-080/2007-080.rnx") == "/obs/grace-a/2007-080.rnx"
    # the templates the rules read, by config entry; unset entries are left out
    assert input_templates(new) == {
        "products.gnss_orbit": new["products"]["gnss_orbit"],
        "products.antex": new["products"]["antex"],
        "products.wl_bias": "resources/download/cnes_wl/{date}.wsb",
        "satellites.grace-a.observations":
            "resources/c/locate/satellites.grace-a.observations/{date}/{date}.rnx",
        "satellites.sim.observations": "resources/c/simulate/{sat}/{date}.rnx",
    }


def test_campaign_inputs_fill_the_campaign_and_refuse_the_shared_simulate_folder():
    # one folder per campaign (issue 23, item 2): {campaign} names the campaign's own
    # folders; a simulated input of another campaign is a file to locate, not to simulate
    config = {"campaign": "b", "products": {"gnss_orbit": "resources/{campaign}/simulate/"
                                            "gnss/{date}.sp3"},
              "satellites": {"s": {"observations": "resources/a/simulate/{sat}/{date}.rnx"}}}
    filled = campaign_inputs(config)
    assert filled["products"]["gnss_orbit"] == "resources/b/simulate/gnss/{date}.sp3"
    assert config["products"]["gnss_orbit"].startswith("resources/{campaign}/")   # a copy
    assert produced_kind(filled["products"]["gnss_orbit"], config) == "simulated"
    assert produced_kind("resources/a/simulate/s/2019-001.rnx", config) is None
    assert produced_kind("resources/download/cod_orbit/{date}.sp3", config) == "downloaded"
    new, located = locate_inputs(filled)
    assert set(located) == {"satellites.s.observations"}
    # the layout before one folder per campaign is refused with the template to write
    config["satellites"]["s"]["observations"] = "resources/simulate/{sat}/{date}.rnx"
    with pytest.raises(ValueError, match=r"satellites.s.observations: .*write "
                       r"'resources/\{campaign\}/simulate/\{sat\}/\{date\}.rnx'"):
        campaign_inputs(config)
    for bad in ("", "..", "a/b"):
        with pytest.raises(ValueError, match="no folder name"):
            Layout.of({"campaign": bad})
    assert Layout.of({"campaign": "b"}).report == "results/b/report.html"


def test_signal_bias_inputs_list_every_arc_day_and_skip_missing_neighbours():
    """Issue 19, part 3: the bias products of every day an arc touches (each hour with its
    own day's biases); a neighbouring day whose product file is missing is left out (its
    epochs then use the central day's, leopod.gnss.signal_bias), the central day's is always
    required; the mode follows the AR product."""
    from leopod.workflow.campaign import signal_bias_inputs

    config = {"campaign": "c",
              "products": {"gnss_orbit": "o/{date}.sp3", "osb": "/data/COD{yyyy}{doy}.BIA",
                           "dcb_p1c1": "resources/c/simulate/gnss/{date}_p1c1.dcb"}}
    located_config, located = locate_inputs(config)
    templates = input_templates(located_config)
    days = ["2019-001", "2019-002", "2019-003"]
    existing = {"/data/COD2019001.BIA"}   # 2019-003's OSB file is not there
    files, spec = signal_bias_inputs(templates, located, "2019-002", days,
                                     exists=lambda p: p in existing)
    assert spec["mode"] == "absolute" and spec["central_day"] == "2019-002"
    assert spec["osb_days"] == ["2019-001", "2019-002"]
    assert [Path(p).name for p in files["signal_bias_osb"]] == ["COD2019001.BIA",
                                                                 "COD2019002.BIA"]
    # files written by rules (simulation) are taken as existing
    assert spec["dcb_days"] == days
    assert files["signal_bias_dcb"][2] == "resources/c/simulate/gnss/2019-003_p1c1.dcb"
    # with CNES/CLS WL biases the codes are brought to the clock reference instead
    config["products"]["wl_bias"] = "w/{date}.wsb"
    located_config, located = locate_inputs(config)
    _, spec = signal_bias_inputs(input_templates(located_config), located, "2019-002", days,
                                 exists=lambda p: True)
    assert spec["mode"] == "clock_reference"
    # no bias product: nothing listed, nothing corrected
    files, spec = signal_bias_inputs({"products.gnss_orbit": "o/{date}.sp3"}, {}, "2019-002",
                                     days)
    assert files == {} and spec["osb_days"] == spec["dcb_days"] == []
