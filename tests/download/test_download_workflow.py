"""The download_<family> rules inside a campaign: the real GRACE-A day fetched, not located.

The campaign is config/grace-a-2007.yaml with its observations, orbits, clocks and ANTEX given
as ``download:<family>``. The real files of ../shared/data play the archive (served over HTTP
on 127.0.0.1, or read as a local directory); every other archive of the default catalogue is
pointed at a closed port on 127.0.0.1, so no test can reach a real archive even when network
access is allowed. Authority for the file contents: ../shared/data/MANIFEST.md (GRACE-A day
2007-080: cod14193.sp3.gz, cod14193.clk.gz, graa0800.07o.gz, igs05_1402.atx.gz).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from _download_servers import HttpArchive

from leopod.workflow.layout import DOWNLOAD_ROOT as ROOT

REPO = Path(__file__).resolve().parents[2]
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
FILES = {"grace_a_obs": "2007-080.rnx", "cod_orbit": "2007-080.sp3",
         "cod_clock": "2007-080.clk", "antex_igs05_1402": "antex_igs05_1402.atx"}


def _campaign(work: Path, shared_url: str, refused: str, *, offline: bool = False,
              end_date: str = "2007-03-21") -> Path:
    cfg = yaml.safe_load((REPO / "config" / "grace-a-2007.yaml").read_text())
    cfg["end_date"] = end_date
    cfg["satellites"]["grace-a"]["observations"] = "download:grace_a_obs"
    cfg["products"].update(gnss_orbit="download:cod_orbit", gnss_clock="download:cod_clock",
                           antex="download:antex_igs05_1402")
    archives = yaml.safe_load((REPO / "config" / "catalogue.yaml").read_text())["archives"]
    urls = {name: refused for name in archives}
    urls["shared"] = shared_url
    cfg["download"] = {"offline": offline, "archive_urls": urls, "retries": 0,
                       "retry_delay_s": 0.0, "timeout_s": 5.0}
    path = work / "campaign.yaml"
    path.write_text(yaml.safe_dump(cfg))
    return path


def _snakemake(work: Path, config: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([SNAKEMAKE, "--snakefile", str(REPO / "Snakefile"), "--directory",
                           str(work), *args, "--configfile", str(config)],
                          check=False, capture_output=True, text=True, timeout=600)


@pytest.mark.shared
def test_an_offline_campaign_runs_from_a_local_archive(shared_data, tmp_path, refused_url):
    config = _campaign(tmp_path, str(shared_data), refused_url, offline=True)
    quality = "results/grace-a-2007/quality/grace-a/2007-080.nc"
    proc = _snakemake(tmp_path, config, quality, "--cores", "2")
    assert proc.returncode == 0, proc.stderr[-3000:]
    for family, name in FILES.items():
        assert (tmp_path / ROOT / family / name).stat().st_size > 0
    log = (tmp_path / "logs/grace-a-2007/download/cod_orbit/2007-080.sp3.log").read_text()
    assert "grace-a_2007-080/cod14193.sp3.gz" in log and "96 epochs" in log
    assert (tmp_path / quality).exists()
    # fetched again with the same content: nothing downstream reruns (profiles/default)
    (tmp_path / ROOT / "cod_orbit/2007-080.sp3").unlink()
    proc = _snakemake(tmp_path, config, f"{ROOT}/cod_orbit/2007-080.sp3", "--cores", "1")
    assert proc.returncode == 0, proc.stderr[-3000:]
    proc = _snakemake(tmp_path, config, quality, "-n")
    assert "Nothing to be done" in proc.stdout + proc.stderr


@pytest.mark.shared
def test_the_rules_fetch_over_http_after_failing_archives(shared_data, tmp_path, refused_url):
    server = HttpArchive(Path(shared_data))
    try:
        config = _campaign(tmp_path, server.url, refused_url)
        targets = [f"{ROOT}/{family}/{name}" for family, name in FILES.items()]
        proc = _snakemake(tmp_path, config, *targets, "--cores", "2")
        requested = server.paths()
    finally:
        server.close()
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "/grace-a_2007-080/cod14193.clk.gz" in requested
    text = (tmp_path / ROOT / "cod_clock/2007-080.clk").read_text()
    assert text.startswith("     2.00") and "CLOCK DATA" in text.splitlines()[0]
    # the preferred archives (CODE, CDDIS, IGN, BKG) were tried first and refused
    log = (tmp_path / "logs/grace-a-2007/download/cod_clock/2007-080.clk.log").read_text()
    assert log.count(refused_url) >= 4


@pytest.mark.shared
def test_a_day_without_products_fails_alone_and_names_every_archive(shared_data, tmp_path,
                                                                    refused_url):
    # 2007-03-22 exists in no archive: its downloads fail, 2007-03-21 is processed
    config = _campaign(tmp_path, str(shared_data), refused_url, end_date="2007-03-22")
    quality = "results/grace-a-2007/quality/grace-a"
    proc = _snakemake(tmp_path, config, f"{quality}/2007-080.nc", f"{quality}/2007-081.nc",
                      "--cores", "2", "--keep-going")
    assert proc.returncode != 0
    assert (tmp_path / "results/grace-a-2007/quality/grace-a/2007-080.nc").exists()
    assert not (tmp_path / "results/grace-a-2007/ingest/grace-a/2007-081_obs.nc").exists()
    assert not list((tmp_path / ROOT / "cod_orbit").glob("2007-081*"))
    log = (tmp_path / "logs/grace-a-2007/download/cod_orbit/2007-081.sp3.log").read_text()
    assert "cannot fetch product 'cod_orbit' for 2007-081" in log
    assert f"{refused_url}/2007/COD14194.EPH.Z" in log                 # CODE, short name
    assert f"{shared_data}/grace-a_2007-081/cod14194.sp3.gz: no such file" in log


def test_an_unknown_family_is_named_before_any_job(tmp_path, refused_url):
    config = _campaign(tmp_path, refused_url, refused_url)
    cfg = yaml.safe_load(config.read_text())
    cfg["products"]["gnss_orbit"] = "download:cod_orbits"
    config.write_text(yaml.safe_dump(cfg))
    proc = _snakemake(tmp_path, config, "-n")
    assert proc.returncode != 0
    assert "products.gnss_orbit: unknown product family 'cod_orbits'" in proc.stdout + proc.stderr
