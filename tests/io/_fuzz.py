"""Mutation fuzzer of the leopod readers (issue 24): seeds, mutations, verdicts.

Seeds are small *valid* files built at run time from the real data in ``../shared`` (a few
records of each product, with the header counts that the excerpt changes set to the excerpt's;
none is copied into the repository). Where ``../shared`` holds no file of a format (WL biases,
manoeuvre lists, leopod's attitude CSV, BLQ) the seed is written by leopod's own writer
(values of the GRACE-A day or its star-camera quaternions),
or is the BLQ text of ``tests/validation/test_station_displacement.py`` (the Onsala service's
layout with synthetic numbers).

A *case* is one mutation of one seed, reproducible from ``(reader, index)`` alone: truncation,
bit flips, character edits, deleted/duplicated/swapped lines, numeric fields replaced by
hostile values (``1_000``, ``1e308``, ``nan``, ``-1``, 10-digit years ...), and damaged gzip
layers. The verdict of a case (:func:`run_case`) is

``accepted``
    the reader returned, and every value passed :func:`suspects`;
``refused``
    :class:`leopod.io.FormatError` whose message names the file;
``crash``
    any other exception, or a FormatError that does not name the file;
``hang``
    the reader ran longer than the time limit;
``suspect``
    the reader returned a value that is not finite, far outside the range of the seed's values
    of that variable (more than 1e6 times the seed's largest magnitude, at least 1e6; for a
    variable the seed lacks, its largest magnitude of any variable), a time
    label outside 1900-2199 or NaT in a time coordinate, or - for a file merely cut short - a
    value of a record that differs from the same record of the seed (the last number cut).

Used by ``tests/io/test_fuzz_readers.py`` (a few hundred cases per reader) and
``benchmarks/fuzz_readers.py`` (>= 10 000 per reader).
"""

from __future__ import annotations

import ast
import contextlib
import dataclasses
import gzip
import logging
import os
import random
import re
import signal
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import xarray as xr

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]

# ------------------------------------------------------------------------------------ seeds


def _text(path: Path) -> list[str]:
    from leopod.io._text import read_lines

    return read_lines(path)


def _upto(lines: list[str], marker: str) -> int:
    """Index of the first line containing ``marker``."""
    return next(k for k, line in enumerate(lines) if marker in line)


def _seed_rinex2(d: Path) -> list[str]:
    lines = _text(d / "grace-a_2007-080/graa0800.07o.gz")
    h = _upto(lines, "END OF HEADER")
    epochs = [k for k in range(h + 1, h + 200) if re.match(r" 07  3 21", lines[k])]
    return lines[:epochs[3]]               # header and the first 3 epoch records


def _seed_rinex3(d: Path, tmp: Path) -> list[str]:
    from leopod.io.rinex_obs import read_rinex_obs
    from leopod.io.rinex_obs_write import write_rinex_obs

    src = tmp / "v2.obs"
    src.write_text("\n".join(_seed_rinex2(d)) + "\n")
    out = tmp / "v3.rnx"
    old = os.environ.get("SOURCE_DATE_EPOCH")
    os.environ["SOURCE_DATE_EPOCH"] = "1174435200"  # the header date: 2007-03-21, reproducible
    try:
        write_rinex_obs(read_rinex_obs(src), out, version=3.04)
    finally:
        if old is None:
            del os.environ["SOURCE_DATE_EPOCH"]
        else:
            os.environ["SOURCE_DATE_EPOCH"] = old
    return _text(out)


def _seed_sp3(d: Path) -> list[str]:
    lines = _text(d / "grace-a_2007-080/cod14193.sp3.gz")
    first = _upto(lines, "*  ")
    n_sat = int(lines[2][3:6])
    body = lines[first:first + 2 * (n_sat + 1)]
    head = lines[:first]
    head[0] = head[0][:32] + f"{2:7d}" + head[0][39:]
    return head + body + ["EOF"]


def _seed_clock(d: Path) -> list[str]:
    lines = _text(d / "grace-a_2007-080/cod14193.clk.gz")
    h = _upto(lines, "END OF HEADER")
    return lines[:h + 1 + 60]


def _seed_antex(d: Path) -> list[str]:
    lines = _text(d / "antex/igs14-small.atx")
    ends = [k for k, line in enumerate(lines) if "END OF ANTENNA" in line]
    return lines[:ends[1] + 1]


def _seed_bias_sinex(d: Path) -> list[str]:
    lines = _text(d / "products_2008-279_whu/WHU0IGSFIN_20082790000_01D_01D_ABS.BIA.Z")
    start = _upto(lines, "+BIAS/SOLUTION")
    stop = _upto(lines, "-BIAS/SOLUTION")
    keep = [k for k in range(start + 1, stop) if not lines[k].startswith("*")][:12]
    comment = [k for k in range(start + 1, stop) if lines[k].startswith("*")]
    out = lines[:start + 1] + [lines[k] for k in comment] + [lines[k] for k in keep]
    out += lines[stop:]
    out[0] = out[0][:-8] + f"{len(keep):08d}"
    return out


def _seed_dcb(d: Path) -> list[str]:
    return _text(d / "products_2008-279_whu/P1C10810_RINEX.DCB.Z")[:20]


def _seed_sinex(d: Path, name: str, blocks_kept: dict[str, int]) -> list[str]:
    """Header, the blocks ``blocks_kept`` (title -> column of the site code) restricted to
    the first two sites, ``%ENDSNX``."""
    lines = _text(d / "slr" / name)
    sites: list[str] = []
    out = [lines[0]]
    k = 1
    while k < len(lines):
        line = lines[k]
        if line.startswith("+") and line[1:].strip() in blocks_kept:
            title = line[1:].strip()
            col = blocks_kept[title]
            out.append(line)
            k += 1
            while not lines[k].startswith("-"):
                row = lines[k]
                code = row[col:col + 4]
                if row.startswith("*"):
                    out.append(row)
                elif code in sites or len(sites) < 2 and title == "SITE/ID":
                    if code not in sites:
                        sites.append(code)
                    out.append(row)
                k += 1
            out.append(lines[k])
        k += 1
    return out + ["%ENDSNX"]


def _seed_sinex_stations(d: Path) -> list[str]:
    return _seed_sinex(d, "SLRF2020_POS+VEL_2023.10.02.snx",
                       {"SITE/ID": 1, "SOLUTION/EPOCHS": 1, "SOLUTION/ESTIMATE": 14})


def _seed_sinex_ecc(d: Path) -> list[str]:
    return _seed_sinex(d, "ecc_xyz.snx", {"SITE/ID": 1, "SITE/ECCENTRICITY": 1})


def _seed_icgem(d: Path) -> list[str]:
    lines = _text(d.parent / "models/gravity/JGM3.gfc")
    out = []
    for line in lines:
        t = line.split()
        if t and t[0] == "max_degree":
            line = "max_degree 4"
        if t and t[0] == "gfc" and int(t[1]) > 4:
            continue
        out.append(line)
    return out


def _seed_fes(d: Path) -> list[str]:
    lines = _text(d.parent / "models/ocean_tides/fes2004_Cnm-Snm.dat")
    return lines[:4] + [line for line in lines[4:] if int(line.split()[2]) <= 3][:40]


def _seed_space_weather(d: Path) -> list[str]:
    lines = _text(d.parent / "models/space_weather/SW-All.csv")
    return lines[:1] + lines[18060:18080]


def _seed_grace_orbit(d: Path) -> list[str]:
    return _text(d / "grace-b_2010-208/grca_truth.csv")[:20]


def _seed_kband(d: Path) -> list[str]:
    return _text(d / "grace-b_2010-208/grc_kb_rng.csv")[:20]


def _seed_crd_np(d: Path) -> list[str]:
    return _text(d / "slr/lageos1-test.npt")


def _seed_crd_fr(d: Path) -> list[str]:
    return _text(d / "slr/champ_201709-small.frd")


def _seed_wlbias(d: Path, tmp: Path) -> list[str]:
    """WL records written by leopod's writer; values: the fractional parts of the first
    epoch's P1 - C1 of the GRACE-A seed in metres (a real, varied set of small numbers)."""
    from leopod.io.wlbias_write import write_wl_bias

    sv = ["G01", "G05", "G09", "G11", "G14"]
    vals = np.array([0.174, -0.166, -0.286, -0.255, 0.229])
    t = np.array(["2007-03-21T00:00:00", "2007-03-21T00:05:00"], dtype="datetime64[ns]")
    ds = xr.Dataset({"wl_bias_cyc": (("time", "sv"), np.vstack([vals, vals + 0.01])),
                     "wl_bias_sigma_cyc": (("time", "sv"), np.full((2, 5), 0.01))},
                    coords={"time": t, "sv": sv})
    out = tmp / "wl.txt"
    write_wl_bias(ds, out)
    return _text(out)


def _seed_manoeuvre(d: Path, tmp: Path) -> list[str]:
    """Two burns written by leopod's writer (epochs of the GRACE-A day)."""
    from leopod.io.manoeuvre import Manoeuvre
    from leopod.io.manoeuvre_write import write_manoeuvres

    t = np.datetime64("2007-03-21T12:00:00", "ns")
    burns = (Manoeuvre(t, t + np.timedelta64(60, "s"), (0.0, 5.0e-5, -1.0e-6)),
             Manoeuvre(t + np.timedelta64(2907, "s"), t + np.timedelta64(2967, "s"),
                       (1.0e-7, -5.0e-5, 0.0)))
    out = tmp / "man.txt"
    write_manoeuvres(out, burns, satellite="grace-a")
    return _text(out)


def _seed_sca1b(d: Path) -> list[str]:
    return _text(d / "grace_l1b_fixture_2003-09-14/SCA1B_2003-09-14_A_00.asc")


def _seed_attitude_csv(d: Path, tmp: Path) -> list[str]:
    """The first 20 GRACE-A star-camera quaternions written by leopod's attitude CSV writer."""
    from leopod.io.attitude import read_sca1b
    from leopod.io.attitude_write import write_attitude_csv

    sca = read_sca1b(d / "grace_l1b_fixture_2003-09-14/SCA1B_2003-09-14_A_00.asc")
    out = tmp / "att.csv"
    write_attitude_csv(out, sca["time"].values[:20], sca["quat"].values[:20],
                       satellite="grace-a")
    return _text(out)


def _seed_blq(d: Path) -> list[str]:
    """The BLQ text of the station-displacement tests (Onsala layout, synthetic numbers)."""
    src = (REPO / "tests/validation/test_station_displacement.py").read_text()
    for node in ast.parse(src).body:
        if isinstance(node, ast.Assign) and getattr(node.targets[0], "id", "") == "BLQ_TEXT":
            return ast.literal_eval(node.value).splitlines()
    raise LookupError("BLQ_TEXT not found")


def _readers() -> dict[str, tuple[Callable, str, Callable]]:
    """reader name -> (read(path), seed file name, seed builder(data_dir, tmp))."""
    from leopod.io.antex import read_antex
    from leopod.io.attitude import read_attitude_csv, read_sca1b
    from leopod.io.bias_sinex import read_bias_sinex
    from leopod.io.blq import read_blq
    from leopod.io.clock import read_rinex_clock
    from leopod.io.crd import read_crd
    from leopod.io.dcb import read_code_dcb
    from leopod.io.fes import read_fes_cnm
    from leopod.io.grace_orbit_csv import read_grace_orbit_csv, read_kband_range_csv
    from leopod.io.icgem import read_icgem
    from leopod.io.manoeuvre import read_manoeuvres
    from leopod.io.rinex_obs import read_rinex_obs
    from leopod.io.sinex import read_sinex_eccentricities, read_sinex_stations
    from leopod.io.sp3 import read_sp3
    from leopod.io.space_weather import read_space_weather
    from leopod.io.wlbias import read_wl_bias

    def plain(f):
        return lambda d, tmp: f(d)

    return {
        "rinex_obs_v2": (read_rinex_obs, "graa0800.07o", plain(_seed_rinex2)),
        "rinex_obs_v3": (read_rinex_obs, "GRAA00XXX_R_20070800000_01D_10S_MO.rnx",
                         _seed_rinex3),
        "sp3": (read_sp3, "cod14193.sp3", plain(_seed_sp3)),
        "clock": (lambda p: read_rinex_clock(p, ("AS", "AR")), "cod14193.clk",
                  plain(_seed_clock)),
        "antex": (read_antex, "igs14-small.atx", plain(_seed_antex)),
        "bias_sinex": (read_bias_sinex, "WHU0IGSFIN.BIA", plain(_seed_bias_sinex)),
        "dcb": (read_code_dcb, "P1C10810_RINEX.DCB", plain(_seed_dcb)),
        "wlbias": (read_wl_bias, "wl.txt", _seed_wlbias),
        "crd_np": (lambda p: read_crd(p, "normal_point"), "lageos1.npt", plain(_seed_crd_np)),
        "crd_fr": (lambda p: read_crd(p, "full_rate"), "champ.frd", plain(_seed_crd_fr)),
        "sinex_stations": (read_sinex_stations, "SLRF2020.snx", plain(_seed_sinex_stations)),
        "sinex_ecc": (read_sinex_eccentricities, "ecc_xyz.snx", plain(_seed_sinex_ecc)),
        "blq": (read_blq, "stations.blq", plain(_seed_blq)),
        "icgem": (read_icgem, "JGM3.gfc", plain(_seed_icgem)),
        "fes": (read_fes_cnm, "fes2004_Cnm-Snm.dat", plain(_seed_fes)),
        "space_weather": (read_space_weather, "SW-All.csv", plain(_seed_space_weather)),
        "grace_orbit_csv": (read_grace_orbit_csv, "grca_truth.csv", plain(_seed_grace_orbit)),
        "kband_range_csv": (read_kband_range_csv, "grc_kb_rng.csv", plain(_seed_kband)),
        "manoeuvre": (lambda p: read_manoeuvres(p), "manoeuvres.txt", _seed_manoeuvre),
        "attitude_sca1b": (read_sca1b, "SCA1B_2003-09-14_A_00.asc", plain(_seed_sca1b)),
        "attitude_csv": (read_attitude_csv, "attitude.csv", _seed_attitude_csv),
    }


@dataclasses.dataclass
class Seed:
    """One reader with its seed file (text) and the seed's parsed result."""

    name: str
    read: Callable
    filename: str
    text: bytes
    result: object


def build_seeds(data: Path, tmp: Path, names: list[str] | None = None) -> dict[str, Seed]:
    """Seeds of the readers ``names`` (all by default) from ``data`` = ``../shared/data``.

    Every seed is parsed once; a seed its reader refuses raises (the fuzzer needs valid
    seeds)."""
    out = {}
    with _quiet():
        _build(data, tmp, names, out)
    return out


@contextlib.contextmanager
def _quiet():
    """Silence the readers' warnings and log messages (lenient-reading notes) meanwhile."""
    logging.disable(logging.WARNING)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            yield
    finally:
        logging.disable(logging.NOTSET)


def _build(data: Path, tmp: Path, names, out: dict) -> None:
    for name, (read, filename, build) in _readers().items():
        if names is not None and name not in names:
            continue
        text = ("\n".join(build(data, tmp)) + "\n").encode("latin-1")
        path = tmp / filename
        path.write_bytes(text)
        out[name] = Seed(name, read, filename, text, read(path))


# -------------------------------------------------------------------------------- mutations
HOSTILE = ["-1", "0", "-0", "1_000", "1e308", "-1e308", "1E-99", "nan", "NaN", "inf", "-inf",
           "9999999999", "-9999999999", "99999", "-43", "40000", "3000", "0000", "00",
           "1.0e+20", "0x10", "+", "-", ".", "E", "1D+300", "٣", "2262", "1677", "65536",
           "-2147483649", "1e-320", " "]
_NUMBER = re.compile(rb"[-+]?\d*\.?\d+(?:[EeDd][-+]?\d+)?")
#: Bytes a character edit writes: digits, signs, separators, and Latin-1 characters that
#: Python treats as digits or blanks ("²", "¹", "¼", NEL, no-break space)
INTERESTING_BYTES = b"0123456789-+. E_\n*:%#\xb2\xb9\xbc\x85\xa0"


def _lines(text: bytes) -> list[bytes]:
    return text.split(b"\n")


def _edit_number(rng: random.Random, text: bytes) -> bytes:
    spans = [m.span() for m in _NUMBER.finditer(text)]
    if not spans:
        return text
    a, b = rng.choice(spans)
    new = rng.choice(HOSTILE).encode("utf-8")
    if rng.random() < 0.5:  # keep the column width (fixed-column formats)
        new = new.rjust(b - a)[: max(b - a, len(new))]
    return text[:a] + new + text[b:]


def _mutate_once(rng: random.Random, text: bytes) -> tuple[bytes, str]:
    kind = rng.choice(["truncate", "truncate", "flip", "byte", "byte", "number", "number",
                       "number", "del_line", "dup_line", "swap_lines", "digit", "blank_field"])
    n = len(text)
    if kind == "truncate":
        return text[:rng.randrange(n)], kind
    if kind == "flip":
        k = rng.randrange(n)
        return text[:k] + bytes([text[k] ^ (1 << rng.randrange(8))]) + text[k + 1:], kind
    if kind == "byte":
        k = rng.randrange(n)
        return text[:k] + bytes([rng.choice(INTERESTING_BYTES)]) + text[k + 1:], kind
    if kind == "digit":
        digits = [m.start() for m in re.finditer(rb"\d", text)]
        if digits:
            k = rng.choice(digits)
            return text[:k] + str(rng.randrange(10)).encode() + text[k + 1:], kind
        return text, kind
    if kind == "number":
        return _edit_number(rng, text), kind
    if kind == "blank_field":
        spans = [m.span() for m in _NUMBER.finditer(text)]
        if spans:
            a, b = rng.choice(spans)
            return text[:a] + b" " * (b - a) + text[b:], kind
        return text, kind
    lines = _lines(text)
    i = rng.randrange(len(lines))
    if kind == "del_line":
        del lines[i]
    elif kind == "dup_line":
        lines.insert(i, lines[i])
    else:
        j = rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
    return b"\n".join(lines), kind


def _damage_gzip(rng: random.Random, text: bytes) -> tuple[bytes, str]:
    kind = rng.choice(["gz_cut", "gz_flip", "gz_empty", "gz_ok", "gz_trailing"])
    if kind == "gz_empty":
        return gzip.compress(b"", mtime=0), kind
    z = gzip.compress(text, mtime=0)
    if kind == "gz_cut":
        return z[:rng.randrange(2, len(z))], kind
    if kind == "gz_flip":
        k = rng.randrange(10, len(z))
        return z[:k] + bytes([z[k] ^ (1 << rng.randrange(8))]) + z[k + 1:], kind
    if kind == "gz_trailing":
        return z + bytes(rng.randrange(256) for _ in range(rng.randrange(1, 9))), kind
    return z, kind


def mutate(seed: Seed, index: int) -> tuple[bytes, str]:
    """Case ``index`` of ``seed``: (file bytes, description). Deterministic."""
    rng = random.Random(f"{seed.name}:{index}")
    text = seed.text
    kinds = []
    for _ in range(rng.choice([1, 1, 1, 2, 3])):
        text, kind = _mutate_once(rng, text or b" ")
        kinds.append(kind)
    if rng.random() < 0.08:
        text, kind = _damage_gzip(rng, text)
        kinds.append(kind)
    if not text:
        text = b" "
    return text, "+".join(kinds)


# --------------------------------------------------------------------------------- verdicts
class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout


def _leaves(obj, prefix="", depth=0):
    """(name, ndarray) of every numeric/datetime array or scalar inside a reader's result."""
    if depth > 4:
        return
    if isinstance(obj, xr.Dataset):
        for name, var in obj.variables.items():
            yield str(name), np.asarray(var.values)
        for key, value in obj.attrs.items():
            if isinstance(value, (int, float, np.number)) and not isinstance(value, bool):
                yield f"attrs.{key}", np.asarray(value)
    elif dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        for f in dataclasses.fields(obj):
            yield from _leaves(getattr(obj, f.name), f"{prefix}{f.name}.", depth + 1)
    elif isinstance(obj, dict):
        for key, value in obj.items():
            yield from _leaves(value, f"{prefix}{key}.", depth + 1)
    elif isinstance(obj, (list, tuple)):
        for value in obj:
            yield from _leaves(value, prefix, depth + 1)
    elif hasattr(obj, "__dict__") and not isinstance(obj, type) and depth < 2:
        for key, value in vars(obj).items():
            yield from _leaves(value, f"{prefix}{key}.", depth + 1)
    elif isinstance(obj, (np.ndarray, np.generic, float, int)) and not isinstance(obj, bool):
        yield prefix.rstrip("."), np.asarray(obj)


_T_MIN = np.datetime64("1900-01-01", "ns")
_T_MAX = np.datetime64("2200-01-01", "ns")


def _scales(result) -> dict[str, float]:
    out: dict[str, float] = {}
    for name, arr in _leaves(result):
        if arr.dtype.kind in "fiu" and arr.size:
            finite = np.abs(arr[np.isfinite(arr)]) if arr.dtype.kind == "f" else np.abs(arr)
            m = float(finite.max()) if finite.size else 0.0
            out[name] = max(out.get(name, 0.0), m)
    return out


def suspects(result, seed: Seed, scales: dict[str, float]) -> list[str]:
    """Reasons why an accepted result is suspect (empty list: nothing suspect)."""
    reasons = []
    # a variable the seed does not have (e.g. an observation type renamed by the mutation)
    # is compared with the largest magnitude of the seed
    top = max(scales.values(), default=1.0)
    for name, arr in _leaves(result):
        if arr.dtype.kind == "f":
            if np.isinf(arr).any():
                reasons.append(f"{name}: infinite value")
                continue
            limit = 1e6 * max(scales.get(name, top), 1.0)
            with np.errstate(invalid="ignore"):
                if (np.abs(arr) > limit).any():
                    reasons.append(f"{name}: |value| {np.nanmax(np.abs(arr)):.3g} > {limit:.3g}")
        elif arr.dtype.kind in "iu":
            limit = 1e6 * max(scales.get(name, top), 1.0)
            if (np.abs(arr.astype(float)) > limit).any():
                reasons.append(f"{name}: |value| {np.abs(arr).max()} > {limit:.3g}")
        elif arr.dtype.kind == "M":
            t = arr.astype("datetime64[ns]")
            ok = ~np.isnat(t)
            if ((t[ok] < _T_MIN) | (t[ok] >= _T_MAX)).any():
                reasons.append(f"{name}: epoch outside 1900-2199")
            if name in ("time", "epoch") and (~ok).any():
                reasons.append(f"{name}: NaT time label")
    return reasons


#: Variables computed from several records, which a file cut after a complete record changes
#: legitimately: CRD's meteorological values are interpolated in time between the record-20
#: lines of the session (the reader keeps a session cut after a complete record, with a
#: warning, by design: tests/io/test_crd.py::test_session_without_h8_is_kept_with_warning).
DERIVED = {"crd_np": {"pressure_hpa", "temperature_k", "humidity_pct"},
           "crd_fr": {"pressure_hpa", "temperature_k", "humidity_pct"}}


def _prefix_changes(result, seed: Seed) -> list[str]:
    """For a file cut short: values of records that the seed also has, but differ."""
    if not isinstance(result, xr.Dataset) or not isinstance(seed.result, xr.Dataset):
        return []
    reasons = []
    for name, var in result.data_vars.items():
        if name not in seed.result or var.dtype.kind != "f" or \
                name in DERIVED.get(seed.name, ()):
            continue
        ref = seed.result[name]
        if ref.dims != var.dims:
            continue
        index = {}
        for dim in var.dims:
            if dim in var.coords and dim in ref.coords:
                common = np.intersect1d(var[dim].values, ref[dim].values)
                index[dim] = common
            else:
                index[dim] = None
        a, b = var, ref
        for dim, common in index.items():
            if common is None:
                n = min(a.sizes[dim], b.sizes[dim])
                a, b = a.isel({dim: slice(0, n)}), b.isel({dim: slice(0, n)})
            else:
                a, b = a.sel({dim: common}), b.sel({dim: common})
        x, y = np.asarray(a.values, float), np.asarray(b.values, float)
        # coefficient grids hold 0 where a (shorter) file gives no record: not a changed value
        both = np.isfinite(x) & np.isfinite(y) & (x != 0)
        if (x[both] != y[both]).any():
            reasons.append(f"{name}: a value of the cut file differs from the seed's")
    return reasons


def run_case(seed: Seed, index: int, folder: Path, scales: dict[str, float],
             timeout_s: float = 5.0) -> tuple[str, str]:
    """Run one case; returns (verdict, detail). Verdicts as in the module docstring."""
    data, kinds = mutate(seed, index)
    path = folder / seed.filename
    path.write_bytes(data)
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, timeout_s)
    try:
        result = seed.read(path)
    except _Timeout:
        return "hang", kinds
    except Exception as err:  # noqa: BLE001 - the verdict is the point
        from leopod.io import FormatError

        if isinstance(err, FormatError) and seed.filename in str(err):
            return "refused", kinds
        return "crash", f"{kinds}: {type(err).__name__}: {str(err)[:160]}"
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
    reasons = suspects(result, seed, scales)
    if kinds == "truncate" or kinds.startswith("truncate+gz_ok"):
        reasons += _prefix_changes(result, seed)
    if reasons:
        return "suspect", f"{kinds}: {'; '.join(reasons)[:200]}"
    return "accepted", kinds


def fuzz_reader(seed: Seed, cases: range, folder: Path, timeout_s: float = 5.0
                ) -> dict[str, list]:
    """Run ``cases`` of one reader; verdict -> list of (index, detail)."""
    scales = _scales(seed.result)
    out: dict[str, list] = {k: [] for k in ("accepted", "refused", "crash", "hang", "suspect")}
    with _quiet():
        for i in cases:
            verdict, detail = run_case(seed, i, folder, scales, timeout_s)
            out[verdict].append((i, detail))
    return out


__all__ = ["HOSTILE", "Seed", "build_seeds", "fuzz_reader", "mutate", "run_case", "suspects"
           ]
