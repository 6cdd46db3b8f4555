"""The one netCDF writer of leopod: metadata, explicit time encoding, atomic writes.

Every intermediate product of the workflow goes through :func:`write_netcdf`, so that all files
carry the same provenance attributes, encode time the same way, are compressed losslessly and
never appear half-written (a failed step leaves no partial output).

Attributes follow the CF conventions 1.10 (Eaton et al. 2022, sec. 2.6.2 "Description of file
contents": ``Conventions``, ``title``, ``institution`` (a workflow job of a campaign that names
one), ``source``, ``history``, ``references``); the time coordinate carries the CF standard
name ``time`` (CF standard name table). Inside a workflow job (:mod:`leopod.io.provenance`) ``history`` holds the UTC time, the
rule and the script, and leopod's ``leopod_settings``, ``leopod_inputs`` and
``leopod_config_sha256`` are added.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterable
from pathlib import Path

import numpy as np
import xarray as xr

from leopod import __version__
from leopod.io._text import FormatError
from leopod.io.provenance import current_job

__all__ = ["write_netcdf", "TIME_UNITS", "atomic_path", "load_netcdf", "on_grid"]

#: Time encoding of every leopod netCDF file: float64 seconds since the GPS epoch (exact to
#: well below 1 ns over decades), so files are stable and independent of the first sample.
TIME_UNITS = "seconds since 1980-01-06 00:00:00"

_COMPRESSION = {"zlib": True, "complevel": 1, "shuffle": True}


class atomic_path:
    """Context manager yielding a temporary path that is renamed onto ``path`` on success.

    The temporary file lives in the destination folder so that the final ``os.replace`` is
    atomic; on any exception the temporary file is removed and ``path`` is left untouched.
    """

    def __init__(self, path: str | Path):
        self.path = Path(path)

    def __enter__(self) -> Path:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{self.path.name}.", suffix=".part",
                                   dir=self.path.parent)
        os.close(fd)
        self.tmp = Path(tmp)
        return self.tmp

    def __exit__(self, exc_type, exc, tb):
        if exc_type is None:
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(self.tmp, 0o666 & ~umask)   # mkstemp creates 0600; use normal permissions
            os.replace(self.tmp, self.path)
        else:
            self.tmp.unlink(missing_ok=True)
        return False


def write_netcdf(ds: xr.Dataset, path: str | Path, *, step: str,
                 inputs: Iterable[str | Path] = (), time_system: str | None = None,
                 reference_frame: str | None = None, title: str | None = None,
                 compress: bool = True) -> Path:
    """Write a Dataset with leopod's standard metadata and encoding, atomically.

    Parameters
    ----------
    ds : xarray.Dataset
        The product. Every data variable should carry ``units`` and ``long_name`` attributes;
        a ``ValueError`` names any that does not.
    path : str or Path
        Destination file.
    step : str
        Workflow step (rule name) that made the file, stored as ``processing_step`` (and in
        the default title).
    inputs : iterable of path
        Input files, stored (base names) as ``input_files`` for provenance.
    time_system : str, optional
        Time system of the ``time`` labels (e.g. ``"GPS"``); defaults to ``ds.attrs``.
    reference_frame : str, optional
        Reference frame of positions (e.g. ``"ITRF"``, ``"GCRF"``, ``"antenna"``).
    title : str, optional
        Human-readable title (CF ``title``; default: ``"leopod <step> product"``).
    compress : bool, optional
        Lossless compression of the numeric variables (default); False for a large file of
        doubles that hardly compress and is read once (compression would only cost time).

    Returns
    -------
    Path
        The written file.
    """
    # datetime variables get their units from the encoding (TIME_UNITS)
    missing = [name for name, var in ds.data_vars.items()
               if "long_name" not in var.attrs
               or ("units" not in var.attrs and not np.issubdtype(var.dtype, np.datetime64))]
    if missing:
        raise ValueError(f"{path}: variables without 'units'/'long_name': {missing}")
    out = ds.copy()
    attrs = dict(out.attrs)
    attrs.update({
        "Conventions": "CF-1.10",
        "title": title or attrs.get("title") or f"leopod {step} product",
        "source": f"leopod {__version__}",
        "processing_step": step,
        "input_files": " ".join(sorted(Path(p).name for p in inputs)),
        # outside a workflow job no wall-clock stamp: identical inputs give identical files
        "history": f"leopod {__version__} {step}",
    })
    job = current_job()
    if job is not None:
        attrs.update(job.netcdf_attributes())
    if time_system is not None:
        attrs["time_system"] = time_system
    if reference_frame is not None:
        attrs["reference_frame"] = reference_frame
    # netCDF has no bool attribute type: store flags as 0/1 integers
    out.attrs = {k: (int(v) if isinstance(v, (bool, np.bool_)) else v) for k, v in attrs.items()}
    if "time" in out.dims and np.issubdtype(out["time"].dtype, np.datetime64):
        out = out.assign_coords(time=out["time"].assign_attrs(standard_name="time"))
    encoding = {}
    for name, var in out.variables.items():
        enc = {}
        if np.issubdtype(var.dtype, np.datetime64):
            enc = {"units": TIME_UNITS, "calendar": "proleptic_gregorian", "dtype": "float64"}
        elif compress and var.dtype.kind in "fiub" and var.ndim > 0:
            enc = dict(_COMPRESSION)
        if var.dtype.kind == "b":
            out[name] = var.astype("i1")
        encoding[name] = enc
    with atomic_path(path) as tmp:
        out.to_netcdf(tmp, encoding=encoding, format="NETCDF4", engine="netcdf4")
    return Path(path)


def merge_days(datasets: list[xr.Dataset]) -> xr.Dataset:
    """Concatenate daily product datasets along time, dropping repeated epochs."""
    if len(datasets) == 1:
        return datasets[0]
    ds = xr.concat(datasets, dim="time", join="outer", data_vars="minimal", coords="minimal",
                   compat="override", combine_attrs="override")
    _, first = np.unique(ds.time.values, return_index=True)
    return ds.isel(time=np.sort(first))


def on_grid(times: np.ndarray, step_s: float) -> np.ndarray:
    """Epochs on a time grid of step ``step_s`` [s]: labels (datetime64) that are whole
    multiples of the step since 1970-01-01 (for a step that divides the day, e.g. 1, 10 or
    30 s: whole multiples since every midnight, as receivers sample).

    Returns
    -------
    ndarray of bool, shape of ``times``
    """
    ns = np.asarray(times).astype("datetime64[ns]").astype("int64")
    return ns % round(step_s * 1e9) == 0


def load_netcdf(path: str | Path, what: str = "netCDF", required: Iterable[str] = (), *,
                lazy: bool = False, step_s: float | None = None) -> xr.Dataset:
    """A netCDF file, loaded, with its ``required`` variables checked.

    A damaged file (e.g. an intermediate of an earlier run cut short or altered on disk) is
    refused with an error that names it and says what to do, instead of the HDF or xarray
    traceback. ``lazy``: open only (variables are read when used, so damage inside a variable's
    data shows only then), for files of which a step reads a few variables. ``step_s`` [s]:
    only the epochs of the ``time`` dimension on this grid (time labels that are multiples of
    it, :func:`on_grid`) are read, so that a step decimating high-rate data never holds the
    whole file (a 1-s day is 30 times its 30-s epochs).

    Raises
    ------
    FileNotFoundError
        If there is no such file.
    FormatError
        If it cannot be read as netCDF or lacks a required variable (``what`` names the kind
        of file in the message).
    """
    if not Path(path).is_file():
        raise FileNotFoundError(f"{path}: no such file")
    try:
        if step_s is None:
            ds = xr.open_dataset(path) if lazy else xr.load_dataset(path)
        else:
            full = xr.open_dataset(path)
            ds = full.isel(time=np.flatnonzero(on_grid(full.time.values, step_s)))
            if not lazy:
                ds = ds.load()
                full.close()
    except (OSError, ValueError, RuntimeError) as err:
        raise FormatError(path, None, "netCDF",
                          f"cannot read the {what} file ({err}); if an earlier run wrote "
                          "it, delete it and run the step again") from None
    missing = [name for name in required if name not in ds.variables]
    if missing:
        raise FormatError(path, None, missing[0],
                          f"not a {what} file: variables {missing} missing")
    return ds
