"""The netCDF writer: metadata, explicit time encoding, lossless round trip, atomic failure."""

import numpy as np
import pytest
import xarray as xr

from leopod.io.netcdf import TIME_UNITS, write_netcdf


def _ds():
    t = np.datetime64("2007-03-21T00:00:00", "ns") + np.arange(3) * np.timedelta64(10, "s")
    pos = np.array([[6.8e6 + 0.123456789, 1.0, -2.0]] * 3)
    return xr.Dataset({"pos_m": (("time", "xyz"), pos, {"units": "m", "long_name": "position"})},
                      coords={"time": t, "xyz": ["x", "y", "z"]})


def test_round_trip_is_lossless_and_self_describing(tmp_path):
    path = write_netcdf(_ds(), tmp_path / "a.nc", step="ingest", inputs=["/x/graa0800.07o.gz"],
                        time_system="GPS", reference_frame="ITRF")
    with xr.open_dataset(path) as back:
        back.load()
        assert back.attrs["processing_step"] == "ingest"
        assert back.attrs["input_files"] == "graa0800.07o.gz"
        assert back.attrs["time_system"] == "GPS"
        assert back.time.encoding["units"] in (TIME_UNITS, "seconds since 1980-01-06")
        np.testing.assert_array_equal(back.pos_m.values, _ds().pos_m.values)   # bit-exact
        np.testing.assert_array_equal(back.time.values, _ds().time.values)


def test_deterministic_bytes(tmp_path):
    a = write_netcdf(_ds(), tmp_path / "a.nc", step="s")
    b = write_netcdf(_ds(), tmp_path / "b.nc", step="s")
    assert a.read_bytes() == b.read_bytes()


def test_missing_units_rejected_and_no_partial_file(tmp_path):
    ds = _ds()
    ds["bad"] = ("time", np.zeros(3))
    with pytest.raises(ValueError, match="bad"):
        write_netcdf(ds, tmp_path / "c.nc", step="s")
    assert list(tmp_path.iterdir()) == []
