"""Checks of arrived files and decompression by name, on the real files of ../shared/data."""

from __future__ import annotations

import gzip
import hashlib
from pathlib import Path

import pytest
from _download_samples import (
    COD_CLK_GZ,
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

from leopod.download import CheckError, DecompressError, check_file, decompress_file
from leopod.download.checksums import ChecksumError, file_digest, listed_digest
from leopod.download.decompress import decompressed_name, layers
from leopod.io.rinex_obs import read_rinex_obs

# ------------------------------------------------------------------------------ decompression


@pytest.mark.parametrize("name, expected_layers, expected_name", [
    ("cod14193.sp3.Z", ["compress"], "cod14193.sp3"),
    ("COD0OPSFIN_20231890000_01D_05M_ORB.SP3.gz", ["gzip"],
     "COD0OPSFIN_20231890000_01D_05M_ORB.SP3"),
    ("GRCB2080.10D", ["hatanaka"], "GRCB2080.10O"),
    ("graa0800.07d.Z", ["compress", "hatanaka"], "graa0800.07o"),
    ("ABMF00GLP_R_20231890000_01D_30S_MO.crx.gz", ["gzip", "hatanaka"],
     "ABMF00GLP_R_20231890000_01D_30S_MO.rnx"),
    ("igs20.atx", [], "igs20.atx"),
    ("SW-All.csv", [], "SW-All.csv"),
])
def test_layers_from_the_name(name, expected_layers, expected_name):
    # IGS/RINEX naming conventions (RINEX 2.11 §4, RINEX 3.04 §4: d = Hatanaka-compressed obs)
    assert layers(name) == expected_layers
    assert decompressed_name(name) == expected_name


@pytest.mark.shared
def test_decompress_gzip_and_compress_match_independent_decoders(shared_data, tmp_path):
    # authority: Python's gzip module and unlzw3, called directly (_download_samples.plain)
    for rel in (COD_SP3_GZ, WHU_CLK_Z):
        src = shared_data / rel
        out = tmp_path / "out"
        decompress_file(src, out, src.name)
        assert out.read_bytes() == plain(src)


@pytest.mark.shared
def test_decompress_hatanaka_full_day(shared_data, tmp_path):
    # authority: MANIFEST.md - GRCB2080.10D is a full day at 10 s (8640 epochs), RINEX 2.20
    out = tmp_path / "GRCB2080.10O"
    assert decompress_file(shared_data / GRACE_B_CRX, out, "GRCB2080.10D") == ["hatanaka"]
    assert out.read_bytes()[:80].split()[0] == b"2.20"
    assert read_rinex_obs(out).sizes["time"] == 8640


@pytest.mark.shared
def test_decompress_rejects_truncated_and_mislabelled(shared_data, tmp_path):
    raw = (shared_data / COD_SP3_GZ).read_bytes()
    cases = {
        "truncated.sp3.gz": (raw[: len(raw) // 2], "truncated gzip"),
        "page.sp3.gz": (HTML_PAGE, "HTML"),
        "page.clk.Z": (HTML_PAGE, "not Unix compress"),
        "GRCB2080.10D": (plain(shared_data / COD_SP3_GZ), "COMPACT RINEX"),
    }
    for name, (content, message) in cases.items():
        src = tmp_path / name
        src.write_bytes(content)
        with pytest.raises(DecompressError, match=message):
            decompress_file(src, tmp_path / "out", name)


# ------------------------------------------------------------------------------ valid files

@pytest.mark.shared
@pytest.mark.parametrize("rel, kind, date", [
    (COD_SP3_GZ, "sp3", GRACE_A_DAY),                # 00:00-23:45, 15 min
    (COD_CLK_GZ, "clock", GRACE_A_DAY),              # 00:00-23:59:30, 30 s
    (WHU_CLK_Z, "clock", WHU_DAY),                   # ends 23:59:00 at 30 s: within one interval
    (WHU_BIA_Z, "bias_sinex", WHU_DAY),
    ("products_2023-189_cod_osb/COD0OPSFIN_20231890000_01D_01D_OSB.BIA", "bias_sinex", "2023-189"),
    ("grace-a_2007-080/graa0800.07o.gz", "rinex_obs", GRACE_A_DAY),
    (GRACE_B_CRX, "rinex_obs", GRACE_B_DAY),
    ("products_2008-279_whu/COD15007.ERP.Z", "erp", WHU_DAY),
    ("eop/finals2000A.all", "eop", WHU_DAY),
    ("antex/igs05_1627.atx", "antex", None),
    ("slr/lageos2_201802.npt.v2C", "crd", "2018-032"),
    ("slr/SLRF2020_POS+VEL_2023.10.02.snx", "sinex", None),
    ("slr/ecc_xyz.snx", "sinex_ecc", None),
    ("products_2008-279_whu/P1C10810_RINEX.DCB.Z", "dcb", None),
    ("format_fixtures/code.bia", "generic", None),
])
def test_real_products_pass(shared_data, rel, kind, date):
    summary = check_file(shared_data / rel, kind, date)
    assert summary


@pytest.mark.shared
def test_models_pass(shared):
    assert "degree 120" in check_file(shared / "models/gravity/EGM2008_120.gfc", "icgem")
    assert "rows" in check_file(shared / "models/space_weather/SW-All.csv", "space_weather",
                                "2023-189")


# ------------------------------------------------------------------------------ failures

def _write(tmp_path: Path, name: str, content: bytes) -> Path:
    path = tmp_path / name
    path.write_bytes(content)
    return path


@pytest.mark.shared
def test_sp3_of_another_day_or_partial_day_fails(shared_data, tmp_path):
    with pytest.raises(CheckError, match=r"cod14193.sp3.gz: the orbit spans 2007-03-21T00:00:00 "
                                         r"to 2007-03-21T23:45:00 and does not cover the day "
                                         r"2007-03-22"):
        check_file(shared_data / COD_SP3_GZ, "sp3", "2007-081")
    partial = _write(tmp_path, "partial.sp3", sp3_first_hours(shared_data, 18))
    with pytest.raises(CheckError, match=r"spans 2007-03-21T00:00:00 to 2007-03-21T17:45:00"):
        check_file(partial, "sp3", GRACE_A_DAY)


@pytest.mark.shared
def test_truncated_sp3_names_file_and_line(shared_data, tmp_path):
    lines = plain(shared_data / COD_SP3_GZ).splitlines(keepends=True)
    cut = _write(tmp_path, "cut.sp3", b"".join(lines[:1000]))
    with pytest.raises(CheckError, match=r"cut.sp3:\d+: field 'number of epochs'"):
        check_file(cut, "sp3", GRACE_A_DAY)


@pytest.mark.shared
def test_bias_with_nan_is_rejected_with_line_and_field(shared_data, tmp_path):
    text, line = bias_with_nan(shared_data)
    path = _write(tmp_path, "WHU.BIA", text)
    with pytest.raises(CheckError, match=rf"WHU.BIA:{line}: field 'ESTIMATED_VALUE': 'nan' is "
                                         "not a finite number"):
        check_file(path, "bias_sinex", WHU_DAY)


@pytest.mark.shared
def test_clock_covering_half_a_day_fails(shared_data, tmp_path):
    text = plain(shared_data / COD_CLK_GZ).decode("latin-1").splitlines(keepends=True)
    kept = [ln for ln in text if not ln.startswith("AS ") or int(ln[19:22]) < 12]
    path = _write(tmp_path, "half.clk", "".join(kept).encode("latin-1"))
    with pytest.raises(CheckError, match=r"half.clk: the clock file spans .* to "
                                         r"2007-03-21T11:59:30 and does not cover"):
        check_file(path, "clock", GRACE_A_DAY)


@pytest.mark.shared
def test_observations_of_another_day_fail(shared_data):
    with pytest.raises(CheckError, match=r"epoch 2010-07-27T00:00:00 is outside the day "
                                         r"2010-07-28"):
        check_file(shared_data / GRACE_B_CRX, "rinex_obs", "2010-209")


@pytest.mark.shared
def test_eop_and_erp_not_reaching_the_day_fail(shared_data):
    with pytest.raises(CheckError, match=r"no finals2000A row .* 2024-01-01 \(MJD 60310\)"):
        check_file(shared_data / "eop/finals2000A.all", "eop", "2024-001")
    with pytest.raises(CheckError, match=r"ERP records span MJD 54743.50 to 54751.50"):
        check_file(shared_data / "products_2008-279_whu/COD15007.ERP.Z", "erp", "2009-001")


def test_html_empty_and_garbage_fail(tmp_path):
    page = _write(tmp_path, "orbit.sp3", HTML_PAGE)
    for kind in ("sp3", "generic", "space_weather"):
        with pytest.raises(CheckError, match=r"orbit.sp3: an HTML/XML page"):
            check_file(page, kind, GRACE_A_DAY)
    empty = _write(tmp_path, "empty.clk", b"")
    with pytest.raises(CheckError, match=r"empty.clk: the file is empty"):
        check_file(empty, "clock", GRACE_A_DAY)
    erp = _write(tmp_path, "bad.erp", b"VERSION 2\n  MJD   X-P  Y-P  UT1UTC\n   E-6\" E-6\" E-7S\n"
                                     b"54743.50   255584   21O979 -4944934\n")
    with pytest.raises(CheckError, match=r"bad.erp:4: field 'Y-P': '21O979' is not a number"):
        check_file(erp, "erp", WHU_DAY)
    with pytest.raises(ValueError, match="unknown product kind 'orbit'"):
        check_file(erp, "orbit")


def test_display_name_replaces_temporary_path(tmp_path):
    path = _write(tmp_path, ".tmp123.part", HTML_PAGE)
    with pytest.raises(CheckError, match=r"^cod14193.sp3.gz \(decompressed\): an HTML"):
        check_file(path, "sp3", GRACE_A_DAY, display="cod14193.sp3.gz (decompressed)")


# ------------------------------------------------------------------------------ checksums

def test_checksum_lists_gnu_and_bsd(tmp_path):
    data = tmp_path / "cod14193.sp3.Z"
    data.write_bytes(b"orbit bytes\n")
    # authority: hashlib (independent computation of the digests written into the lists)
    md5 = hashlib.md5(b"orbit bytes\n").hexdigest()
    sha512 = hashlib.sha512(b"orbit bytes\n").hexdigest()
    gnu = f"{'0' * 32}  other.sp3.Z\n{md5} *./1419/cod14193.sp3.Z\n".encode()
    assert listed_digest(gnu, "cod14193.sp3.Z", "MD5SUMS") == ("md5", md5)
    bsd = f"SHA512 (cod14193.sp3.Z) = {sha512.upper()}\n".encode()
    assert listed_digest(bsd, "1419/cod14193.sp3.Z", "SHA512SUMS") == ("sha512", sha512)
    assert file_digest(data, "sha512") == sha512
    with pytest.raises(ChecksumError, match="SHA512SUMS has no entry for igs14193.sp3.Z"):
        listed_digest(bsd, "igs14193.sp3.Z", "SHA512SUMS")


def test_gzip_member_sha256(tmp_path):
    # the digest of what is delivered is that of the decompressed bytes (hashlib authority)
    src = _write(tmp_path, "x.sp3.gz", gzip.compress(b"abc\n"))
    decompress_file(src, tmp_path / "x.sp3", src.name)
    assert file_digest(tmp_path / "x.sp3") == hashlib.sha256(b"abc\n").hexdigest()
