"""Property-based tests (hypothesis) of the reader contract's field parsers, leopod.io._fields.

Authority: the contract of the module docstring (issue 24 item 2): a field is a number of the
syntax ``[+-]digits[.digits][E|D[+-]digits]``, finite and inside its range, or a FormatError
naming file, line and field; dates are proleptic Gregorian with years 1900-2199, and their
nanoseconds agree with numpy's datetime64[ns].
"""

from __future__ import annotations

import datetime as dt
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from leopod.io import FormatError
from leopod.io._fields import epoch_ns, integer, integers, is_number, number, numbers

PATH = "file.txt"
FAST = settings(max_examples=300, deadline=None)
ANY_TEXT = st.text(alphabet=st.characters(codec="latin-1"), max_size=24)
NUMBERISH = st.text(alphabet="0123456789+-.eEdD _naifNI\t", max_size=16)


@FAST
@given(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e300, max_value=1e300),
       st.sampled_from(["{:.6E}", "{:.12e}", "{:.3f}", "{!r}", "{:.9g}"]))
def test_formatted_finite_numbers_read_back(x, fmt):
    text = fmt.format(x).replace("inf", "")  # repr of huge floats stays finite here
    assert number(f"  {text} ", PATH, 7, "F") == float(text)


@FAST
@given(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e30, max_value=1e30))
def test_fortran_d_exponent_is_an_e_exponent(x):
    text = f"{x:.10E}"
    assert number(text.replace("E", "D"), PATH, 1, "F") == number(text, PATH, 1, "F")


@FAST
@given(ANY_TEXT | NUMBERISH, st.integers(-10**6, 0), st.integers(0, 10**6), st.booleans())
def test_any_text_is_a_value_in_range_or_a_located_error(text, lo, hi, as_integer):
    parse = integer if as_integer else number
    try:
        value = parse(text, PATH, 3, "VALUE", lo=lo, hi=hi)
    except FormatError as err:
        assert (err.path, err.line, err.field) == (PATH, 3, "VALUE")
        return
    assert math.isfinite(value) and lo <= value <= hi
    assert "_" not in text and is_number(text)
    assert value == (int(text) if as_integer else float(text.replace("D", "E")
                                                        .replace("d", "e")))


@FAST
@given(st.integers(1, 10**6), st.integers(0, 999))
def test_underscores_are_refused(whole, frac):
    text = f"{whole:_}.{frac}" if whole >= 1000 else f"{whole}_{frac}"
    with pytest.raises(FormatError, match="not a number"):
        number(text, PATH, 1, "F")
    with pytest.raises(FormatError):
        integer(text.split(".")[0], PATH, 1, "N")


@pytest.mark.parametrize("text", ["nan", "NaN", "inf", "-inf", "+Infinity", "1e999", "-1D400"])
def test_non_finite_is_refused(text):
    with pytest.raises(FormatError, match="finite"):
        number(text, PATH, 1, "F")


@FAST
@given(st.lists(st.floats(-1e3, 1e3, allow_nan=False).map(lambda v: f"{v:.4f}"), max_size=20),
       st.data())
def test_vectorised_parser_agrees_and_locates_the_first_bad_field(texts, data):
    lines = list(range(10, 10 + len(texts)))
    np.testing.assert_array_equal(numbers(texts, lines, "X", PATH, lo=-1e3, hi=1e3),
                                  [number(t, PATH, 1, "X") for t in texts])
    if texts:
        k = data.draw(st.integers(0, len(texts) - 1))
        bad = list(texts)
        bad[k] = data.draw(st.sampled_from(["1_0", "nan", "inf", "1e5", "x", ""]))
        with pytest.raises(FormatError) as err:
            numbers(bad, lines, "X", PATH, lo=-1e3, hi=1e3)
        assert err.value.line == lines[k]


@FAST
@given(st.lists(st.integers(-10**12, 10**12).map(str), max_size=10))
def test_vectorised_integers(texts):
    lines = list(range(len(texts)))
    got = integers(texts, lines, "N", PATH, lo=-10**12, hi=10**12)
    assert got.tolist() == [int(t) for t in texts]


@FAST
@given(st.datetimes(min_value=dt.datetime(1900, 1, 1), max_value=dt.datetime(2199, 12, 31)))
def test_epochs_agree_with_numpy(t):
    sec = t.second + t.microsecond * 1e-6
    ns = epoch_ns(t.year, t.month, t.day, t.hour, t.minute, sec, PATH, 1)
    want = np.datetime64(t.replace(second=0, microsecond=0), "ns").astype(np.int64) \
        + round(sec * 1e9)
    assert ns == want


@FAST
@given(st.integers(-10**10, 10**10), st.integers(-10**10, 10**10), st.integers(-10**10, 10**10),
       st.integers(-99, 99), st.integers(-99, 99), st.floats(-100, 100))
def test_any_epoch_fields_give_an_epoch_in_range_or_a_located_error(y, mo, d, h, mi, s):
    try:
        ns = epoch_ns(y, mo, d, h, mi, s, PATH, 9, "EPOCH")
    except FormatError as err:
        assert err.line == 9
        return
    t = np.datetime64(ns, "ns")
    assert np.datetime64("1900-01-01") <= t < np.datetime64("2200-01-01")
