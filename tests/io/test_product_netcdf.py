"""GNSS products as netCDF (leopod.io.product_netcdf): parsed once, read back identical.

Authority: the text readers themselves (read_sp3, read_rinex_clock, read_antex). The netCDF
files must give back their Datasets and antenna patterns bit for bit, on the real GRACE-A day
(CODE orbits and clocks, IGS05 ANTEX), on multi-GNSS ANTEX subsets with azimuth grids and
on the simulated default campaign's products; damaged files are refused with their name.
"""

from __future__ import annotations

import gzip
import importlib.util
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from leopod.estimation.arc import ArcData
from leopod.estimation.inputs import satellite_antenna
from leopod.io import FormatError
from leopod.io.antex import read_antex
from leopod.io.clock import read_rinex_clock
from leopod.io.product_netcdf import (
    antex_from_dataset,
    read_antenna_product,
    read_clock_product,
    read_orbit_product,
    satellite_antenna_dataset,
    write_product,
)
from leopod.io.sp3 import read_sp3
from leopod.signals import signal_settings
from leopod.simulate.campaign import simulate_gnss_products, simulate_world_truth
from leopod.simulate.settings import SimulationSettings
from leopod.workflow.boundary import REPOSITORY
from leopod.workflow.config import section_defaults

GRACE = "grace-a_2007-080"
SIGNALS = signal_settings({"G": {"phase": ["L1C", "L2W"], "code": ["C1C", "C1W", "C2W"],
                                 "pod_code": ["C1W", "C2W"]}})


def _gnss_products_main():
    """scripts/gnss_products.py's ``main`` (the rule's own code)."""
    path = REPOSITORY / "scripts" / "gnss_products.py"
    spec = importlib.util.spec_from_file_location("leopod_script_gnss_products", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.main


def _assert_same_product(parsed: xr.Dataset, stored: xr.Dataset) -> None:
    """Every variable and coordinate of ``parsed`` in ``stored`` with identical dtype kind,
    dims and values (NaN where NaN), and the reader's attributes kept."""
    assert set(parsed.variables) == set(stored.variables)
    for name, var in parsed.variables.items():
        back = stored[name]
        assert back.dims == var.dims, name
        assert back.dtype.kind == var.dtype.kind, name
        if var.dtype.kind in "fM":
            np.testing.assert_array_equal(back.values, var.values, err_msg=name)
            assert np.array_equal(back.values, var.values, equal_nan=True), name
        else:
            assert back.values.tolist() == var.values.tolist(), name
    for key, value in parsed.attrs.items():
        assert stored.attrs[key] == value, key


def _assert_same_antenna_model(antex, stored, sv, epoch) -> None:
    """PCO and the PCV function of :func:`satellite_antenna` identical from both models."""
    pco_a, pcv_a = satellite_antenna(antex, sv, epoch, "G", SIGNALS["G"])
    pco_b, pcv_b = satellite_antenna(stored, sv, epoch, "G", SIGNALS["G"])
    assert np.isfinite(pco_a).all()
    assert np.array_equal(pco_a, pco_b, equal_nan=True)
    sat_index = np.repeat(np.arange(len(sv)), 181)
    nadir = np.tile(np.linspace(-1.0, 17.0, 181), len(sv))   # beyond the grid: edge values
    np.testing.assert_array_equal(pcv_a(sat_index, nadir), pcv_b(sat_index, nadir))


# --- the real GRACE-A day ------------------------------------------------------------------


@pytest.fixture(scope="module")
def grace_products(shared_data, tmp_path_factory):
    """The GRACE-A day's products written by the gnss_products script (GPS satellites)."""
    d = shared_data / GRACE
    out = tmp_path_factory.mktemp("products")
    paths = {k: out / f"2007-080_{k}.nc" for k in ("orbit", "clock", "antenna")}
    _gnss_products_main()("2007-080", d / "cod14193.sp3.gz", d / "cod14193.clk.gz",
                          d / "igs05_1402.atx.gz", paths["orbit"], paths["clock"],
                          paths["antenna"], systems=["G"])
    return d, paths


@pytest.mark.shared
def test_grace_orbit_and_clock_read_back_identical(grace_products):
    d, paths = grace_products
    _assert_same_product(read_sp3(d / "cod14193.sp3.gz"), read_orbit_product(paths["orbit"]))
    _assert_same_product(read_rinex_clock(d / "cod14193.clk.gz"),
                         read_clock_product(paths["clock"]))
    stored = xr.load_dataset(paths["orbit"])
    assert stored.attrs["processing_step"] == "gnss_products"
    assert stored.attrs["input_files"] == "cod14193.sp3.gz"
    assert stored.attrs["reference_frame"] == "IGS05"


@pytest.mark.shared
def test_grace_antenna_model_is_bit_identical(grace_products):
    d, paths = grace_products
    antex = read_antex(d / "igs05_1402.atx.gz")
    stored = read_antenna_product(paths["antenna"])
    # the GPS entries valid from 2007-03-20 to 2007-03-23 only, but each of them whole
    kept = {(a.serial, a.svn) for a in stored.antennas}
    assert {s[0] for s in kept} == {p for p in antex.prns if p.startswith("G")}
    assert all(s[0].startswith("G") for s in kept)
    for a in stored.antennas:
        original = next(b for b in antex.antennas if (b.serial, b.svn) == (a.serial, a.svn))
        xr.testing.assert_identical(a.to_dataset(), original.to_dataset())
    # what the POD computes at the start of an arc and in the middle of the day
    sv = np.array(sorted(s for s in read_sp3(d / "cod14193.sp3.gz").sv.values if s[0] == "G"))
    for epoch in ("2007-03-20T21:00", "2007-03-21T12:00", "2007-03-22T03:00"):
        _assert_same_antenna_model(antex, stored, sv, np.datetime64(epoch, "ns"))
    # entries valid outside the window were dropped: the model refuses such epochs
    with pytest.raises(ValueError, match="kept for"):
        stored.satellite("G05", "2007-03-25T00:00")


@pytest.mark.shared
def test_arc_data_from_netcdf_equals_arc_data_from_text_files(grace_products):
    # ArcData.read on the rule's netCDF products and on the text files themselves
    d, paths = grace_products
    none = {"obs": [], "quality": [], "leo": []}
    text = ArcData.read({**none, "orbit": [d / "cod14193.sp3.gz"],
                         "clock": [d / "cod14193.clk.gz"], "antenna": d / "igs05_1402.atx.gz"})
    stored = ArcData.read({**none, "orbit": [paths["orbit"]], "clock": [paths["clock"]],
                           "antenna": paths["antenna"]})
    _assert_same_product(text.orbit, stored.orbit)
    _assert_same_product(text.clock, stored.clock)
    sv = np.array(sorted(s for s in text.orbit.sv.values if s[0] == "G"))
    _assert_same_antenna_model(text.antex, stored.antex, sv, np.datetime64("2007-03-21", "ns"))
    assert stored.files[-1] == str(paths["antenna"])


@pytest.mark.shared
@pytest.mark.parametrize("name", ["igs14-small.atx", "igs20-small.atx", "igs05_1627.atx"])
def test_multi_gnss_antex_with_azimuth_grids_round_trip(shared_data, tmp_path, name):
    # igs14/igs20 subsets: Galileo, BDS, QZSS, NavIC satellites, azimuth grids (DAZI > 0),
    # frequency lists in their own order, validity ends at 23:59:59.9999999
    antex = read_antex(shared_data / "antex" / name)
    path = write_product(satellite_antenna_dataset(antex), tmp_path / "a.nc", inputs=[name],
                         title="satellite antennas")
    stored = read_antenna_product(path)
    satellites = [a for a in antex.antennas if a.kind == "satellite"]
    assert len(stored.antennas) == len(satellites)
    for a, b in zip(satellites, stored.antennas, strict=True):
        assert b.frequencies == a.frequencies
        xr.testing.assert_identical(b.to_dataset(), a.to_dataset())
        if a.dazi_deg > 0:
            np.testing.assert_array_equal(b.pcv_m(a.frequencies[0], [0.0, 3.3, 9.0],
                                                  [0.0, 123.4, 359.0]),
                                          a.pcv_m(a.frequencies[0], [0.0, 3.3, 9.0],
                                                  [0.0, 123.4, 359.0]))
    assert stored.window is None


# --- the simulated default campaign --------------------------------------------------------


@pytest.fixture(scope="module")
def simulated_day(tmp_path_factory):
    """GNSS products of the default campaign's second day (schema-default simulation)."""
    d = tmp_path_factory.mktemp("sim")
    settings = SimulationSettings.from_config(section_defaults("simulate"))
    biases = simulate_world_truth(settings, ["hy2b-sim"], "2019-01-01", "2019-01-03",
                                  biases_path=d / "b.nc", stations_path=d / "s.snx")
    files = {k: d / f"g{k}" for k in (".sp3", ".clk", "_int.clk", ".wsb", ".bia")}
    simulate_gnss_products("2019-002", settings, "2019-01-01", "2019-01-03", biases,
                           orbit=files[".sp3"], clock=files[".clk"],
                           integer_clock=files["_int.clk"], wl_bias=files[".wsb"],
                           osb=files[".bia"])
    return d, files


def test_simulated_products_read_back_identical(simulated_day, tmp_path):
    _, files = simulated_day
    out = {k: tmp_path / f"{k}.nc" for k in ("orbit", "clock")}
    _gnss_products_main()("2019-002", files[".sp3"], files["_int.clk"], None, out["orbit"],
                          out["clock"], None, systems=["G"])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["clock.nc", "orbit.nc"]
    _assert_same_product(read_sp3(files[".sp3"]), read_orbit_product(out["orbit"]))
    _assert_same_product(read_rinex_clock(files["_int.clk"]), read_clock_product(out["clock"]))
    none = {"obs": [], "quality": [], "leo": []}
    text = ArcData.read({**none, "orbit": [files[".sp3"]], "clock": [files["_int.clk"]]})
    stored = ArcData.read({**none, "orbit": [out["orbit"]], "clock": [out["clock"]]})
    _assert_same_product(text.orbit, stored.orbit)
    _assert_same_product(text.clock, stored.clock)
    assert stored.antex is None


# --- damaged files -------------------------------------------------------------------------


def test_damaged_sp3_names_file_line_field_and_writes_nothing(simulated_day, tmp_path):
    _, files = simulated_day
    lines = files[".sp3"].read_text().splitlines()
    k = next(i for i, ln in enumerate(lines) if ln.startswith("PG05"))
    lines[k] = lines[k][:20] + "  12x45.678" + lines[k][31:]
    bad = tmp_path / "bad.sp3"
    bad.write_text("\n".join(lines) + "\n")
    out = tmp_path / "out"
    with pytest.raises(FormatError, match=rf"bad.sp3:{k + 1}: field 'G05 y'"):
        _gnss_products_main()("2019-002", bad, files["_int.clk"], None, out / "orbit.nc",
                              out / "clock.nc", None, systems=["G"])
    assert not out.exists() or not list(out.iterdir())


def test_damaged_clock_leaves_no_orbit_behind(simulated_day, tmp_path):
    _, files = simulated_day
    text = files["_int.clk"].read_text().splitlines()
    k = next(i for i, ln in enumerate(text) if ln.startswith("AS G07"))
    text = text[:k + 1]                  # truncated inside the data
    text[-1] = text[-1][:40]
    bad = tmp_path / "bad.clk"
    bad.write_text("\n".join(text) + "\n")
    out = tmp_path / "out"
    with pytest.raises(FormatError, match=r"bad.clk:\d+: field "):
        _gnss_products_main()("2019-002", files[".sp3"], bad, None, out / "orbit.nc",
                              out / "clock.nc", None, systems=["G"])
    assert not out.exists() or not list(out.iterdir())


def test_damaged_netcdf_products_are_named(tmp_path, simulated_day):
    _, files = simulated_day
    garbage = tmp_path / "2019-002_orbit.nc"
    garbage.write_bytes(gzip.compress(b"not a netCDF file"))
    with pytest.raises(FormatError, match="2019-002_orbit.nc: field 'netCDF'"):
        read_orbit_product(garbage)
    # a clock file handed over as an orbit file: the missing variable is named
    clock = write_product(read_rinex_clock(files["_int.clk"]), tmp_path / "clock.nc",
                          inputs=[], title="clocks")
    with pytest.raises(FormatError, match="clock.nc: field 'pos_m'"):
        read_orbit_product(clock)
    with pytest.raises(FormatError, match="clock.nc: field 'pco_m'"):
        read_antenna_product(clock)


def test_a_product_that_would_not_read_back_identically_is_refused(tmp_path):
    # an epoch 1 ns off the 30-s grid: float64 seconds since 1980 cannot hold it (0.24 us steps)
    t = np.datetime64("2019-01-02T00:00:00", "ns") + np.array([0, 30_000_000_001], "m8[ns]")
    ds = xr.Dataset({"clk_s": (("time", "sv"), np.zeros((2, 1)),
                               {"units": "s", "long_name": "clock"})},
                    coords={"time": t, "sv": ["G01"]})
    with pytest.raises(ValueError, match="'time' does not read back identically"):
        write_product(ds, tmp_path / "c.nc", inputs=[], title="clocks")
    assert list(tmp_path.iterdir()) == []


def test_no_satellite_of_the_systems_gives_an_empty_model(tmp_path):
    antex = read_antex(_plane_antex(tmp_path))
    ds = satellite_antenna_dataset(antex, ["C"], "2019-01-01", "2019-01-04")
    stored = antex_from_dataset(xr.load_dataset(
        write_product(ds, tmp_path / "a.nc", inputs=[], title="antennas")))
    assert stored.antennas == [] and stored.prns == []
    with pytest.raises(KeyError, match="PRN absent"):
        stored.satellite("C20", "2019-01-02")


def _plane_antex(folder: Path) -> Path:
    """An ANTEX file with one GPS satellite entry (valid from 2000 on)."""
    def rec(text, label):
        return f"{text:<60s}{label:<20s}"
    lines = [rec("     1.4            M", "ANTEX VERSION / SYST"), rec("A", "PCV TYPE / REFANT"),
             rec("", "END OF HEADER"), rec("", "START OF ANTENNA"),
             rec(f"{'BLOCK IIR-M':<20s}{'G05':<20s}{'G050':<10s}{'2009-043A':<10s}",
                 "TYPE / SERIAL NO"),
             rec("     0.0", "DAZI"), rec("     0.0  14.0   1.0", "ZEN1 / ZEN2 / DZEN"),
             rec("     1", "# OF FREQUENCIES"),
             rec("  2000     1     1     0     0    0.0000000", "VALID FROM"),
             rec("   G01", "START OF FREQUENCY"),
             rec("    279.00      0.00   2319.50", "NORTH / EAST / UP"),
             "   NOAZI" + "".join(f"{v:8.2f}" for v in np.linspace(-5.0, 5.0, 15)),
             rec("   G01", "END OF FREQUENCY"), rec("", "END OF ANTENNA")]
    path = folder / "plane.atx"
    path.write_text("\n".join(lines) + "\n")
    return path
