"""The script boundary: every script's ``main`` runs from plain Python with paths and settings.

Authorities: the MANIFEST of the real GRACE-A day (10 s, 8640 epochs, 7-10 satellites per
epoch) for the ingest/quality chain; analytic truth (a circular orbit displaced by known RTN
offsets) for the overlap; Snakemake itself for the job that ``mock_snakemake`` rebuilds.
"""

from __future__ import annotations

import ast
import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from leopod.constants import GM_EARTH_M3_S2
from leopod.frames.earth_rotation import gcrf_to_itrf
from leopod.frames.rtn import rtn_matrix
from leopod.gnss.quality import QualitySettings
from leopod.signals import signal_settings
from leopod.workflow.boundary import REPOSITORY, mock_snakemake
from leopod.workflow.config import section_defaults

SCRIPTS = REPOSITORY / "scripts"


def _script(name: str):
    """scripts/<name>.py imported as a module (its ``__main__`` block does not run)."""
    spec = importlib.util.spec_from_file_location(f"leopod_script_{name}", SCRIPTS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("path", sorted(SCRIPTS.glob("*.py")), ids=lambda p: p.stem)
def test_every_script_has_main_and_run(path):
    """The shape every script shares: ``main`` (plain paths and settings) and ``run``
    (the Snakemake job mapped onto ``main``); no Snakemake object reaches ``main``."""
    tree = ast.parse(path.read_text())
    functions = {n.name: n for n in tree.body if isinstance(n, ast.FunctionDef)}
    assert {"main", "run"} <= set(functions)
    params = [a.arg for a in functions["main"].args.args + functions["main"].args.kwonlyargs]
    assert not {"snakemake", "sm", "inp", "out", "params"} & set(params)


def _circular_arc(start: str, offset_rtn_m=(0.0, 0.0, 0.0)) -> xr.Dataset:
    """30 h of a circular 500-km orbit at 30 s (GCRF + ITRF), displaced in its RTN axes."""
    a_m = 6_878_137.0
    n = math.sqrt(GM_EARTH_M3_S2 / a_m**3)
    t_s = np.arange(0.0, 30 * 3600.0 + 1e-6, 30.0)
    times = np.datetime64(start, "ns") + (t_s * 1e9).astype("timedelta64[ns]")
    u = n * (times - np.datetime64("2023-01-01", "ns")).astype(np.int64) * 1e-9
    inc = math.radians(97.4)
    pos = a_m * np.stack([np.cos(u), np.sin(u) * math.cos(inc), np.sin(u) * math.sin(inc)], 1)
    vel = a_m * n * np.stack([-np.sin(u), np.cos(u) * math.cos(inc),
                              np.cos(u) * math.sin(inc)], 1)
    pos = pos + np.einsum("nji,j->ni", rtn_matrix(pos, vel), np.asarray(offset_rtn_m))
    pos_itrf, vel_itrf = gcrf_to_itrf(times, pos, vel)
    dims = ("time", "xyz")
    return xr.Dataset({"pos_itrf_m": (dims, pos_itrf), "vel_itrf_m_s": (dims, vel_itrf),
                       "pos_gcrf_m": (dims, pos), "vel_gcrf_m_s": (dims, vel)},
                      coords={"time": times, "xyz": ["x", "y", "z"]})


def test_overlap_main_from_plain_paths(tmp_path):
    # arc b displaced by (1, -2, 3) cm in RTN: the overlap a - b is (-1, 2, -3) cm, 3D 3.74 cm
    a, b = tmp_path / "a.nc", tmp_path / "b.nc"
    _circular_arc("2022-12-31T21:00").to_netcdf(a)
    _circular_arc("2023-01-01T21:00", (0.01, -0.02, 0.03)).to_netcdf(b)
    out = tmp_path / "overlap.nc"
    _script("overlap").main(a, b, out, trim_s=0.0, title="test")
    rms = xr.load_dataset(out).rms_m
    np.testing.assert_allclose([float(rms.sel(component=c)) for c in ("R", "T", "N", "3D")],
                               [0.01, 0.02, 0.03, math.sqrt(14e-4)], atol=2e-4)


def test_campaign_summary_main_with_two_systems_and_pco_z(tmp_path):
    # GPS+BDS residuals and a PCO-Z parameter reach all three tables and the figures; every
    # column of the netCDF, per-system ones included, carries units and a long name
    # (authority: the summary's own column definitions, leopod.validation.summary).
    res = xr.Dataset({"phase_residual_m": (("time", "sv"), [[0.003, 0.004, -0.002]]),
                      "code_residual_m": (("time", "sv"), [[0.3, 0.4, 0.5]])},
                     coords={"sv": ["G01", "C20", "C30"]})
    par = xr.Dataset({"estimate": ("parameter", [0.0169]), "sigma": ("parameter", [0.0071])},
                     coords={"parameter": ["pco_z_m"]})
    res.to_netcdf(tmp_path / "res.nc")
    par.to_netcdf(tmp_path / "par.nc")
    files = {s: {"residuals": {"2021-186": str(tmp_path / "res.nc")},
                 "parameters": {"2021-186": str(tmp_path / "par.nc")}}
             for s in ("float_pod", "fixed_pod")}
    outputs = {k: tmp_path / f"summary.{k}" for k in ("nc", "csv", "html")}
    outputs |= {"pco_z_png": tmp_path / "pco.png", "fixing_png": tmp_path / "rates.png",
                "isb_png": tmp_path / "isb.png"}
    _script("campaign_summary").main(files, ["2021-186"], [], outputs, title="test")
    ds = xr.load_dataset(outputs["nc"])
    assert float(ds.phase_rms_C_mm[0]) == pytest.approx(np.sqrt(10.0))
    assert ds.phase_rms_C_mm.attrs["units"] == "mm" and "system C" in \
        ds.phase_rms_C_mm.attrs["long_name"]
    assert float(ds.pco_z_cm[0]) == pytest.approx(1.69)
    html = outputs["html"].read_text()
    # readable headers (column_label) of the per-system and PCO-Z columns
    assert "PCO-Z sigma" in html and "phase RMS G" in html and "0.71" in html
    assert outputs["pco_z_png"].read_bytes().startswith(b"\x89PNG")
    assert outputs["fixing_png"].read_bytes().startswith(b"\x89PNG")
    assert outputs["isb_png"].read_bytes().startswith(b"\x89PNG")     # "no ISB" note


@pytest.mark.shared
def test_products_ingest_and_quality_main_from_plain_paths(shared_data, tmp_path):
    d = shared_data / "grace-a_2007-080"
    signals = signal_settings({"G": {"phase": ["L1C", "L2W"], "code": ["C1C", "C1W", "C2W"],
                                     "pod_code": ["C1W", "C2W"]}})
    out = {k: tmp_path / f"{k}.nc" for k in ("obs", "gnss", "leo", "orbit", "clock", "antenna")}
    _script("gnss_products").main("2007-080", d / "cod14193.sp3.gz", d / "cod14193.clk.gz",
                                  d / "igs05_1402.atx.gz", out["orbit"], out["clock"],
                                  out["antenna"], systems=["G"])
    _script("ingest").main(d / "graa0800.07o.gz", out["orbit"], out["clock"], None,
                           out["antenna"], out["obs"], out["gnss"], out["leo"],
                           signals=signals,
                           pco_body_m={"L1": [0.0, 0.0, -0.4514], "L2": [0.0, 0.0, -0.4757]},
                           sp3_id=None)
    obs = xr.open_dataset(out["obs"])
    assert obs.sizes["time"] == 8640
    # graa0800.07o line 12: "  2007     3    21     0     0    0.0000000     GPS  TIME OF
    # FIRST OBS": GPS time, so the epochs do not move
    assert obs.attrs["time_system"] == "GPS" and obs.attrs["time_system_file"] == "GPS"
    assert obs.time.values[0] == np.datetime64("2007-03-21T00:00:00")
    figures = {k: tmp_path / f"{k}.png" for k in ("mp_elevation", "skyplot", "noise",
                                                   "visibility")}
    outputs = {"nc": tmp_path / "quality.nc", "summary": tmp_path / "summary.html", **figures}
    _script("quality").main(out["obs"], out["gnss"], out["leo"], signals,
                            QualitySettings.from_config(section_defaults("quality")),
                            "GRACE-A 2007-080", outputs, bds2_scb=True,
                            pco_body_m={"L1": [0.0, 0.0, -0.4514], "L2": [0.0, 0.0, -0.4757]},
                            antenna_path=out["antenna"])
    quality = xr.load_dataset(outputs["nc"])
    # antenna terms of the MP and HMW: the LEO's L1/L2 PCOs (2.43 cm apart along the boresight)
    # give a1 - a2 = (z1 - z2) sin(el) (analytic line-of-sight projection); igs05 gives the GPS
    # satellites the same L1 and L2 offsets and patterns
    el = np.radians(quality.el_deg.values)
    diff = (quality.antenna_range_1_m - quality.antenna_range_2_m).values
    seen = np.isfinite(diff) & np.isfinite(el)
    assert seen.sum() > 1000
    np.testing.assert_allclose(diff[seen], 0.0243 * np.sin(el[seen]), atol=1e-5)
    assert "ANTEX" in quality.attrs["antenna_gnss"] and "L2" in quality.attrs[
        "antenna_leo_pco_body_m"]
    assert 7.0 <= float(quality.G_mean_sv_per_epoch) <= 10.0
    # nadir angle at the GPS satellites of the LEO: at most that of a line tangent to the
    # LEO's sphere, sin(nadir) <= r_leo / r_gps (about 15 deg)
    gnss = xr.load_dataset(out["gnss"]).reindex(sv=quality.sv)
    r_leo = np.linalg.norm(xr.load_dataset(out["leo"]).pos_m.values, axis=-1)[:, None]
    ok = np.isfinite(quality.el_deg.values)
    limit = np.degrees(np.arcsin(r_leo / np.linalg.norm(gnss.pos_m.values, axis=-1)))
    nadir = quality.nadir_sv_deg.values
    assert ok.sum() > 1000 and np.all(nadir[ok] >= 0.0)
    assert np.all(nadir[ok] <= limit[ok] + 1e-9) and np.max(nadir[ok]) > 13.0
    assert all(p.stat().st_size > 0 for p in figures.values())


def test_mock_snakemake_rebuilds_a_job_of_the_default_campaign(monkeypatch):
    monkeypatch.chdir(Path.cwd())           # mock_snakemake moves to the repository root
    sm = mock_snakemake("float_pod", sat="hy2b-sim", date="2019-002")
    assert [Path(p).name for p in sm.input.obs] == [
        "2019-001_obs.nc", "2019-002_obs.nc", "2019-003_obs.nc"]      # the 30-h arc's days
    assert sm.output.sp3 == "results/hy2b-sim/float_pod/hy2b-sim/2019-002.sp3"
    assert sm.params.pod["outlier_k"] == section_defaults("pod")["outlier_k"]
    assert sm.rule == "float_pod"
    assert str(sm.log[0]) == "logs/hy2b-sim/float_pod/hy2b-sim/2019-002.log"
    with pytest.raises(ValueError, match="wildcards"):
        mock_snakemake("float_pod", sat="hy2b-sim")


def test_mock_snakemake_of_a_campaign_directory(monkeypatch, tmp_path):
    # a campaign run elsewhere (snakemake --directory D --configfile F): the job of that
    # directory, with its own settings
    monkeypatch.chdir(Path.cwd())
    repo = Path(__file__).resolve().parents[2]
    cfg = yaml.safe_load((repo / "config" / "config.yaml").read_text())
    cfg["pod"]["system"] = ["G", "C"]
    (tmp_path / "c.yaml").write_text(yaml.safe_dump(cfg))
    sm = mock_snakemake("float_pod", root=tmp_path, configfiles=[tmp_path / "c.yaml"],
                        snakefile=repo / "Snakefile", sat="hy2b-sim", date="2019-002")
    assert Path.cwd() == tmp_path and sm.params.pod["system"] == ["G", "C"]
    assert sm.output.sp3 == "results/hy2b-sim/float_pod/hy2b-sim/2019-002.sp3"
