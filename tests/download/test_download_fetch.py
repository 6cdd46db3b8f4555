"""fetch_product against local HTTP/FTP archives on 127.0.0.1 serving the real files of
../shared/data: decompression, fallbacks, resume, checksums, offline mirrors, atomicity.

Expected file contents come from independent decoders (gzip, unlzw3: _download_samples.plain)
or from MANIFEST.md facts (8640 epochs of 10 s in GRCB2080.10D); digests from hashlib.
"""

from __future__ import annotations

import gzip
import hashlib
import json
import socket
from pathlib import Path

import pytest
from _download_samples import (
    COD_SP3_GZ,
    GRACE_A_DAY,
    GRACE_B_CRX,
    GRACE_B_DAY,
    HTML_PAGE,
    WHU_BIA_Z,
    WHU_CLK_Z,
    WHU_DAY,
    bias_with_nan,
    plain,
    sp3_first_hours,
)
from _download_servers import FTP_USER, copy_into

from leopod.download import Catalogue, DownloadError, fetch_product
from leopod.io.rinex_obs import read_rinex_obs

REPO = Path(__file__).resolve().parents[2]
FAST = {"retries": 0, "retry_delay_s": 0.0, "timeout_s": 5.0}
SP3_PATH = "1419/cod14193.sp3.gz"  # the CODE SP3 of 2007-080 (GPS week 1419, day 3)


def catalogue(archives: dict, sources: list, *, kind="sp3", period="day", name="cod_orbit",
              description="CODE final GNSS orbits (SP3)") -> Catalogue:
    """A one-family catalogue; ``archives`` maps name -> URL or (URL, auth)."""
    arch = {k: ({"url": v} if isinstance(v, str) else {"url": v[0], "auth": v[1]})
            for k, v in archives.items()}
    family = {"description": description, "kind": kind, "period": period, "suffix": ".x",
              "sources": sources}
    return Catalogue.from_config({"archives": arch, "families": {name: family}})


def leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir()) if folder.exists() else []


@pytest.fixture
def sp3_gz(shared_data) -> Path:
    return shared_data / COD_SP3_GZ


# ------------------------------------------------------------------------------ normal fetches

@pytest.mark.shared
def test_http_gzip_product_is_decompressed_and_reported(http_archive, sp3_gz, tmp_path):
    copy_into(sp3_gz, http_archive.root, SP3_PATH)
    cat = catalogue({"ac": http_archive.url}, [{"archive": "ac", "path": SP3_PATH}])
    dest = tmp_path / "resources" / "cod_orbit" / "2007-080.sp3"
    report = fetch_product(cat, "cod_orbit", GRACE_A_DAY, dest, **FAST)
    expected = plain(sp3_gz)
    assert dest.read_bytes() == expected
    url = f"{http_archive.url}/{SP3_PATH}"
    assert report.origin == url and report.attempts == [(url, "ok")]
    assert report.used_network and report.date == GRACE_A_DAY and report.family == "cod_orbit"
    assert report.bytes == len(expected)
    assert report.sha256 == hashlib.sha256(expected).hexdigest()
    assert "96 epochs" in report.summary
    assert leftovers(dest.parent) == ["2007-080.sp3"]


@pytest.mark.shared
def test_ftp_real_whu_layout_of_the_default_catalogue(ftp_archive, shared_data, tmp_path):
    """The default catalogue's WHU templates, with the archive redirected to a local FTP
    server holding the two real WHU files of 2008-279 at their real paths."""
    copy_into(shared_data / WHU_CLK_Z, ftp_archive.public, "2008/clock/whp15000.clk.Z")
    copy_into(shared_data / WHU_BIA_Z, ftp_archive.public,
              "2008/bias/WHU0IGSFIN_20082790000_01D_01D_ABS.BIA.Z")
    cat = Catalogue.from_yaml(REPO / "config/catalogue.yaml").with_archive_urls(
        {"whu": ftp_archive.url})
    clk = fetch_product(cat, "whu_phase_clock", WHU_DAY, tmp_path / "clk" / "2008-279.clk", **FAST)
    # the long name does not exist for 2008: FTP 550, then the short name
    assert clk.attempts[0][0].endswith("WHU5IGSFIN_20082790000_01D_30S_CLK.CLK.Z")
    assert clk.attempts[0][1].startswith("FTP 550")
    assert clk.attempts[1] == (f"{ftp_archive.url}/2008/clock/whp15000.clk.Z", "ok")
    assert clk.dest.read_bytes() == plain(shared_data / WHU_CLK_Z)
    bia = fetch_product(cat, "whu_abs_bias", WHU_DAY, tmp_path / "bia" / "2008-279.bia", **FAST)
    assert bia.dest.read_bytes() == plain(shared_data / WHU_BIA_Z)
    assert "128 biases" in bia.summary


@pytest.mark.shared
def test_http_hatanaka_observations(http_archive, shared_data, tmp_path):
    copy_into(shared_data / GRACE_B_CRX, http_archive.root, "leo/2010/GRCB2080.10D")
    cat = catalogue({"leo": http_archive.url},
                    [{"archive": "leo", "path": "leo/{yyyy}/GRCB{doy}0.{yy}D"}], kind="rinex_obs")
    dest = tmp_path / "grace-b" / "2010-208.rnx"
    fetch_product(cat, "cod_orbit", GRACE_B_DAY, dest, **FAST)
    assert dest.read_bytes()[:80].split()[:3] == [b"2.20", b"OBSERVATION", b"DATA"]
    assert read_rinex_obs(dest).sizes["time"] == 8640  # MANIFEST.md: full day at 10 s


@pytest.mark.shared
def test_ftp_user_login_from_netrc(ftp_archive, sp3_gz, netrc_file, tmp_path):
    copy_into(sp3_gz, ftp_archive.private, SP3_PATH)
    sources = [{"archive": "private", "path": SP3_PATH}]
    cat = catalogue({"private": (ftp_archive.url, "netrc")}, sources)
    netrc_file({"127.0.0.1": FTP_USER})
    report = fetch_product(cat, "cod_orbit", GRACE_A_DAY, tmp_path / "a.sp3", **FAST)
    assert report.dest.read_bytes() == plain(sp3_gz)
    # no entry for the host: a clear, permanent failure
    netrc_file({"ftp.example.org": FTP_USER})
    with pytest.raises(DownloadError, match="no netrc entry for host 127.0.0.1"):
        fetch_product(cat, "cod_orbit", GRACE_A_DAY, tmp_path / "b.sp3", **FAST)
    # anonymous login does not see the user's tree
    anonymous = catalogue({"private": ftp_archive.url}, sources)
    with pytest.raises(DownloadError, match="FTP 550"):
        fetch_product(anonymous, "cod_orbit", GRACE_A_DAY, tmp_path / "c.sp3", **FAST)


@pytest.mark.shared
def test_http_basic_auth_per_host_after_redirect(http_archive, sp3_gz, netrc_file, tmp_path):
    """An archive redirecting to a login host (as CDDIS to urs.earthdata.nasa.gov): the
    credentials are those of the login host, looked up in netrc when it asks."""
    login = f"http://localhost:{http_archive.port}/login/cod14193.sp3.gz"
    http_archive.rules["/archive/cod14193.sp3.gz"] = {"redirect": login}
    http_archive.rules["/login/cod14193.sp3.gz"] = {"auth": ("bob", "pw"),
                                                    "body": sp3_gz.read_bytes()}
    cat = catalogue({"cddis": (f"{http_archive.url}/archive", "netrc")},
                    [{"archive": "cddis", "path": "cod14193.sp3.gz"}])
    netrc_file({"localhost": ("bob", "pw")})  # nothing for 127.0.0.1
    report = fetch_product(cat, "cod_orbit", GRACE_A_DAY, tmp_path / "a.sp3", **FAST)
    assert report.dest.read_bytes() == plain(sp3_gz)
    login_requests = [r for r in http_archive.requests if r["path"].startswith("/login")]
    assert [r["Authorization"] is None for r in login_requests] == [True, False]
    assert login_requests[1]["Host"] == f"localhost:{http_archive.port}"
    netrc_file({"localhost": ("bob", "wrong")})
    with pytest.raises(DownloadError, match="HTTP 401"):
        fetch_product(cat, "cod_orbit", GRACE_A_DAY, tmp_path / "b.sp3", **FAST)


# ------------------------------------------------------------------------------ fallbacks

@pytest.mark.shared
def test_fallback_over_refused_404_and_500(http_archive, refused_url, sp3_gz, tmp_path):
    copy_into(sp3_gz, http_archive.root, SP3_PATH)
    http_archive.rules["/broken/cod14193.sp3.gz"] = {"status": 500}
    cat = catalogue({"down": refused_url, "ac": http_archive.url}, [
        {"archive": "down", "path": SP3_PATH},
        {"archive": "ac", "path": "missing/cod14193.sp3.gz"},
        {"archive": "ac", "path": "broken/cod14193.sp3.gz"},
        {"archive": "ac", "path": SP3_PATH},
    ])
    report = fetch_product(cat, "cod_orbit", GRACE_A_DAY, tmp_path / "o.sp3", retries=2,
                           retry_delay_s=0.0, timeout_s=5.0)
    reasons = [why for _, why in report.attempts]
    assert reasons[0].startswith("cannot connect") and "refused" in reasons[0].lower()
    assert reasons[1:] == ["HTTP 404 Not Found", "HTTP 500 Internal Server Error", "ok"]
    paths = http_archive.paths()
    assert paths.count("/missing/cod14193.sp3.gz") == 1  # 404 is permanent: no retry
    assert paths.count("/broken/cod14193.sp3.gz") == 3   # 500 is transient: 1 + 2 retries
    assert report.dest.read_bytes() == plain(sp3_gz)


@pytest.mark.shared
@pytest.mark.parametrize("corruption, reason", [
    ("truncated_gzip", "corrupt or truncated gzip stream"),
    ("html_as_gzip", "named .gz but not gzip data (an HTML/XML page)"),
    ("html_as_plain", "cod14193.sp3: an HTML/XML page"),
    ("partial_day", "does not cover the day 2007-03-21"),
])
def test_fallback_on_corrupt_orbit(http_archive, sp3_gz, shared_data, tmp_path, corruption,
                                   reason):
    raw = sp3_gz.read_bytes()
    bad_name, body = {
        "truncated_gzip": ("cod14193.sp3.gz", raw[: len(raw) // 2]),
        "html_as_gzip": ("cod14193.sp3.gz", HTML_PAGE),
        "html_as_plain": ("cod14193.sp3", HTML_PAGE),
        "partial_day": ("cod14193.sp3.gz", gzip.compress(sp3_first_hours(shared_data, 18))),
    }[corruption]
    http_archive.rules[f"/bad/{bad_name}"] = {"body": body}
    copy_into(sp3_gz, http_archive.root, SP3_PATH)
    cat = catalogue({"ac": http_archive.url}, [{"archive": "ac", "path": f"bad/{bad_name}"},
                                               {"archive": "ac", "path": SP3_PATH}])
    dest = tmp_path / "res" / "o.sp3"
    report = fetch_product(cat, "cod_orbit", GRACE_A_DAY, dest, **FAST)
    assert reason in report.attempts[0][1]
    assert report.attempts[1][1] == "ok"
    assert dest.read_bytes() == plain(sp3_gz)
    assert leftovers(dest.parent) == ["o.sp3"]  # the corrupt .part was discarded


@pytest.mark.shared
def test_fallback_on_bias_with_nan(ftp_archive, http_archive, shared_data, tmp_path):
    """PRIDE-PPPAR#56: a NaN OSB must not reach the processing; the next source is used."""
    text, line = bias_with_nan(shared_data)
    name = "WHU0IGSFIN_20082790000_01D_01D_ABS.BIA"
    http_archive.rules[f"/{name}"] = {"body": text}
    copy_into(shared_data / WHU_BIA_Z, ftp_archive.public, f"2008/bias/{name}.Z")
    cat = catalogue({"mirror": http_archive.url, "whu": ftp_archive.url},
                    [{"archive": "mirror", "path": name},
                     {"archive": "whu", "path": "{yyyy}/bias/" + name + ".Z"}], kind="bias_sinex")
    report = fetch_product(cat, "cod_orbit", WHU_DAY, tmp_path / "b.bia", **FAST)
    assert report.attempts[0][1] == (f"{name}:{line}: field 'ESTIMATED_VALUE': 'nan' is not a "
                                     "finite number")
    assert report.origin.startswith("ftp://")
    assert report.dest.read_bytes() == plain(shared_data / WHU_BIA_Z)


@pytest.mark.shared
def test_timeout_goes_to_next_source(http_archive, sp3_gz, tmp_path):
    http_archive.rules["/slow/cod14193.sp3.gz"] = {"delay_s": 1.5}
    copy_into(sp3_gz, http_archive.root, SP3_PATH)
    cat = catalogue({"ac": http_archive.url}, [{"archive": "ac", "path": "slow/cod14193.sp3.gz"},
                                               {"archive": "ac", "path": SP3_PATH}])
    report = fetch_product(cat, "cod_orbit", GRACE_A_DAY, tmp_path / "o.sp3", retries=0,
                           retry_delay_s=0.0, timeout_s=0.2)
    assert report.attempts[0][1] == "timed out after 0.2 s"
    assert report.attempts[1][1] == "ok"


@pytest.mark.shared
def test_all_sources_fail_error_names_product_and_every_url(http_archive, refused_url, sp3_gz,
                                                            tmp_path):
    http_archive.rules["/bad/cod14193.sp3.gz"] = {"body": HTML_PAGE}
    cat = catalogue({"ac": http_archive.url, "down": refused_url}, [
        {"archive": "ac", "path": "missing/cod14193.sp3.gz"},
        {"archive": "down", "path": SP3_PATH},
        {"archive": "ac", "path": "bad/cod14193.sp3.gz"},
    ])
    dest = tmp_path / "res" / "o.sp3"
    with pytest.raises(DownloadError) as info:
        fetch_product(cat, "cod_orbit", GRACE_A_DAY, dest, **FAST)
    lines = str(info.value).splitlines()
    assert lines[0].startswith("cannot fetch product 'cod_orbit' for 2007-080 (CODE final GNSS "
                               "orbits (SP3))")
    assert lines[1] == f"  {http_archive.url}/missing/cod14193.sp3.gz: HTTP 404 Not Found"
    assert lines[2].startswith(f"  {refused_url}/{SP3_PATH}: cannot connect")
    assert lines[3].startswith(f"  {http_archive.url}/bad/cod14193.sp3.gz: named .gz but not gzip")
    assert len(lines) == 4 and len(info.value.attempts) == 3
    assert leftovers(dest.parent) == []  # atomic: no destination, no temporary file


# ------------------------------------------------------------------------------ resume

@pytest.mark.shared
def test_http_resume_after_interruption(http_archive, sp3_gz, tmp_path):
    copy_into(sp3_gz, http_archive.root, SP3_PATH)
    http_archive.rules[f"/{SP3_PATH}"] = {"cut_after": 1000}
    cat = catalogue({"ac": http_archive.url}, [{"archive": "ac", "path": SP3_PATH}])
    dest = tmp_path / "res" / "o.sp3"
    report = fetch_product(cat, "cod_orbit", GRACE_A_DAY, dest, retries=1, retry_delay_s=0.0,
                           timeout_s=5.0)
    first, second = http_archive.requests
    assert first["Range"] is None
    assert second["Range"] == "bytes=1000-" and second["If-Range"].startswith('"')
    assert report.dest.read_bytes() == plain(sp3_gz)
    assert leftovers(dest.parent) == ["o.sp3"]


@pytest.mark.shared
def test_resume_across_runs_keeps_only_the_part(http_archive, sp3_gz, tmp_path):
    copy_into(sp3_gz, http_archive.root, SP3_PATH)
    http_archive.rules[f"/{SP3_PATH}"] = {"cut_after": 5000}
    cat = catalogue({"ac": http_archive.url}, [{"archive": "ac", "path": SP3_PATH}])
    dest = tmp_path / "res" / "o.sp3"
    with pytest.raises(DownloadError, match="connection closed after 5000 of"):
        fetch_product(cat, "cod_orbit", GRACE_A_DAY, dest, **FAST)
    assert leftovers(dest.parent) == ["o.sp3.part", "o.sp3.part.json"]
    assert (dest.parent / "o.sp3.part").read_bytes() == sp3_gz.read_bytes()[:5000]
    state = json.loads((dest.parent / "o.sp3.part.json").read_text())
    assert state["url"] == f"{http_archive.url}/{SP3_PATH}"
    fetch_product(cat, "cod_orbit", GRACE_A_DAY, dest, **FAST)  # a later run
    assert http_archive.requests[-1]["Range"] == "bytes=5000-"
    assert dest.read_bytes() == plain(sp3_gz)
    assert leftovers(dest.parent) == ["o.sp3"]


@pytest.mark.shared
def test_server_ignoring_range_restarts_cleanly(http_archive, sp3_gz, tmp_path):
    copy_into(sp3_gz, http_archive.root, SP3_PATH)
    http_archive.rules[f"/{SP3_PATH}"] = {"cut_after": 3000, "ignore_range": True}
    cat = catalogue({"ac": http_archive.url}, [{"archive": "ac", "path": SP3_PATH}])
    report = fetch_product(cat, "cod_orbit", GRACE_A_DAY, tmp_path / "o.sp3", retries=1,
                           retry_delay_s=0.0, timeout_s=5.0)
    assert http_archive.requests[1]["Range"] == "bytes=3000-"  # asked, answered with 200
    assert report.dest.read_bytes() == plain(sp3_gz)


@pytest.mark.shared
def test_changed_remote_file_is_not_appended(http_archive, sp3_gz, tmp_path):
    """A .part whose recorded validator no longer matches (If-Range) restarts from byte 0."""
    copy_into(sp3_gz, http_archive.root, SP3_PATH)
    url = f"{http_archive.url}/{SP3_PATH}"
    (tmp_path / "o.sp3.part").write_bytes(b"stale bytes of an older version")
    (tmp_path / "o.sp3.part.json").write_text(json.dumps({"url": url, "validator": '"old"'}))
    cat = catalogue({"ac": http_archive.url}, [{"archive": "ac", "path": SP3_PATH}])
    report = fetch_product(cat, "cod_orbit", GRACE_A_DAY, tmp_path / "o.sp3", **FAST)
    assert http_archive.requests[0]["If-Range"] == '"old"'
    assert report.dest.read_bytes() == plain(sp3_gz)


@pytest.mark.shared
def test_part_of_another_url_is_not_continued(http_archive, sp3_gz, tmp_path):
    copy_into(sp3_gz, http_archive.root, SP3_PATH)
    (tmp_path / "o.sp3.part").write_bytes(b"x" * 100)
    (tmp_path / "o.sp3.part.json").write_text(json.dumps({"url": "ftp://elsewhere/x"}))
    cat = catalogue({"ac": http_archive.url}, [{"archive": "ac", "path": SP3_PATH}])
    fetch_product(cat, "cod_orbit", GRACE_A_DAY, tmp_path / "o.sp3", **FAST)
    assert http_archive.requests[0]["Range"] is None


@pytest.mark.shared
def test_ftp_resume_with_rest(ftp_archive, sp3_gz, tmp_path):
    copy_into(sp3_gz, ftp_archive.public, SP3_PATH)
    ftp_archive.truncate_next("cod14193.sp3.gz", 2000)
    cat = catalogue({"ign": ftp_archive.url}, [{"archive": "ign", "path": SP3_PATH}])
    dest = tmp_path / "res" / "o.sp3"
    report = fetch_product(cat, "cod_orbit", GRACE_A_DAY, dest, retries=1, retry_delay_s=0.0,
                           timeout_s=5.0)
    commands = ftp_archive.commands
    assert ("REST", "2000") in commands
    assert commands.index(("REST", "2000")) > commands.index(("RETR", "cod14193.sp3.gz"))
    assert report.dest.read_bytes() == plain(sp3_gz)
    assert leftovers(dest.parent) == ["o.sp3"]


# ------------------------------------------------------------------------------ checksums

def _sums(entries: dict[str, bytes], algorithm="sha512") -> bytes:
    # authority: hashlib digests of the served bytes (sha512sum format)
    return "".join(f"{hashlib.new(algorithm, data).hexdigest()}  {name}\n"
                   for name, data in entries.items()).encode()


@pytest.mark.shared
def test_checksum_list_verified_and_mismatch_rejected(http_archive, ftp_archive, sp3_gz,
                                                      tmp_path):
    raw = sp3_gz.read_bytes()
    copy_into(sp3_gz, http_archive.root, SP3_PATH)
    copy_into(sp3_gz, ftp_archive.public, SP3_PATH)
    source = {"archive": "cddis", "path": SP3_PATH, "checksums": "{gpsweek}/SHA512SUMS"}
    fallback = {"archive": "ign", "path": SP3_PATH}
    cat = catalogue({"cddis": http_archive.url, "ign": ftp_archive.url}, [source, fallback])

    (http_archive.root / "1419" / "SHA512SUMS").write_bytes(_sums({"cod14193.sp3.gz": raw}))
    res = tmp_path / "res"
    good = fetch_product(cat, "cod_orbit", GRACE_A_DAY, res / "a.sp3", **FAST)
    assert good.origin.startswith("http://") and good.attempts[0][1] == "ok"

    (http_archive.root / "1419" / "SHA512SUMS").write_bytes(
        _sums({"cod14193.sp3.gz": raw + b"x"}, "md5"))
    bad = fetch_product(cat, "cod_orbit", GRACE_A_DAY, res / "b.sp3", **FAST)
    assert bad.attempts[0][1].startswith("md5 mismatch for cod14193.sp3.gz")
    assert bad.origin.startswith("ftp://") and bad.dest.read_bytes() == plain(sp3_gz)

    (http_archive.root / "1419" / "SHA512SUMS").write_bytes(_sums({"igs14193.sp3.Z": raw}))
    missing = fetch_product(cat, "cod_orbit", GRACE_A_DAY, res / "c.sp3", **FAST)
    assert "has no entry for cod14193.sp3.gz" in missing.attempts[0][1]

    (http_archive.root / "1419" / "SHA512SUMS").unlink()
    absent = fetch_product(cat, "cod_orbit", GRACE_A_DAY, res / "d.sp3", **FAST)
    assert absent.attempts[0][1] == (f"checksum list {http_archive.url}/1419/SHA512SUMS: "
                                     "HTTP 404 Not Found")
    assert leftovers(res) == ["a.sp3", "b.sp3", "c.sp3", "d.sp3"]  # no .part, list or temp file


@pytest.mark.shared
def test_fixed_sha256_of_a_static_file(http_archive, sp3_gz, tmp_path):
    copy_into(sp3_gz, http_archive.root, "static/cod.sp3.gz")
    right = hashlib.sha256(sp3_gz.read_bytes()).hexdigest()
    for digest, ok in ((right, True), ("0" * 64, False)):
        cat = catalogue({"ac": http_archive.url}, [{"archive": "ac", "path": "static/cod.sp3.gz",
                                                    "sha256": digest}], period="static")
        if ok:
            fetch_product(cat, "cod_orbit", None, tmp_path / "ok.sp3", **FAST)
        else:
            with pytest.raises(DownloadError, match=f"sha256 mismatch .* got {right}"):
                fetch_product(cat, "cod_orbit", None, tmp_path / "bad.sp3", **FAST)
    assert not (tmp_path / "bad.sp3").exists()


# ------------------------------------------------------------------------------ no network

@pytest.mark.shared
def test_offline_from_mirror_without_any_server(refused_url, sp3_gz, tmp_path):
    cat = catalogue({"code": refused_url, "cddis": refused_url},
                    [{"archive": "code", "path": "{yyyy}/COD{gpsweek}{dow}.EPH.Z"},
                     {"archive": "cddis", "path": SP3_PATH}])
    flat = tmp_path / "flat"  # a flat folder of decompressed products
    flat.mkdir()
    (flat / "cod14193.sp3").write_bytes(plain(sp3_gz))
    res = tmp_path / "res"
    res.mkdir()
    (res / "a.sp3.part").write_bytes(b"start of an interrupted download")
    (res / "a.sp3.part.json").write_text(json.dumps({"url": f"{refused_url}/{SP3_PATH}"}))
    report = fetch_product(cat, "cod_orbit", GRACE_A_DAY, res / "a.sp3", mirrors=[flat],
                           offline=True, **FAST)
    assert report.origin == str(flat / "cod14193.sp3") and not report.used_network
    assert leftovers(res) == ["a.sp3"]  # the stale .part is useless once the product is there
    tree = tmp_path / "tree"  # a copy of the archive layout, compressed as published
    copy_into(sp3_gz, tree / "cddis", SP3_PATH)
    report = fetch_product(cat, "cod_orbit", GRACE_A_DAY, tmp_path / "b.sp3",
                           mirrors=[tmp_path / "empty", tree], offline=True, **FAST)
    assert report.origin == str(tree / "cddis" / SP3_PATH)
    assert report.attempts[0][1].startswith("no copy in the mirror")
    assert report.dest.read_bytes() == plain(sp3_gz)
    with pytest.raises(DownloadError, match=r"not tried \(offline\)") as info:
        fetch_product(cat, "cod_orbit", GRACE_A_DAY, tmp_path / "c.sp3",
                      mirrors=[tmp_path / "empty"], offline=True, **FAST)
    assert "COD14193.EPH.Z, cod14193.sp3.gz" in str(info.value)


@pytest.mark.shared
def test_existing_valid_destination_is_used_without_network(http_archive, sp3_gz, tmp_path):
    copy_into(sp3_gz, http_archive.root, SP3_PATH)
    dest = tmp_path / "o.sp3"
    dest.write_bytes(plain(sp3_gz))
    cat = catalogue({"ac": http_archive.url}, [{"archive": "ac", "path": SP3_PATH}])
    report = fetch_product(cat, "cod_orbit", GRACE_A_DAY, dest, **FAST)
    assert http_archive.requests == []
    assert report.origin == str(dest) and not report.used_network
    assert report.attempts == [(str(dest), "present and valid")]


@pytest.mark.shared
def test_existing_invalid_destination_is_replaced_or_moved_aside(http_archive, sp3_gz, tmp_path):
    copy_into(sp3_gz, http_archive.root, SP3_PATH)
    dest = tmp_path / "o.sp3"
    dest.write_bytes(HTML_PAGE)
    cat = catalogue({"ac": http_archive.url}, [{"archive": "ac", "path": SP3_PATH}])
    report = fetch_product(cat, "cod_orbit", GRACE_A_DAY, dest, **FAST)
    assert report.attempts[0][1].startswith("present but not usable")
    assert dest.read_bytes() == plain(sp3_gz)
    # for a day the file does not cover and no source has: moved aside, never left in place
    with pytest.raises(DownloadError, match="moved aside to o.sp3.invalid"):
        fetch_product(cat, "cod_orbit", "2007-081", dest, **FAST)
    assert not dest.exists() and (tmp_path / "o.sp3.invalid").exists()


@pytest.mark.shared
def test_flat_mirror_with_other_compression(shared_data, tmp_path):
    """A flat folder holding cod14193.sp3.gz serves the CDDIS short name cod14193.sp3.Z of the
    default catalogue (same product, other compression)."""
    cat = Catalogue.from_yaml(REPO / "config/catalogue.yaml")
    mirror = shared_data / "grace-a_2007-080"
    report = fetch_product(cat, "cod_orbit", GRACE_A_DAY, tmp_path / "cod.sp3", mirrors=[mirror],
                           offline=True)
    assert report.origin == str(mirror / "cod14193.sp3.gz") and not report.used_network
    assert report.dest.read_bytes() == plain(mirror / "cod14193.sp3.gz")


@pytest.mark.shared
@pytest.mark.parametrize("family, date", [
    ("cod_orbit", "2010-208"), ("cod_clock", GRACE_A_DAY), ("cod_osb", "2023-189"),
    ("cod_erp", WHU_DAY), ("cod_p1c1_dcb", WHU_DAY), ("antex_igs05_1402", None),
    ("eop_finals2000a", WHU_DAY), ("slrf2020", None), ("slr_eccentricities", None),
])
def test_default_catalogue_shared_sources_offline(shared_data, tmp_path, family, date):
    """The 'shared' templates of the default catalogue name files that exist and pass."""
    cat = Catalogue.from_yaml(REPO / "config/catalogue.yaml").with_archive_urls(
        {"shared": str(shared_data)})
    report = fetch_product(cat, family, date, tmp_path / "out", offline=True)
    assert report.origin.startswith(str(shared_data)) and not report.used_network


@pytest.mark.shared
def test_local_archive_of_the_default_catalogue_offline(shared_data, tmp_path):
    """The default catalogue's 'shared' archive (a plain directory) works offline."""
    cat = Catalogue.from_yaml(REPO / "config/catalogue.yaml").with_archive_urls(
        {"shared": str(shared_data)})
    report = fetch_product(cat, "grace_a_obs", "2007-03-21", tmp_path / "graa.rnx", offline=True)
    assert not report.used_network and report.origin.endswith("graa0800.07o.gz")
    assert report.dest.read_bytes() == plain(shared_data / "grace-a_2007-080/graa0800.07o.gz")
    assert report.date == GRACE_A_DAY


@pytest.mark.shared
def test_file_url_archive_with_checksum_list(sp3_gz, tmp_path):
    """A file:// archive (a mounted mirror) is read in place, its checksum list honoured."""
    root = tmp_path / "mirror"
    copy_into(sp3_gz, root, SP3_PATH)
    (root / "1419" / "MD5SUMS").write_bytes(_sums({"cod14193.sp3.gz": sp3_gz.read_bytes()},
                                                  "md5"))
    cat = catalogue({"local": root.as_uri()}, [{"archive": "local", "path": SP3_PATH,
                                                "checksums": "{gpsweek}/MD5SUMS"}])
    report = fetch_product(cat, "cod_orbit", GRACE_A_DAY, tmp_path / "res" / "o.sp3",
                           offline=True)
    assert report.origin == f"{root.as_uri()}/{SP3_PATH}" and not report.used_network
    assert report.dest.read_bytes() == plain(sp3_gz)
    assert (root / SP3_PATH).is_file()  # the source is left in place
    assert leftovers(tmp_path / "res") == ["o.sp3"]


def test_network_guard_blocks_non_loopback(no_external_network):
    with pytest.raises(OSError):
        socket.create_connection(("192.0.2.1", 80), timeout=0.1)  # TEST-NET-1 (RFC 5737)
    with pytest.raises(socket.gaierror):
        socket.getaddrinfo("cddis.nasa.gov", 443)
    assert len(no_external_network) == 2
    no_external_network.clear()  # the violations were provoked on purpose
