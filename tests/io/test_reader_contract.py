"""Regression tests of the failures named in issue 24, on the fuzzer's real seed files.

Authority: issue 24 (the list of crashes, hangs, bare errors and silent wrong numbers found by
mutating real files) and the reader contract of :mod:`leopod.io._fields`; each case edits one
field of a small valid file built from ../shared/data (``tests/io/_fuzz.py``; skipped when the
data is absent) and expects a :class:`leopod.io.FormatError` naming the file and the line.
"""

from __future__ import annotations

import gzip
import zlib

import _fuzz
import pytest

from leopod.io import FormatError


@pytest.fixture(scope="module")
def seeds(shared_data, tmp_path_factory):
    return _fuzz.build_seeds(shared_data, tmp_path_factory.mktemp("seeds"))


def _lines(seed) -> list[str]:
    return seed.text.decode("latin-1").split("\n")


def _refused(seed, tmp_path, text: str | bytes, line: int | None = None) -> FormatError:
    path = tmp_path / seed.filename
    path.write_bytes(text if isinstance(text, bytes) else text.encode("latin-1"))
    with pytest.raises(FormatError) as err:
        seed.read(path)
    assert seed.filename in str(err.value)
    if line is not None:
        assert err.value.line == line, err.value
    return err.value


def _edit(seed, k: int, start: int, stop: int, new: str) -> str:
    """The seed with line k (0-based) columns [start, stop) replaced by ``new`` (right-justified
    to the field width when shorter)."""
    lines = _lines(seed)
    lines[k] = lines[k][:start] + new.rjust(stop - start) + lines[k][stop:]
    return "\n".join(lines)


def _first(seed, prefix: str) -> int:
    return next(k for k, line in enumerate(_lines(seed)) if line.startswith(prefix))


# ---------------------------------------------------------------- compression (every reader)
@pytest.mark.shared
@pytest.mark.parametrize("reader", list(_fuzz._readers()))
def test_damaged_and_empty_gzip_are_format_errors(seeds, reader, tmp_path):
    # issue 24: zlib.error escaped io._text._decompress; an empty payload gave IndexError
    seed = seeds[reader]
    z = bytearray(gzip.compress(seed.text, mtime=0))
    z[len(z) // 2] ^= 0xFF
    err = _refused(seed, tmp_path, bytes(z))
    assert err.field == "gzip"
    assert _refused(seed, tmp_path, gzip.compress(b"", mtime=0)).field == "file"
    raw = zlib.compress(seed.text)  # a zlib stream is not a format we read: text check
    _refused(seed, tmp_path, raw[:2] + b"\x00" + raw[3:])


# ------------------------------------------------------------------------- dates and ranges
@pytest.mark.shared
@pytest.mark.parametrize(("reader", "prefix", "start", "stop", "new"), [
    ("sp3", "*  ", 3, 7, "3000"),                    # sp3._check_epochs OverflowError
    ("clock", "AR ", 8, 12, "1677"),                 # clock._epochs OverflowError
    ("bias_sinex", " OSB", 35, 39, "0000"),          # year 0 wrapped to 1754
    ("antex", "  2008    10    16", 0, 6, "  3000"),  # VALID UNTIL 3000 wrapped to 1831
    ("wlbias", "WL ", 8, 12, "9999"),
    ("rinex_obs_v3", "> ", 2, 6, "2500"),
    ("crd_np", "H4", 6, 10, "1234"),
    ("grace_orbit_csv", "27/7/2010,00:00:10", 5, 9, "20100"),
    ("manoeuvre", "2007-", 0, 4, "2263"),
    ("attitude_csv", "2003-", 0, 4, "3000"),         # numpy wrapped it to 1830-11-23
])
def test_years_outside_the_contract_are_refused(seeds, tmp_path, reader, prefix, start, stop,
                                                new):
    seed = seeds[reader]
    k = _first(seed, prefix)
    err = _refused(seed, tmp_path, _edit(seed, k, start, stop, new), k + 1)
    assert "outside" in err.message or "invalid" in err.message


@pytest.mark.shared
@pytest.mark.parametrize(("reader", "prefix", "start", "stop", "new"), [
    ("sp3", "PG01", 4, 18, "1e308"),                 # became inf after km -> m
    ("grace_orbit_csv", "27/7/2010,00:00:10", 19, 30, "1e308"),
    ("crd_np", "11 ", 3, 18, "1e308"),
    ("crd_fr", "10 ", 50, 51, "99999999999"),        # crd.per_session int8 overflow
    ("sp3", "PG01", 4, 18, "1_000"),                 # underscores: Python's float accepts
    ("dcb", "G01", 22, 35, "1_0"),
    ("blq", "  .0", 0, 7, "1e20"),
    ("icgem", "gfc    2    0", 19, 38, "0.1e+21"),
    ("space_weather", "2007-03-13", 16, 18, "1e9"),
    ("fes", " 55.565", 16, 19, "40000"),             # asked for 858 GiB
    ("fes", " 55.565", 16, 19, "9999999999"),        # bare ValueError without the file
    ("icgem", "gfc    2    0", 11, 13, "99999999999999999999"),  # icgem._ints OverflowError
    ("attitude_sca1b", "116769605", 12, 13, "99999"),  # sca_id overflowed int16
    ("attitude_sca1b", "116769605", 14, 32, "1e308"),
])
def test_values_outside_their_physical_range_are_refused(seeds, tmp_path, reader, prefix,
                                                         start, stop, new):
    seed = seeds[reader]
    k = _first(seed, prefix)
    _refused(seed, tmp_path, _edit(seed, k, start, stop, new), k + 1)


@pytest.mark.shared
def test_sp3_negative_satellite_count_and_antex_tiny_dzen(seeds, tmp_path):
    # issue 24: np.zeros(-43) and np.arange(1e101) raised bare errors without the file
    sp3 = seeds["sp3"]
    _refused(sp3, tmp_path, _edit(sp3, 2, 3, 6, "-43"), 3)
    atx = seeds["antex"]
    k = _first(atx, "     0.0  17.0   1.0")
    _refused(atx, tmp_path, _edit(atx, k, 14, 20, "1E-99"), k + 1)


@pytest.mark.shared
@pytest.mark.parametrize("reader", ["rinex_obs_v2", "rinex_obs_v3"])
def test_rinex_negative_satellite_count_does_not_hang(seeds, tmp_path, reader):
    # issue 24: _skip_event / _scan_v3 did not advance on a count of -1
    seed = seeds[reader]
    k = _first(seed, " 07  3 21" if reader.endswith("v2") else "> ")
    cols = (29, 32) if reader.endswith("v2") else (32, 35)
    _refused(seed, tmp_path, _edit(seed, k, *cols, "-1"), k + 1)


@pytest.mark.shared
def test_icgem_record_above_max_degree_is_an_error(seeds, tmp_path):
    # issue 24: a record above max_degree was dropped although the docstring promises an error
    seed = seeds["icgem"]
    text = seed.text.decode() + "gfc    5    0  0.1e-06  0.0e+00 0.1e-10 0.1e-10\n"
    err = _refused(seed, tmp_path, text, len(_lines(seed)))
    assert err.field == "L"


@pytest.mark.shared
def test_blank_space_weather_date_is_refused(seeds, tmp_path):
    # issue 24: a blank date became NaT
    seed = seeds["space_weather"]
    _refused(seed, tmp_path, _edit(seed, 2, 0, 10, ""), 3)


@pytest.mark.shared
def test_bias_sinex_record_with_shifted_columns_is_refused(seeds, tmp_path):
    # issue 24: a record shifted by one column was read with a wrong value
    seed = seeds["bias_sinex"]
    k = _first(seed, " OSB")
    lines = _lines(seed)
    lines[k] = " " + lines[k]
    _refused(seed, tmp_path, "\n".join(lines), k + 1)


# -------------------------------------------------------------------- a file cut short
@pytest.mark.shared
@pytest.mark.parametrize("reader", ["rinex_obs_v2", "rinex_obs_v3", "wlbias", "dcb", "blq",
                                    "space_weather", "grace_orbit_csv", "kband_range_csv",
                                    "fes", "crd_np", "icgem", "manoeuvre", "clock", "sp3",
                                    "bias_sinex", "sinex_stations", "antex"])
def test_file_cut_inside_its_last_number_is_refused(seeds, tmp_path, reader):
    """issue 24: a file cut inside its last number parsed with a wrong value (RINEX 2/3, WL
    biases - the exponent lost -, DCB, BLQ, space weather, CSVs, FES, CRD)."""
    seed = seeds[reader]
    text = seed.text.decode("latin-1").rstrip("\n ")
    last_digit = max(k for k, c in enumerate(text) if c.isdigit())
    if reader.startswith("rinex"):  # the last characters are the LLI and SSI digits
        last_digit -= 2
    _refused(seed, tmp_path, text[:last_digit])  # one digit (or the exponent's) removed


@pytest.mark.shared
def test_sp3_cut_before_the_clock_column_without_eof_is_refused(seeds, tmp_path):
    # issue 24: "an SP3 cut before its clock column with no EOF line is accepted"
    seed = seeds["sp3"]
    lines = _lines(seed)
    last = max(k for k, line in enumerate(lines) if line.startswith("P"))
    text = "\n".join(lines[:last] + [lines[last][:46]])
    err = _refused(seed, tmp_path, text + "\n", last + 1)
    assert err.field == "EOF"


@pytest.mark.shared
@pytest.mark.parametrize(("reader", "prefix", "start", "stop", "new"), [
    ("sp3", "PG01", 2, 4, "0\u00b2"),        # "²".isdigit() is True: int() raised ValueError
    ("rinex_obs_v3", "G01", 1, 3, "\u00b2\u00b9"),
    ("crd_np", "H3", 15, 22, "760390\u00b9"),
])
def test_non_ascii_digits_are_refused(seeds, tmp_path, reader, prefix, start, stop, new):
    # the 10 000-case fuzz run found int('2²') escaping from the SP3 satellite identifier
    seed = seeds[reader]
    k = next(j for j, line in enumerate(_lines(seed)) if line.startswith(prefix)
             and j > 10)
    _refused(seed, tmp_path, _edit(seed, k, start, stop, new), k + 1)


def test_only_cr_and_lf_end_lines(tmp_path):
    # str.splitlines also breaks at form feed and NEL (\x85, a Latin-1 byte): line numbers
    # must stay those of an editor
    from leopod.io._text import read_lines

    path = tmp_path / "f.txt"
    path.write_bytes(b"a\x0cb\x85c\r\nd\re")
    lines = read_lines(path)
    assert list(lines) == ["a\x0cb\x85c", "d", "e"] and not lines.final_newline


def test_damaged_attitude_netcdf_is_a_format_error(tmp_path):
    from leopod.io.attitude import read_attitude_netcdf

    path = tmp_path / "attitude.nc"
    path.write_bytes(b"CDF\x01" + bytes(range(256)) * 4)
    with pytest.raises(FormatError) as err:
        read_attitude_netcdf(path)
    assert err.value.field == "netCDF" and "attitude.nc" in str(err.value)
