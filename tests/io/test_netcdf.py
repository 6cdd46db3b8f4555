"""The netCDF writer: metadata, explicit time encoding, lossless round trip, atomic failure."""

import datetime as dt
import json

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


@pytest.fixture
def job(tmp_path):
    """A workflow job declared to the writers (leopod.io.provenance), undeclared after."""
    from leopod.io.provenance import JobProvenance, file_sha256, set_job

    (tmp_path / "abc.txt").write_bytes(b"abc")
    job = JobProvenance(rule="float_pod", script="scripts/float_pod.py",
                        settings=json.dumps({"pod": {"elevation_mask_deg": 7.0}}),
                        inputs=(str(tmp_path / "abc.txt"),), config_sha256="0" * 64,
                        references="Peng et al. (2021)", institution="Some University",
                        started="2019-01-01T00:00:00Z")
    set_job(job)
    yield job
    set_job(None)
    file_sha256.cache_clear()


def test_a_job_s_files_carry_cf_attributes_settings_inputs_and_config_hash(tmp_path, job):
    # CF-1.10 sec. 2.6.2 global attributes and the standard name "time" (CF Standard Name
    # Table); SHA-256 of "abc" = ba7816bf...15ad (FIPS 180-2, appendix B.1 example)
    with xr.open_dataset(write_netcdf(_ds(), tmp_path / "a.nc", step="float_pod")) as back:
        attrs = back.attrs
        assert back.time.attrs["standard_name"] == "time"
    assert attrs["Conventions"] == "CF-1.10" and attrs["source"].startswith("leopod ")
    assert attrs["title"] == "leopod float_pod product"
    assert attrs["history"] == (f"2019-01-01T00:00:00Z: {attrs['source']}, Snakemake rule "
                                "float_pod (script scripts/float_pod.py)")
    assert attrs["references"] == "Peng et al. (2021)"
    assert json.loads(attrs["leopod_settings"]) == {"pod": {"elevation_mask_deg": 7.0}}
    assert json.loads(attrs["leopod_inputs"]) == {str(tmp_path / "abc.txt"): (
        "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad")}
    assert attrs["leopod_config_sha256"] == "0" * 64
    assert attrs["institution"] == "Some University"       # the campaign's, not a placeholder


def test_outside_a_job_the_history_has_no_time_and_no_job_attributes(tmp_path):
    with xr.open_dataset(write_netcdf(_ds(), tmp_path / "a.nc", step="s")) as back:
        assert back.attrs["history"].endswith(" s")
        assert not [k for k in back.attrs if k.startswith("leopod_")]
        assert "institution" not in back.attrs             # nobody named: none written


def test_the_history_time_is_source_date_epoch_or_now(monkeypatch):
    # SOURCE_DATE_EPOCH 1546300800 = 2019-01-01 00:00:00 UTC (reproducible-builds spec)
    from leopod.io.provenance import JobProvenance

    def started():
        return JobProvenance(rule="r", script="s", settings="{}", inputs=(),
                             config_sha256="").started

    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1546300800")
    assert started() == "2019-01-01T00:00:00Z"
    monkeypatch.delenv("SOURCE_DATE_EPOCH")
    now = dt.datetime.now(dt.UTC)
    stamp = dt.datetime.strptime(started(), "%Y-%m-%dT%H:%M:%SZ").replace(tzinfo=dt.UTC)
    assert abs((stamp - now).total_seconds()) < 5
