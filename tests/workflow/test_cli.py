"""The leopod command (leopod.cli): check, run and report over Snakemake; compare orbits.

Authorities: the campaign schema (what conforms), the files on disk (what is missing), the
workflow's own dry run (what a run plans), and analytic orbits (what compare measures).
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
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


def test_run_exclude_failed_leaves_failed_days_out_until_none_fails(tmp_path, monkeypatch,
                                                                      capsys):
    # issue 24, item 5: pass 1 fails day 2's ingest (bad data -> exclude_days), pass 2 then
    # fails day 3's float POD (usable data -> exclude_pod_days), pass 3 succeeds; Snakemake
    # stands in for a function that writes the job logs as leopod.workflow.log does
    import leopod.cli

    stamp = "2026-11-27 14:00:00,000"
    failing = {1: ("ingest", "2019-002", "step ingest failed: x.rnx: line 9: cut short"),
               2: ("float_pod", "2019-003", "step float_pod failed: no observations")}
    calls = []

    def snakemake(cmd):
        calls.append(cmd)
        if len(calls) in failing:
            rule, day, text = failing[len(calls)]
            log = tmp_path / "logs/hy2b-sim" / rule / "hy2b-sim" / f"{day}.log"
            log.parent.mkdir(parents=True, exist_ok=True)
            log.write_text(f"{stamp} INFO root: rule {rule}, wildcards {{'sat': 'hy2b-sim', "
                           f"'date': '{day}'}}\n{stamp} ERROR root: {text}\n")
        return subprocess.CompletedProcess(cmd, 1 if len(calls) in failing else 0)

    monkeypatch.setattr(leopod.cli.subprocess, "run", snakemake)
    status = main(["run", str(DEFAULT), "--directory", str(tmp_path), "--exclude-failed"])
    assert status == 1 and len(calls) == 3
    assert all("--keep-going" in cmd for cmd in calls)
    overlay = tmp_path / "results/hy2b-sim/failed_days.yaml"
    assert str(overlay) in calls[1] and str(overlay) in calls[2]
    assert yaml.safe_load(overlay.read_text()) == {
        "exclude_days": {"2019-002": "ingest: x.rnx: line 9: cut short"},
        "exclude_pod_days": {"2019-003": "float_pod: no observations"}}
    out = capsys.readouterr().out
    assert "  2019-002  excluded: ingest: x.rnx: line 9: cut short" in out
    assert "  2019-003  excluded: float_pod: no observations" in out
    assert "hy2b-sim float_pod: 0 of 1 day(s) with an orbit" in out


def _circular_sp3(path: Path, radius_offset_m: float = 0.0, start="2019-01-02T00:00") -> Path:
    """SP3 of a 7000-km circular orbit (3 h at 30 s), its radius changed by ``radius_offset_m``."""
    from leopod.io.sp3_write import write_sp3

    t = np.arange(0, 3 * 3600 + 1, 30.0)
    phase, tilt = 2 * np.pi * t / 5800.0, np.radians(60.0)
    unit = np.column_stack([np.cos(phase), np.sin(phase) * np.cos(tilt),
                            np.sin(phase) * np.sin(tilt)])
    times = np.datetime64(start, "ns") + (t * 1e9).astype("timedelta64[ns]")
    pos = (7.0e6 + radius_offset_m) * unit
    write_sp3(xr.Dataset({"pos_m": (("time", "sv", "xyz"), pos[:, None, :])},
                         coords={"time": times, "sv": ["L01"], "xyz": ["x", "y", "z"]},
                         attrs={"time_system": "GPS"}), path)
    return path


def test_compare_gives_the_radial_offset_of_two_orbits(tmp_path):
    # analytic truth: the reference is the orbit raised by 5 cm along its position vector, a
    # purely radial offset in any Earth-centred frame (orbit minus reference: R -5 cm, T = N = 0
    # up to the 1-mm rounding of SP3 positions)
    orbit, reference = _circular_sp3(tmp_path / "a.sp3"), _circular_sp3(tmp_path / "b.sp3", 0.05)
    proc = _leopod("compare", orbit, reference, "--figure", tmp_path / "diff.png", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    total = next(line for line in proc.stdout.splitlines() if line.startswith("total"))
    values = [float(v) for v in total.split()[1:]]
    epochs, mean, rms = values[0], values[1:5], values[9:13]
    assert epochs == 361
    assert abs(mean[0] + 5.0) < 0.01 and abs(mean[1]) < 0.02 and abs(mean[2]) < 0.02
    assert abs(rms[0] - 5.0) < 0.01 and rms[1] < 0.05 and rms[2] < 0.05
    assert (tmp_path / "diff.png").stat().st_size > 10_000


def test_compare_without_a_common_span_fails_with_one_line(tmp_path):
    orbit = _circular_sp3(tmp_path / "a.sp3")
    reference = _circular_sp3(tmp_path / "b.sp3", start="2019-01-05T00:00")
    proc = _leopod("compare", orbit, reference, cwd=tmp_path)
    assert proc.returncode == 1
    assert proc.stderr.strip() == "leopod compare: the orbit and the reference have no common span"


def test_a_dry_run_with_missing_inputs_warns_and_lists_them(tmp_path, capsys, monkeypatch):
    # issue 23: Snakemake plans a dry run of a campaign whose files are missing without a word
    # (the files are located by jobs); leopod run warns first, per entry, naming the files.
    # Authority: the file system (the GRACE-A campaign's ../shared paths from an empty folder).
    calls = []
    monkeypatch.setattr("leopod.cli._execute", lambda cmd, progress: calls.append(cmd) or 0)
    assert main(["run", str(GRACE), "--directory", str(tmp_path), "--", "-n"]) == 0
    err = capsys.readouterr().err
    assert "warning: input files missing" in err
    assert ("warning: satellites.grace-a.observations: 1 file(s) missing: "
            "../shared/data/grace-a_2007-080/graa0800.07o.gz") in err
    assert len(calls) == 1 and "-n" in calls[0]
