"""Satellite code and phase biases (Bias-SINEX OSBs, CODE DCBs) removed from the observations.

One function, :func:`signal_corrections_m`, turns a day's bias products into the correction of
every satellite and signal; :func:`correct_signal_biases` removes it from a stretch of
observations, each epoch with the products of its own day (arcs of ~30 h take their first and
last hours from the neighbouring days, whose biases may differ: the products are joined at
midnight). The quality, POD and ambiguity steps call the same two functions.

Sign convention (Schaer 2016, Bias-SINEX 1.00; the comment block of CODE's ``.BIA`` files):
a bias is **subtracted** from the observation it belongs to::

    C1C_corrected = C1C − OSB(C1C),   L1C_corrected = L1C − OSB(L1C)

and a differential code bias is the difference of the OSBs, ``DCB(P1−C1) = OSB(C1W) −
OSB(C1C)`` (:mod:`leopod.io.dcb`); the IGS convention for receivers that report C1 (IGS
``p1c1bias.hist``, "cc2noncc") is accordingly ``C1 → C1 + DCB(P1−C1)``, which makes C1
"compatible with modern P1".

Two modes, because the satellite clock and the ambiguity-resolution product already contain
the biases of the clock-reference signals (e.g. GPS C1W/C2W, the
``SATELLITE_CLOCK_REFERENCE_OBSERVABLES`` of the Bias-SINEX description):

``absolute`` (the AR product is the Bias-SINEX file itself)
    Every code loses its full code OSB and, when the product has phase OSBs, every phase its
    phase OSB; the ionosphere-free code OSB of the clock-reference pair is zero by the
    product's datum, so the clock is untouched, and the wide-lane and narrow-lane ambiguities
    of the corrected observations are integers: the ambiguity step must then not apply the
    OSBs a second time (:func:`leopod.ambiguity.products.ar_product`, ``osb_applied``).
    A code without its own OSB (GPS C1C in WHU's 2008 file) takes
    ``OSB(C1C) = OSB(C1W) − DCB(P1−C1)`` from a DCB file.
``clock_reference`` (CNES/CLS wide-lane biases with integer clocks, or no AR product)
    Every code is brought to the clock-reference code of its band,
    ``correction = OSB(code) − OSB(reference)`` (from the OSB file, else
    ``−DCB(reference−code)`` from a DCB file), so the WL product, which is defined with the
    reference codes, applies unchanged; the reference codes and the phases are left alone
    (phase biases are in the integer clocks and the WL product).

Observations of a satellite whose correction is unknown (no OSB nor DCB for it while the
product has the signal for other satellites) are set to NaN: they would keep their bias.

Not corrected: the code-only a-priori orbit of the ingest step (metre level, refined by the
POD) and receiver biases (common to all satellites, absorbed by the receiver clock and the
single differences).
"""

from __future__ import annotations

import logging
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from leopod.constants import C_LIGHT_M_S
from leopod.io.bias_sinex import osb, read_bias_sinex
from leopod.io.dcb import read_code_dcb
from leopod.time.calendar import parse_date_id

__all__ = ["CLOCK_REFERENCE_CODES", "DCB_SIGNALS", "MODES", "SignalBiasProduct",
           "SignalBiases", "correct_signal_biases", "read_signal_biases", "signal_bias_mode",
           "signal_corrections_m"]

log = logging.getLogger(__name__)

#: Clock-reference code pair per system when the OSB file does not declare it
#: (``SATELLITE_CLOCK_REFERENCE_OBSERVABLES``): the pairs of the IGS/CODE/WHU GPS clocks and of
#: the BDS-3 B1C/B2a products.
CLOCK_REFERENCE_CODES = {"G": ("C1W", "C2W"), "C": ("C1P", "C5P")}

#: DCB type of a CODE file -> (minuend, subtrahend) RINEX 3 codes: ``DCB(X−Y) = OSB(X) −
#: OSB(Y)``. P1 is the GPS P(Y) code tracked semi-codeless (C1W), C1 the C/A code (C1C).
DCB_SIGNALS = {"P1-C1": ("C1W", "C1C")}

#: Correction modes (module docstring).
MODES = ("absolute", "clock_reference")

_HALF_DAY = np.timedelta64(43200, "s")


def signal_bias_mode(*, wl_bias: bool, osb: bool) -> str:
    """The correction mode of a campaign (module docstring).

    Parameters
    ----------
    wl_bias, osb : bool
        Whether the campaign has a CNES/CLS WL product / a Bias-SINEX file.

    Returns
    -------
    str
        ``absolute`` if the AR product is the Bias-SINEX file (``products.osb`` without
        ``products.wl_bias``, see :func:`leopod.ambiguity.products.ar_product`), else
        ``clock_reference``.
    """
    return "absolute" if osb and not wl_bias else "clock_reference"


@dataclass(frozen=True)
class SignalBiasProduct:
    """The bias products of one day.

    Attributes
    ----------
    day : str
        Day ``YYYY-DDD`` the products belong to.
    osb : xarray.Dataset or None
        Bias-SINEX file (:func:`leopod.io.bias_sinex.read_bias_sinex`).
    dcb : tuple of xarray.Dataset
        CODE DCB files (:func:`leopod.io.dcb.read_code_dcb`), types of :data:`DCB_SIGNALS`.
    source : str
        The files, for logs and attributes.
    """

    day: str
    osb: xr.Dataset | None = None
    dcb: tuple[xr.Dataset, ...] = ()
    source: str = ""

    @classmethod
    def read(cls, day: str, osb_path=None, dcb_paths: Sequence = ()) -> SignalBiasProduct:
        """Read the OSB file (optional) and the DCB files of ``day``."""
        dcb = tuple(read_code_dcb(p) for p in dcb_paths)
        for p, ds in zip(dcb_paths, dcb, strict=True):
            if ds.attrs["dcb_type"] not in DCB_SIGNALS:
                raise ValueError(f"{p}: DCB type {ds.attrs['dcb_type']} is not supported for "
                                 f"code corrections (supported: {', '.join(DCB_SIGNALS)})")
        files = [str(p) for p in ([osb_path] if osb_path else []) + list(dcb_paths)]
        return cls(day=day, osb=read_bias_sinex(osb_path) if osb_path else None, dcb=dcb,
                   source=" ".join(files))

    @property
    def start(self) -> np.datetime64:
        """00:00 of the day (GPS time)."""
        return np.datetime64(parse_date_id(self.day), "ns")

    def reference_codes(self, system: str) -> tuple[str, ...]:
        """Clock-reference codes of ``system``: the codes among the OSB file's
        ``SATELLITE_CLOCK_REFERENCE_OBSERVABLES``, else :data:`CLOCK_REFERENCE_CODES` (also
        when the file declares phases only, as WHU's 2008 file does for its phase clocks,
        ``G L1C L2W``)."""
        key = f"satellite_clock_reference_observables_{system}"
        if self.osb is not None and self.osb.attrs.get(key):
            codes = tuple(c for c in self.osb.attrs[key].split() if c[0] == "C")
            if codes:
                return codes
        return CLOCK_REFERENCE_CODES.get(system, ())

    def has_osb(self, signal: str, system: str) -> bool:
        """True if the OSB file has satellite records of ``signal`` for ``system``."""
        if self.osb is None:
            return False
        ds = self.osb
        return bool(((ds["bias_type"] == "OSB") & (ds["obs1"] == signal) & (ds["station"] == "")
                     & ds["prn"].str.startswith(system)).any())

    def osb_m(self, sv: str, signal: str, epoch) -> float:
        """OSB [m] of ``sv``/``signal`` at ``epoch``; a code without an OSB record is derived
        from a DCB (``OSB(C1C) = OSB(C1W) − DCB(P1−C1)``); NaN if neither exists."""
        value = self._file_osb(sv, signal, epoch)
        if np.isnan(value) and signal[0] == "C":
            for ds in self.dcb:
                minuend, subtrahend = DCB_SIGNALS[ds.attrs["dcb_type"]]
                if subtrahend == signal:
                    return self._file_osb(sv, minuend, epoch) - _dcb_m(ds, sv)
        return value

    def relative_m(self, sv: str, signal: str, reference: str, epoch) -> float:
        """``OSB(signal) − OSB(reference)`` [m] from the OSB file, else ``−DCB(reference −
        signal)`` from a DCB file; NaN if neither gives it."""
        if self.osb is not None:
            value = self._file_osb(sv, signal, epoch) - self._file_osb(sv, reference, epoch)
            if np.isfinite(value):
                return value
        for ds in self.dcb:
            if DCB_SIGNALS[ds.attrs["dcb_type"]] == (reference, signal):
                return -_dcb_m(ds, sv)
        return np.nan

    def knows(self, signal: str, reference: str | None, system: str) -> bool:
        """True if the products relate ``signal`` (to ``reference`` when given) for
        ``system`` at all (whatever the satellite)."""
        if self.has_osb(signal, system) and (reference is None
                                             or self.has_osb(reference, system)):
            return True
        for ds in self.dcb:
            minuend, subtrahend = DCB_SIGNALS[ds.attrs["dcb_type"]]
            if subtrahend == signal and (reference is None or minuend == reference) and (
                    reference is not None or self.has_osb(minuend, system)):
                return True
        return False

    def _file_osb(self, sv, signal, epoch) -> float:
        if self.osb is None:
            return np.nan
        try:
            return osb(self.osb, sv, signal, epoch)
        except KeyError:
            return np.nan


def _dcb_m(ds: xr.Dataset, sv: str) -> float:
    """Satellite DCB [m] of ``sv`` (NaN if the file has none)."""
    if sv not in ds["sv"].values:
        return np.nan
    return float(ds["dcb_s"].sel(sv=sv)) * C_LIGHT_M_S


def signal_corrections_m(product: SignalBiasProduct, svs: Sequence[str],
                         signals: Sequence[str], epoch, *, mode: str,
                         observed: Mapping[str, set] | None = None) -> xr.DataArray:
    """Correction of every satellite and signal [m], to be **subtracted** from the observation.

    Parameters
    ----------
    product : SignalBiasProduct
        The day's bias products.
    svs : sequence of str, shape (s,)
        Satellites (``G05``); the system is the first letter.
    signals : sequence of str, shape (k,)
        RINEX 3 codes (``C1C``) and phases (``L1C``) of the observations.
    epoch : datetime64
        Epoch at which the products are evaluated (GPS time).
    mode : {"absolute", "clock_reference"}
        Module docstring.
    observed : mapping of str to set of str, optional
        Signals each system has observations of: a code left uncorrected is warned about
        only if observed (a combined receiver's dataset holds every system's signals, most of
        them empty for the other systems). None: warn for every signal.

    Returns
    -------
    xarray.DataArray, (sv, signal)
        ``corrected = observed − correction`` [m] (Schaer 2016). Zero where the mode leaves
        the signal alone (reference codes and phases in ``clock_reference`` mode; phases or
        codes the product has for no satellite of the system, with a warning for codes);
        NaN where the product has the signal but not for that satellite.

    Raises
    ------
    ValueError
        If ``mode`` is unknown.
    """
    if mode not in MODES:
        raise ValueError(f"unknown signal-bias mode {mode!r} (known: {', '.join(MODES)})")
    svs, signals = [str(s) for s in svs], [str(c) for c in signals]
    out = np.zeros((len(svs), len(signals)))
    for system in sorted({s[0] for s in svs}):
        rows = [i for i, s in enumerate(svs) if s[0] == system]
        refs = product.reference_codes(system)
        for k, signal in enumerate(signals):
            if mode == "absolute":
                if not product.knows(signal, None, system):
                    if signal[0] == "C" and product.osb is not None and (
                            observed is None or signal in observed.get(system, ())):
                        log.warning("%s: no OSB (nor DCB) of %s %s: code left uncorrected",
                                    product.source, system, signal)
                    continue
                for i in rows:
                    out[i, k] = product.osb_m(svs[i], signal, epoch)
            else:
                if signal[0] != "C" or signal in refs:
                    continue
                reference = next((r for r in refs if r[1] == signal[1]), None)
                if reference is None or not product.knows(signal, reference, system):
                    if observed is not None and signal not in observed.get(system, ()):
                        continue
                    log.warning("%s: nothing relates %s %s to the clock-reference code of its "
                                "band (%s): code left uncorrected", product.source or "no "
                                "bias product", system, signal, " ".join(refs) or "none")
                    continue
                for i in rows:
                    out[i, k] = product.relative_m(svs[i], signal, reference, epoch)
    return xr.DataArray(out, dims=("sv", "signal"), coords={"sv": svs, "signal": signals},
                        attrs={"units": "m", "long_name": f"signal bias correction ({mode}); "
                               "corrected = observed - correction"})


@dataclass(frozen=True)
class SignalBiases:
    """The bias products of the days of a stretch of observations (an arc) and the mode.

    Attributes
    ----------
    products : dict
        Day ``YYYY-DDD`` -> :class:`SignalBiasProduct` (days whose products exist).
    mode : str
        :data:`MODES`.
    central_day : str
        Day whose products replace those of a day that has none (arc ends at campaign ends).
    fallbacks : list of str
        Days whose epochs were corrected with the central day's products (filled by
        :meth:`for_day`; each also logged as a warning).
    """

    products: Mapping[str, SignalBiasProduct]
    mode: str
    central_day: str
    fallbacks: list = field(default_factory=list)

    @property
    def osb_applied(self) -> bool:
        """True if the Bias-SINEX OSBs are removed from codes and phases (``absolute``)."""
        return self.mode == "absolute" and any(p.osb is not None
                                               for p in self.products.values())

    def for_day(self, day: str) -> SignalBiasProduct:
        """Products of ``day``, else (with a warning) those of the central day."""
        if day in self.products:
            return self.products[day]
        if self.central_day not in self.products:
            raise KeyError(f"no signal-bias products for {day} nor for the central day "
                           f"{self.central_day}")
        log.warning("no bias products for %s: the central day's (%s) are used for its "
                    "epochs", day, self.central_day)
        self.fallbacks.append(day)
        return self.products[self.central_day]


def read_signal_biases(inputs: Mapping, spec: Mapping | None) -> SignalBiases | None:
    """Read the bias products a step's job lists.

    Parameters
    ----------
    inputs : mapping
        The job's inputs; ``signal_bias_osb`` and ``signal_bias_dcb`` are lists of paths
        (Bias-SINEX, CODE DCB), one per entry of ``spec["osb_days"]`` / ``spec["dcb_days"]``.
    spec : mapping or None
        ``mode``, ``central_day``, ``osb_days``, ``dcb_days``
        (:func:`leopod.workflow.campaign.signal_bias_inputs`).

    Returns
    -------
    SignalBiases or None
        None if there is no spec or no file (nothing is corrected).

    Raises
    ------
    ValueError
        If the lists of files and days differ in length, or a DCB file is of a type other
        than those of :data:`DCB_SIGNALS`.
    leopod.io._text.FormatError
        If a file is malformed (message naming file, line and field).
    """
    if not spec:
        return None
    osb_paths = list(inputs.get("signal_bias_osb") or [])
    dcb_paths = list(inputs.get("signal_bias_dcb") or [])
    osb_days, dcb_days = list(spec.get("osb_days", [])), list(spec.get("dcb_days", []))
    if len(osb_paths) != len(osb_days) or len(dcb_paths) != len(dcb_days):
        raise ValueError(f"signal-bias inputs and days differ: OSB {osb_paths} for "
                         f"{osb_days}, DCB {dcb_paths} for {dcb_days}")
    if not osb_paths and not dcb_paths:
        return None
    days = sorted(set(osb_days) | set(dcb_days))
    products = {}
    for day in days:
        osb_path = osb_paths[osb_days.index(day)] if day in osb_days else None
        dcbs = [p for p, d in zip(dcb_paths, dcb_days, strict=True) if d == day]
        products[day] = SignalBiasProduct.read(day, osb_path, dcbs)
    return SignalBiases(products, spec["mode"], spec["central_day"])


def correct_signal_biases(obs: xr.Dataset, biases: SignalBiases | None,
                          signals: Sequence[str]) -> tuple[xr.Dataset, dict]:
    """Remove the satellite signal biases from ``obs``, each epoch with its own day's products.

    Parameters
    ----------
    obs : xarray.Dataset
        Observations on (time, sv) in metres (ingest schema; codes ``C..``, phases ``L..``).
    biases : SignalBiases or None
        Products and mode (None: ``obs`` is returned unchanged).
    signals : sequence of str
        The signals to correct (those present in ``obs``; others are skipped).

    Returns
    -------
    corrected : xarray.Dataset
        Copy of ``obs`` (attribute ``signal_biases`` on every corrected variable and on the
        dataset).
    summary : dict
        Per signal: ``rms_m`` (RMS of the applied correction), ``dropped`` (observations set
        to NaN for want of a correction); ``days`` -> the product day used per day.

    Notes
    -----
    The products of a day are evaluated at the middle of the day's observed epochs (daily
    OSB windows and monthly DCBs are constant over the day; a sub-daily product is taken at
    that one epoch).
    """
    if biases is None:
        return obs, {}
    present = [s for s in dict.fromkeys(signals) if s in obs.data_vars]
    times = obs["time"].values.astype("datetime64[ns]")
    svs = [str(s) for s in obs["sv"].values]
    day_start = times.astype("datetime64[D]").astype("datetime64[ns]")
    out = obs.copy()
    new = {s: obs[s].transpose("time", "sv").values.copy() for s in present}
    corr_all = {s: np.zeros(0) for s in present}
    summary: dict = {"days": {}}
    for start in np.unique(day_start):
        rows = day_start == start
        day = str(start.astype("datetime64[D]").item().strftime("%Y-%j"))
        product = biases.for_day(day)
        summary["days"][day] = product.day
        epoch = (times[rows][0] + (times[rows][-1] - times[rows][0]) / 2
                 if product.day == day else product.start + _HALF_DAY)
        observed: dict = {}
        for s in present:
            for j in np.flatnonzero(np.isfinite(new[s][rows]).any(axis=0)):
                observed.setdefault(svs[j][0], set()).add(s)
        corr = signal_corrections_m(product, svs, present, epoch, mode=biases.mode,
                                    observed=observed)
        for k, s in enumerate(present):
            values = new[s][rows]
            c = corr.values[:, k][None, :]
            new[s][rows] = values - c
            have = np.isfinite(values)
            corr_all[s] = np.concatenate([corr_all[s], np.broadcast_to(c, values.shape)[have]])
    text = (f"satellite signal biases removed ({biases.mode}, Bias-SINEX sign: corrected = "
            f"observed - bias); products "
            + " ".join(f"{d}<-{p}" for d, p in summary["days"].items()))
    for s in present:
        before = np.isfinite(obs[s].transpose("time", "sv").values)
        dropped = int((before & ~np.isfinite(new[s])).sum())
        out[s] = obs[s].transpose("time", "sv").copy(data=new[s])
        out[s].attrs = {**obs[s].attrs, "signal_biases": text}
        c = corr_all[s][np.isfinite(corr_all[s])]
        summary[s] = {"rms_m": float(np.sqrt(np.mean(c**2))) if c.size else 0.0,
                      "dropped": dropped}
        if dropped:
            log.warning("signal biases: %d %s observations without a bias correction set to "
                        "NaN", dropped, s)
        log.info("signal biases (%s) on %s: RMS of the correction %.3f m", biases.mode, s,
                 summary[s]["rms_m"])
    out.attrs["signal_biases"] = text
    return out, summary
