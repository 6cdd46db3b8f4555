"""Read ICGEM gravity field models (.gfc files).

Specification: F. Barthelmes, C. Foerste, "The ICGEM-format", GFZ Potsdam, version of
2011-06-07 (icgem1.0: static ``gfc`` records and time-variable ``gfct``/``trnd``/``acos``/
``asin`` records with one reference epoch), as published by the International Centre for Global
Earth Models (icgem.gfz-potsdam.de). A time-variable coefficient at epoch t is (t, t0 in years)::

    G(t) = gfct + trnd (t - t0)
           + sum_p [acos_p cos(2 pi (t - t0) / p) + asin_p sin(2 pi (t - t0) / p)]

Piecewise time-variable models (``format icgem2.0``, Ince et al. 2019, with validity
intervals t0..t1 on every ``gfct``/``trnd``/``acos``/``asin`` record, e.g. EIGEN-6S4) have no
single reference epoch, so the one-``t0`` schema below cannot hold them: ``read_icgem(path,
epoch=...)`` evaluates them at an epoch and returns that static field (``attrs["epoch"]``,
``attrs["evaluated_terms"]``); without ``epoch`` such a file is refused with a FormatError
naming its first piecewise record. A file of format icgem2.0 with ``gfc`` records only is read
as any static model. Bodies
other than the Earth write ``gravity_constant`` instead of ``earth_gravity_constant`` (e.g.
the lunar GrazLGM300c); both are read into ``gm_m3_s2``.

Dataset returned by :func:`read_icgem`
--------------------------------------
Coordinates
    ``n`` (n,) int -- degree 0..N;  ``m`` (m,) int -- order 0..N
    ``period`` (period,) float [year] -- periods of the ``acos``/``asin`` terms, descending
    (only for time-variable models)
Data variables, fully normalised (converted when the file says ``norm unnormalized``)
    ``C``, ``S`` (n, m) float64 [1] -- coefficients (for ``gfct`` records: the value at t0);
    0 where the file gives none (including m > n, and degree 1 when omitted)
    ``sigma_C``, ``sigma_S`` (n, m) float64 [1] -- standard deviations as given by the file
    (calibrated or formal, see ``attrs["errors"]``); NaN where not given; only when the
    records carry them
    ``trnd_C``, ``trnd_S`` (n, m) float64 [year-1] -- secular rates (``trnd`` or ``dot``)
    ``acos_C``, ``acos_S``, ``asin_C``, ``asin_S`` (period, n, m) float64 [1] -- amplitudes of
    the periodic terms; the time-variable variables are 0 where the file gives no term and
    exist only for time-variable models (their standard deviations are not returned)
Attributes
    ``modelname``, ``product_type``, ``gm_m3_s2`` (earth_gravity_constant), ``radius_m``,
    ``max_degree`` (of the returned arrays), ``max_degree_file``, ``errors``, ``norm``
    (always "fully_normalized"), ``norm_in_file``, ``tide_system`` (spaces replaced by "_",
    "unknown" when absent), ``format`` ("icgem1.0" when absent), ``time_variable_terms``
    (e.g. "gfct trnd acos asin", "" for a static model), ``t0`` (reference epoch, ISO date,
    only for time-variable models), ``filename``.

Errors
------
:class:`leopod.io.FormatError` (file, line, field) for a missing ``end_of_head`` or mandatory
keyword (product_type, modelname, earth_gravity_constant, radius, max_degree), an unknown
record key, a record with the wrong number of fields (e.g. truncated), a non-numeric or
non-finite value, a degree/order outside 0 <= m <= n <= max_degree, a coefficient given twice,
records of one key with different numbers of fields, time-variable records with different
reference epochs, a file whose declared maximum degree lacks some orders (truncated), and a
file whose last line has no line end (cut inside its last record: in this free format the
cut number could not be told from a shorter one). Values follow the reader contract of
:mod:`leopod.io._fields`: coefficients within +-10, standard deviations 0..10, degrees and
orders 0..10800, GM and radius in physical ranges.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from scipy.special import gammaln

from leopod.io._fields import epoch_ns, integers, is_digits, require_line_end
from leopod.io._text import (
    FormatError,
    parse_float,
    parse_floats,
    parse_int,
    read_lines,
)

__all__ = ["read_icgem"]

_MANDATORY = ("product_type", "modelname", "earth_gravity_constant", "radius", "max_degree")
_KEYWORDS = _MANDATORY + ("errors", "norm", "tide_system", "format", "gravity_constant")
# number of blank-separated fields of each record key (icgem1.0): without / with sigmas
_N_FIELDS = {"gfc": (5, 7), "gfct": (8,), "trnd": (5, 7), "dot": (5, 7), "acos": (8,),
             "asin": (8,)}
_TIME_VARIABLE = ("gfct", "trnd", "dot", "acos", "asin")
# icgem2.0 (Ince et al. 2019): every time-variable record ends with its interval t0 t1
# (yyyymmdd.hhmm), acos/asin then with the period [year]
_N_FIELDS_2 = {"gfct": (7, 9), "trnd": (7, 9), "dot": (7, 9), "acos": (8, 10),
               "asin": (8, 10)}
_YEAR_NS = 365.25 * 86_400e9
#: Largest degree a header may declare (Earth2014 reaches 10800); arrays are sized by it.
_MAX_DEGREE = 10_800


def _ints(texts: list[str], line_nos: list[int], field: str, path: Path) -> np.ndarray:
    """Degree/order texts -> int64 in 0.._MAX_DEGREE, with exact error locations."""
    return integers(texts, line_nos, field, path, lo=0, hi=_MAX_DEGREE)


def _parse_header(lines: list[str], path: Path) -> tuple[dict, int]:
    """Header keywords and the index of the first line after ``end_of_head``."""
    keys: dict[str, tuple[str, int]] = {}
    for i, text in enumerate(lines):
        if text.startswith("end_of_head"):
            break
        parts = text.split(None, 1)
        if parts and parts[0] in _KEYWORDS and parts[0] not in keys:
            keys[parts[0]] = (parts[1].strip() if len(parts) > 1 else "", i + 1)
    else:
        raise FormatError(path, None, "end_of_head", "the header end ('end_of_head') is missing")
    if "earth_gravity_constant" not in keys and "gravity_constant" in keys:
        keys["earth_gravity_constant"] = keys["gravity_constant"]  # another body's GM
    for key in _MANDATORY:
        if key not in keys or not keys[key][0]:
            raise FormatError(path, None, key, "the mandatory header keyword is missing")
    product, line_no = keys["product_type"]
    if product != "gravity_field":
        raise FormatError(path, line_no, "product_type", f"'{product}' is not 'gravity_field'")
    norm, norm_line = keys.get("norm", ("fully_normalized", None))
    if norm not in ("fully_normalized", "unnormalized"):
        raise FormatError(path, norm_line, "norm", f"'{norm}' is neither 'fully_normalized' "
                          "nor 'unnormalized'")
    attrs = {
        "modelname": keys["modelname"][0],
        "product_type": product,
        "gm_m3_s2": parse_float(keys["earth_gravity_constant"][0], path,
                                keys["earth_gravity_constant"][1], "earth_gravity_constant",
                                kind="gm_m3_s2"),
        "radius_m": parse_float(keys["radius"][0], path, keys["radius"][1], "radius",
                                kind="radius_m"),
        "max_degree_file": parse_int(keys["max_degree"][0], path, keys["max_degree"][1],
                                     "max_degree", lo=0, hi=_MAX_DEGREE),
        "errors": keys.get("errors", ("no", 0))[0] or "no",
        "norm": "fully_normalized",
        "norm_in_file": norm,
        "tide_system": "_".join(keys.get("tide_system", ("unknown", 0))[0].split()) or "unknown",
        "format": keys.get("format", ("icgem1.0", 0))[0] or "icgem1.0",
    }
    if attrs["max_degree_file"] < 0:
        raise FormatError(path, keys["max_degree"][1], "max_degree", "must not be negative")
    return attrs, i + 1


def _collect(lines: list[str], first: int, max_degree: int, n_file: int, file_format: str,
             path: Path, piecewise_ok: bool = False
             ) -> tuple[dict[str, list[list[str]]], dict[str, list[int]]]:
    """Split the data lines by record key, keeping only degrees <= max_degree.

    Checks that all records of one key have the same number of fields and that the static
    records of the declared maximum degree ``n_file`` cover every order 0..n_file (a file cut
    short loses them). Returns the token lists and 1-based line numbers per key.
    """
    tokens: dict[str, list[list[str]]] = {k: [] for k in _N_FIELDS}
    line_nos: dict[str, list[int]] = {k: [] for k in _N_FIELDS}
    n_fields: dict[str, int] = {}
    top_orders: set[str] = set()
    for i in range(first, len(lines)):
        parts = lines[i].split()
        if not parts:
            continue
        key = parts[0]
        allowed = _N_FIELDS.get(key)
        if allowed is None:
            raise FormatError(path, i + 1, "key", f"unknown record key '{key}' (expected "
                              f"{', '.join(_N_FIELDS)})")
        if key in _TIME_VARIABLE and file_format != "icgem1.0":
            if not piecewise_ok:
                raise FormatError(path, i + 1, key, f"time-variable records of format "
                                  f"'{file_format}' (piecewise intervals t0..t1 per record) "
                                  "need an epoch: read_icgem(path, epoch=...) evaluates them")
            allowed = _N_FIELDS_2[key]
        if len(parts) not in allowed:
            raise FormatError(path, i + 1, key, f"{len(parts)} fields, expected "
                              f"{' or '.join(map(str, allowed))} (truncated record?)")
        expected = n_fields.setdefault(key, len(parts))
        if len(parts) != expected:
            raise FormatError(path, i + 1, key, f"{len(parts)} fields, expected {expected} as "
                              f"in the first {key} record (truncated record?)")
        n = parse_int(parts[1], path, i + 1, "L", lo=0, hi=n_file)
        if n == n_file and key in ("gfc", "gfct"):
            top_orders.add(parts[2])
        if n <= max_degree:
            tokens[key].append(parts)
            line_nos[key].append(i + 1)
    if len(top_orders) < n_file + 1:
        raise FormatError(path, len(lines), "L", f"the declared max_degree {n_file} has "
                          f"{len(top_orders)} of its {n_file + 1} orders: truncated file?")
    return tokens, line_nos


def _degree_order(rows: list[list[str]], nums: list[int], n_file: int, path: Path
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Degree and order columns, checking 0 <= m <= n <= n_file."""
    n = _ints([r[1] for r in rows], nums, "L", path)
    m = _ints([r[2] for r in rows], nums, "M", path)
    bad = np.nonzero((m < 0) | (m > n) | (n > n_file))[0]
    if bad.size:
        k = bad[0]
        raise FormatError(path, nums[k], "M" if n[k] <= n_file else "L", f"degree {n[k]} "
                          f"order {m[k]} is outside 0 <= M <= L <= {n_file}")
    return n, m


def _check_unique(n: np.ndarray, m: np.ndarray, nums: list[int], what: str, path: Path,
                  extra: np.ndarray | None = None) -> None:
    """Reject a (degree, order[, period]) given twice."""
    key = n * (n.max(initial=0) + 1) + m
    if extra is not None:
        key = key * (len(np.unique(extra)) + 1) + np.unique(extra, return_inverse=True)[1]
    order = np.argsort(key, kind="stable")
    dup = np.nonzero(np.diff(key[order]) == 0)[0]
    if dup.size:
        k = order[dup[0] + 1]
        raise FormatError(path, nums[k], what, f"degree {n[k]} order {m[k]} is given twice")


def _unnormalized_to_normalized(n_max: int) -> np.ndarray:
    """Factor f (n, m) with C_normalised = C_unnormalised * f (Heiskanen & Moritz 1967)."""
    n = np.arange(n_max + 1)[:, None]
    m = np.arange(n_max + 1)[None, :]
    valid = m <= n
    nn, mm = np.where(valid, n, 0), np.where(valid, m, 0)
    log_ratio = gammaln(nn + mm + 1.0) - gammaln(nn - mm + 1.0)
    norm_sq = np.where(mm == 0, 1.0, 2.0) * (2 * nn + 1)
    return np.where(valid, np.exp(0.5 * log_ratio) / np.sqrt(norm_sq), 0.0)


def _reference_epoch(rows: list[list[str]], nums: list[int], path: Path) -> str:
    """The common t0 (yyyymmdd[.0...]) of the gfct records as an ISO date."""
    first = rows[0][7]
    for row, line_no in zip(rows, nums):
        if row[7] != first:
            raise FormatError(path, line_no, "t0", f"reference epoch {row[7]} differs from "
                              f"{first}: one common t0 is supported")
    date, _, frac = first.partition(".")
    if len(date) != 8 or not is_digits(date) or (frac and not set(frac) <= {"0"}):
        raise FormatError(path, nums[0], "t0", f"'{first}' is not a yyyymmdd date")
    return f"{date[:4]}-{date[4:6]}-{date[6:]}"


def read_icgem(path: str | Path, max_degree: int | None = None, *,
               epoch=None) -> xr.Dataset:
    """Read an ICGEM gravity field model (.gfc, plain or compressed).

    Parameters
    ----------
    path : str or Path
        The .gfc file.
    max_degree : int, optional
        Keep only degrees 0..max_degree (default: the model's maximum degree).
    epoch : datetime64, datetime or ISO str, optional
        For a piecewise model (format icgem2.0 with time-variable records): the epoch at which
        its coefficients are evaluated (:func:`_evaluate_piecewise`); the result is then a
        static field with ``attrs["epoch"]``. Ignored for other files.

    Returns
    -------
    xarray.Dataset
        Fully normalised ``C``, ``S`` (n, m) and, when present, ``sigma_C``/``sigma_S`` and the
        time-variable terms; see the module docstring.

    Raises
    ------
    FormatError
        If the file does not follow the ICGEM format (see the module docstring).
    ValueError
        If ``max_degree`` is negative or exceeds the model's maximum degree.
    """
    path = Path(path)
    lines = read_lines(path)
    require_line_end(lines, path)
    attrs, first = _parse_header(lines, path)
    n_file = attrs["max_degree_file"]
    if max_degree is None:
        max_degree = n_file
    if not 0 <= max_degree <= n_file:
        raise ValueError(f"max_degree {max_degree} outside 0..{n_file} (the model's degree)")
    piecewise = attrs["format"] != "icgem1.0" and epoch is not None
    tokens, line_nos = _collect(lines, first, max_degree, n_file, attrs["format"], path,
                                piecewise)
    tv_keys = [k for k in _TIME_VARIABLE if tokens[k]]
    if piecewise and tv_keys:
        return _evaluate_piecewise(tokens, line_nos, attrs, max_degree, n_file,
                                   np.datetime64(epoch, "ns"), path)

    size = max_degree + 1
    coef = {name: np.zeros((size, size)) for name in ("C", "S")}
    sigma = {name: np.full((size, size), np.nan) for name in ("C", "S")}
    static_rows = tokens["gfc"] + tokens["gfct"]
    static_nums = line_nos["gfc"] + line_nos["gfct"]
    n, m = _degree_order(static_rows, static_nums, n_file, path)
    _check_unique(n, m, static_nums, "gfc", path)
    coef["C"][n, m] = parse_floats([r[3] for r in static_rows], static_nums, "C", path,
                                   kind="stokes")
    coef["S"][n, m] = parse_floats([r[4] for r in static_rows], static_nums, "S", path,
                                   kind="stokes")
    with_sigma = [k for k, r in enumerate(static_rows) if len(r) >= 7]
    has_sigma = bool(with_sigma)
    if has_sigma:
        rows = [static_rows[k] for k in with_sigma]
        nums = [static_nums[k] for k in with_sigma]
        sigma["C"][n[with_sigma], m[with_sigma]] = parse_floats(
            [r[5] for r in rows], nums, "sigma C", path, kind="stokes_sigma")
        sigma["S"][n[with_sigma], m[with_sigma]] = parse_floats(
            [r[6] for r in rows], nums, "sigma S", path, kind="stokes_sigma")

    scale = (_unnormalized_to_normalized(max_degree) if attrs["norm_in_file"] == "unnormalized"
             else 1.0)
    coords = {"n": np.arange(size), "m": np.arange(size)}
    data = {}
    for name in ("C", "S"):
        data[name] = (("n", "m"), coef[name] * scale,
                      {"units": "1", "long_name": f"fully normalised {name} coefficient"})
        if has_sigma:
            data[f"sigma_{name}"] = (("n", "m"), sigma[name] * scale, {
                "units": "1", "long_name": f"standard deviation of {name} ({attrs['errors']})"})

    attrs["time_variable_terms"] = " ".join(tv_keys)
    if tv_keys:
        attrs["t0"] = _reference_epoch(tokens["gfct"], line_nos["gfct"], path) \
            if tokens["gfct"] else ""
        _add_time_variable(tokens, line_nos, size, n_file, scale, data, coords, path)
    attrs["max_degree"] = max_degree
    attrs["filename"] = path.name
    return xr.Dataset(data, coords=coords, attrs=attrs)


def _add_time_variable(tokens: dict[str, list[list[str]]], line_nos: dict[str, list[int]],
                       size: int, n_file: int, scale: np.ndarray | float, data: dict,
                       coords: dict, path: Path) -> None:
    """Add the trnd and acos/asin variables (and the ``period`` coordinate) to ``data``."""
    rows = tokens["trnd"] + tokens["dot"]
    nums = line_nos["trnd"] + line_nos["dot"]
    n, m = _degree_order(rows, nums, n_file, path)
    _check_unique(n, m, nums, "trnd", path)
    for col, name in ((3, "C"), (4, "S")):
        grid = np.zeros((size, size))
        grid[n, m] = parse_floats([r[col] for r in rows], nums, name, path, kind="stokes")
        data[f"trnd_{name}"] = (("n", "m"), grid * scale, {
            "units": "year-1", "long_name": f"secular rate of {name} per year"})
    periods = parse_floats([r[7] for k in ("acos", "asin") for r in tokens[k]],
                           line_nos["acos"] + line_nos["asin"], "period", path, lo=1e-6,
                           hi=1e6)
    unique = np.unique(periods)[::-1]
    coords["period"] = ("period", unique, {"units": "year", "long_name": "period of the term"})
    for key in ("acos", "asin"):
        rows, nums = tokens[key], line_nos[key]
        n, m = _degree_order(rows, nums, n_file, path)
        p = parse_floats([r[7] for r in rows], nums, "period", path, lo=1e-6, hi=1e6)
        _check_unique(n, m, nums, key, path, extra=p)
        p_idx = np.searchsorted(-unique, -p)
        for col, name in ((3, "C"), (4, "S")):
            grid = np.zeros((unique.size, size, size))
            grid[p_idx, n, m] = parse_floats([r[col] for r in rows], nums, name, path,
                                             kind="stokes")
            data[f"{key}_{name}"] = (("period", "n", "m"), grid * scale, {
                "units": "1", "long_name": f"{'cosine' if key == 'acos' else 'sine'} amplitude "
                                           f"of {name}"})


def _interval_epoch(text: str, path: Path, line: int, field: str) -> int:
    """ns since 1970 of an icgem2.0 interval bound ``yyyymmdd.hhmm`` (minute 60 is carried
    into the hour: EIGEN-6S4 writes ``20041226.0060``)."""
    date, _, hhmm = text.partition(".")
    hhmm = hhmm.ljust(4, "0")
    if len(date) != 8 or not is_digits(date) or len(hhmm) != 4 or not is_digits(hhmm):
        raise FormatError(path, line, field, f"'{text}' is not yyyymmdd.hhmm")
    minute = int(hhmm[2:])
    carry = minute == 60
    ns = epoch_ns(int(date[:4]), int(date[4:6]), int(date[6:]), int(hhmm[:2]),
                  0 if carry else minute, 0.0, path, line, field)
    return ns + (3_600_000_000_000 if carry else 0)


def _evaluate_piecewise(tokens: dict, line_nos: dict, attrs: dict, max_degree: int,
                        n_file: int, epoch: np.datetime64, path: Path) -> xr.Dataset:
    """A piecewise (icgem2.0) model evaluated at ``epoch``, as a static field.

    ICGEM format 2.0 (Ince et al. 2019, ESSD 11, 647, doi:10.5194/essd-11-647-2019; format
    description at icgem.gfz-potsdam.de): each ``gfct``/``trnd``/``acos``/``asin`` record
    holds on its interval t0 <= t < t1, and a coefficient is ``gfc`` (static records) plus,
    with dt = t - t0 in years of 365.25 days,
    ``gfct + trnd dt + sum_p [acos_p cos(2 pi dt / p) + asin_p sin(2 pi dt / p)]``.
    Standard deviations are those of the static and ``gfct`` records.
    """
    t = int(np.datetime64(epoch, "ns").astype(np.int64))
    size = max_degree + 1
    coef = {name: np.zeros((size, size)) for name in ("C", "S")}
    sigma = {name: np.full((size, size), np.nan) for name in ("C", "S")}
    for key in ("gfc", "gfct", "trnd", "dot", "acos", "asin"):
        rows, nums = tokens[key], line_nos[key]
        if not rows:
            continue
        n, m = _degree_order(rows, nums, n_file, path)
        factor = np.ones(len(rows))
        if key != "gfc":
            tail = 3 if key in ("acos", "asin") else 2
            t0 = np.array([_interval_epoch(r[-tail], path, k, "t0") for r, k in zip(rows, nums)])
            t1 = np.array([_interval_epoch(r[-tail + 1], path, k, "t1")
                           for r, k in zip(rows, nums)])
            active = (t0 <= t) & (t < t1)
            dt_years = (t - t0) / _YEAR_NS
            if key in ("acos", "asin"):
                period = parse_floats([r[-1] for r in rows], nums, "period", path, lo=1e-6,
                                      hi=1e6)
                arg = 2.0 * np.pi * dt_years / period
                factor = np.cos(arg) if key == "acos" else np.sin(arg)
            elif key in ("trnd", "dot"):
                factor = dt_years
            keep = np.flatnonzero(active)
            rows, nums = [rows[k] for k in keep], [nums[k] for k in keep]
            n, m, factor = n[keep], m[keep], factor[keep]
        if key in ("gfc", "gfct"):
            _check_unique(n, m, nums, key, path)
        for col, name in ((3, "C"), (4, "S")):
            values = parse_floats([r[col] for r in rows], nums, name, path, kind="stokes")
            np.add.at(coef[name], (n, m), values * factor)
        if key in ("gfc", "gfct") and rows and len(rows[0]) >= (7 if key == "gfc" else 9):
            for col, name in ((5, "C"), (6, "S")):
                sigma[name][n, m] = parse_floats([r[col] for r in rows], nums, f"sigma {name}",
                                                 path, kind="stokes_sigma")
    scale = (_unnormalized_to_normalized(max_degree) if attrs["norm_in_file"] == "unnormalized"
             else 1.0)
    data = {}
    for name in ("C", "S"):
        data[name] = (("n", "m"), coef[name] * scale, {
            "units": "1", "long_name": f"fully normalised {name} coefficient at the epoch"})
        data[f"sigma_{name}"] = (("n", "m"), sigma[name] * scale, {
            "units": "1", "long_name": f"standard deviation of {name} ({attrs['errors']})"})
    attrs.update(time_variable_terms="", epoch=str(np.datetime64(t, "ns")),
                 evaluated_terms=" ".join(k for k in _TIME_VARIABLE if tokens[k]),
                 max_degree=max_degree, filename=path.name)
    return xr.Dataset(data, coords={"n": np.arange(size), "m": np.arange(size)}, attrs=attrs)

