"""Catalogue: validation on load, template expansion, and the default config/catalogue.yaml."""

from __future__ import annotations

import copy
from pathlib import Path
from urllib.parse import urlsplit

import pytest

from leopod.download import Catalogue
from leopod.download.catalogue import PLACEHOLDERS

REPO = Path(__file__).resolve().parents[2]

MINIMAL = {
    "archives": {
        "code": {"url": "http://example.invalid/CODE"},
        "cddis": {"url": "https://example.invalid/gnss/products", "auth": "netrc"},
    },
    "families": {
        "cod_orbit": {
            "description": "CODE final orbits",
            "kind": "sp3", "period": "day", "suffix": ".sp3",
            "sources": [
                {"archive": "code", "path": "{yyyy}/COD{gpsweek}{dow}.EPH.Z"},
                {"archive": "cddis", "path": "{gpsweek}/cod{gpsweek}{dow}.sp3.Z",
                 "checksums": "{gpsweek}/SHA512SUMS"},
            ],
        },
        "atx": {
            "description": "antennas", "kind": "antex", "period": "static", "suffix": ".atx",
            "sources": [{"archive": "code", "path": "igs20.atx"}],
        },
    },
}


def test_default_catalogue_loads_and_every_template_expands():
    """config/catalogue.yaml is valid; every source of every family expands to a full URL."""
    cat = Catalogue.from_yaml(REPO / "config" / "catalogue.yaml")
    assert len(cat.families) >= 20
    kinds = {fam.kind for fam in cat.families.values()}
    # the brief's minimum: orbits, clocks, biases, ANTEX, EOP, space weather, gravity, SLR
    assert {"sp3", "clock", "bias_sinex", "wl_bias", "antex", "eop", "erp", "space_weather",
            "icgem", "crd", "sinex", "sinex_ecc"} <= kinds
    for date in ("2008-279", "2023-189", "2024-366"):
        for name, fam in cat.families.items():
            locations = cat.locations(name, date)
            assert len(locations) == len(fam.sources)
            for loc in locations:
                assert "{" not in loc.url and "}" not in loc.url, (name, loc.url)
                assert loc.url.startswith(loc.archive.url.rstrip("/")), (name, loc.url)
                scheme = urlsplit(loc.url).scheme
                assert scheme in ("http", "https", "ftp", "") or loc.archive.is_local
                if loc.checksums_url:
                    assert "{" not in loc.checksums_url


def test_default_catalogue_expands_real_names():
    """Real IGS names for 2007-080 (GPS week 1419, day 3: ../shared/data/MANIFEST.md) and
    2023-189 (the CODE OSB file name of products_2023-189_cod_osb)."""
    cat = Catalogue.from_yaml(REPO / "config" / "catalogue.yaml")
    urls = [loc.url for loc in cat.locations("cod_orbit", "2007-080")]
    assert "https://cddis.nasa.gov/archive/gnss/products/1419/cod14193.sp3.Z" in urls
    assert "http://ftp.aiub.unibe.ch/CODE/2007/COD14193.EPH.Z" in urls
    names = [loc.name for loc in cat.locations("cod_osb", "2023-07-08")]
    assert "COD0OPSFIN_20231890000_01D_01D_OSB.BIA.gz" in names
    whu = [loc.url for loc in cat.locations("whu_abs_bias", "2008-279")]
    assert whu[0] == ("ftp://igs.gnsswhu.cn/pub/whu/phasebias/2008/bias/"
                      "WHU0IGSFIN_20082790000_01D_01D_ABS.BIA.Z")


def test_expansion_and_checksum_url():
    cat = Catalogue.from_config(MINIMAL)
    first, second = cat.locations("cod_orbit", "2007-080")
    assert first.url == "http://example.invalid/CODE/2007/COD14193.EPH.Z"
    assert first.checksums_url is None
    assert second.url == "https://example.invalid/gnss/products/1419/cod14193.sp3.Z"
    assert second.checksums_url == "https://example.invalid/gnss/products/1419/SHA512SUMS"
    assert second.archive.auth == "netrc"
    assert [loc.url for loc in cat.locations("atx", None)] == ["http://example.invalid/CODE/igs20.atx"]


def test_placeholders_are_those_of_leopod_time():
    assert set(PLACEHOLDERS) == {"yyyy", "yy", "doy", "gpsweek", "dow", "date", "month", "day"}


def _broken(edit):
    mapping = copy.deepcopy(MINIMAL)
    edit(mapping)
    return mapping


@pytest.mark.parametrize("edit, message", [
    (lambda m: m["families"]["cod_orbit"]["sources"][0].update(path="{yyyy}/COD{week}.EPH.Z"),
     r"family 'cod_orbit' source 1 'path'.*'\{yyyy\}/COD\{week\}.EPH.Z'.*unknown placeholder"),
    (lambda m: m["families"]["cod_orbit"]["sources"][1].update(archive="kasi"),
     r"family 'cod_orbit' source 2: unknown archive 'kasi'"),
    (lambda m: m["families"]["cod_orbit"].update(kind="orbit"),
     r"family 'cod_orbit': unknown kind 'orbit'"),
    (lambda m: m["families"]["cod_orbit"].pop("suffix"),
     r"family 'cod_orbit': missing key\(s\) \['suffix'\]"),
    (lambda m: m["families"]["cod_orbit"].update(period="week"),
     r"family 'cod_orbit': period must be one of"),
    (lambda m: m["families"]["atx"]["sources"][0].update(path="igs{gpsweek}.atx"),
     r"family 'atx' source 1 'path'.*static family must not contain"),
    (lambda m: m["families"]["cod_orbit"]["sources"][0].update(path="{doy:03d}/x"),
     r"only plain placeholders"),
    (lambda m: m["families"]["cod_orbit"]["sources"][0].update(path="../{yyyy}/x"),
     r"relative path inside the archive"),
    (lambda m: m["families"]["cod_orbit"]["sources"][0].update(md5="abc"),
     r"source 1: unknown key\(s\) \['md5'\]"),
    (lambda m: m["families"]["atx"]["sources"][0].update(sha256="1234"),
     r"'sha256' must be 64 hexadecimal"),
    (lambda m: m["families"]["cod_orbit"]["sources"][1].update(checksums="{gps_week}/MD5SUMS"),
     r"source 2 'checksums'.*unknown placeholder"),
    (lambda m: m["archives"]["code"].update(url="sftp://example.invalid/CODE"),
     r"archive 'code': unsupported URL scheme 'sftp'"),
    (lambda m: m["archives"]["code"].update(auth="token"),
     r"archive 'code': 'auth' must be 'netrc'"),
    (lambda m: m["families"]["cod_orbit"].update(sources=[]),
     r"'sources' must be a non-empty list"),
])
def test_invalid_catalogue_names_family_and_key(edit, message):
    with pytest.raises(ValueError, match=message):
        Catalogue.from_config(_broken(edit))


def test_daily_family_needs_a_date_and_unknown_family_is_named():
    cat = Catalogue.from_config(MINIMAL)
    with pytest.raises(ValueError, match="daily: a date"):
        cat.locations("cod_orbit", None)
    with pytest.raises(ValueError, match="unknown product family 'grg_orbit'.*atx, cod_orbit"):
        cat.locations("grg_orbit", "2007-080")


def test_with_archive_urls_redirects_and_keeps_auth():
    cat = Catalogue.from_config(MINIMAL).with_archive_urls({"cddis": "ftp://127.0.0.1:2121/pub"})
    loc = cat.locations("cod_orbit", "2007-080")[1]
    assert loc.url == "ftp://127.0.0.1:2121/pub/1419/cod14193.sp3.Z"
    assert loc.archive.auth == "netrc"
    with pytest.raises(ValueError, match="unknown archive 'esa'"):
        cat.with_archive_urls({"esa": "http://127.0.0.1/"})


def test_yaml_error_names_the_file(tmp_path):
    path = tmp_path / "catalogue.yaml"
    path.write_text("archives: {}\nfamilies: {x: {description: d}}\n")
    with pytest.raises(ValueError, match=r"catalogue.yaml: catalogue family 'x': missing key"):
        Catalogue.from_yaml(path)
