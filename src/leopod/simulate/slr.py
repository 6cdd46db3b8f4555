"""Simulated satellite laser ranging (SLR) normal points of a LEO from ILRS stations.

For every station the day is cut into normal-point bins aligned with 0 h UTC (ILRS normal
point rule); each bin gets one candidate epoch drawn uniformly inside the bin (stations report
the full-rate epoch nearest the mean of the bin). Candidates with the retro-reflector above
the elevation cut-off form passes (consecutive candidates less than ``pass_gap_s`` apart).
Weather and station schedules: a pass is tracked with the station's clear-sky probability,
and each bin of a tracked pass yields a normal point with ``bin_fill_probability``.
Meteorological data per pass: pressure and temperature of a standard atmosphere at the
station height (Berg 1948: ``P = 1013.25 (1 − 2.26e-5 h)^5.225`` hPa,
``T = 291.15 − 0.0065 h`` K) plus Gaussian variations, relative humidity around 60 %; all
rounded to the CRD 2 resolution (0.01 hPa, 0.01 K, 0.1 %) *before* the delay is computed, so
the CRD file reproduces the modelled delay exactly.

The written two-way time of flight is that of :func:`leopod.validation.slr_model.slr_range`
(light time with Earth rotation, Mendes–Pavlis troposphere with FCULa at the written
meteorological values, Shapiro delay) plus ``2 (bias + noise) / c``, with the station range
bias and white noise defined on the one-way range. The ranges start at the station's
reference point: the SINEX marker position plus the ILRS eccentricity
(:attr:`SlrStation.ecc_xyz_m`) plus the solid Earth tide and pole tide displacements at the
transmit epoch (:func:`leopod.validation.station_displacement.station_displacements`,
IERS Conventions 2010, sec. 7.1.1 and 7.1.4). The truth of each point is kept beside it.
Not simulated: ocean loading, retro-reflector signature, timing biases, outliers.

Epochs. The truth orbit is labelled in GPS time; normal points are transmit epochs in UTC
(CRD), converted with :func:`leopod.time.scales.utc_to_gps`.
"""

from __future__ import annotations

import datetime as _dt
import logging
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import erfa
import numpy as np
import xarray as xr

from leopod.constants import C_LIGHT_M_S, WGS84_A_M, WGS84_INV_F
from leopod.frames.leo_attitude import LeoAttitude
from leopod.io.crd_write import write_crd
from leopod.io.sinex_write import write_sinex_eccentricities, write_sinex_stations
from leopod.settings import Settings
from leopod.time.eop import EarthOrientation
from leopod.time.scales import gps_to_utc, utc_to_gps
from leopod.validation.slr_model import OrbitReflector, elevation_rad, slr_range
from leopod.validation.station_displacement import station_displacements

__all__ = ["DEFAULT_STATIONS", "SlrSettings", "SlrStation", "simulate_normal_points",
           "write_normal_points", "write_slr_files", "write_station_eccentricities",
           "write_station_sinex"]

logger = logging.getLogger(__name__)

_NS_PER_S = 1_000_000_000
_NS_PER_DAY = 86_400 * _NS_PER_S
#: Last transmit epoch kept before the end of the truth orbit [s] (> two-way light time).
_END_MARGIN_S = 0.1
#: Elevation margin of the first (light-time free) visibility screening [deg].
_SCREEN_MARGIN_DEG = 0.5
#: Standard atmosphere (Berg 1948): sea-level pressure [hPa], pressure scale 2.26e-5 /m,
#: exponent 5.225; sea-level temperature [K] and lapse rate [K/m].
_P0_HPA, _P_SCALE_PER_M, _P_EXP = 1013.25, 2.26e-5, 5.225
_T0_K, _LAPSE_K_M = 291.15, 0.0065
#: CRD 2 resolution of record 20 (pressure, temperature, humidity).
_MET_DECIMALS = (2, 2, 1)


@dataclass(frozen=True)
class SlrStation:
    """An ILRS laser ranging station of the simulated network.

    Attributes
    ----------
    pad_id : str
        CDP pad identifier (4 digits), e.g. "7090".
    code : str
        ILRS 4-character station code, e.g. "YARL".
    name : str
        Site name.
    domes : str
        DOMES number.
    pos_itrf_m : tuple of float
        Earth-fixed marker position [m] (SLRF2020 at 2020.0, rounded to 1 m; fixed in this
        world).
    clear_sky_probability : float
        Probability that a visible pass is tracked (weather and schedule), rough values.
    ecc_xyz_m : tuple of float
        Eccentricity from the marker to the system reference point, Earth-fixed XYZ [m].
    """

    pad_id: str
    code: str
    name: str
    domes: str
    pos_itrf_m: tuple[float, float, float]
    clear_sky_probability: float
    ecc_xyz_m: tuple[float, float, float] = (0.0, 0.0, 0.0)

    @property
    def reference_point_m(self) -> np.ndarray:
        """Marker plus eccentricity [m], shape (3,)."""
        return np.add(self.pos_itrf_m, self.ecc_xyz_m)


#: 16 ILRS stations: coordinates from SLRF2020_POS+VEL_2023.10.02.snx (ILRS) propagated to
#: 2020-01-01 and rounded to 1 m (7080 McDonald from its last SLRF2020 solution, ended 2015);
#: eccentricities (XYZ) valid on 2020-01-01 in the ILRS file ecc_xyz.snx of 2023-03-14 (zero
#: for the stations whose marker is the reference point).
#: The clear-sky (tracking) probabilities are rough guesses, higher for the productive LEO
#: trackers of Peng et al. (2021) Table IV (Yarragadee, Changchun, Greenbelt, Graz). They give ~600
#: normal points a day (~1400 if every visible bin were tracked); the real HY-2B tracking is
#: sparser (Peng et al. 2021, Table IV: ~10 600 NPs from 10 stations over several months, i.e. tens
#: per day): ``simulate.slr.clear_sky_probability: 0.05`` comes closer to it.
DEFAULT_STATIONS: tuple[SlrStation, ...] = (
    SlrStation("7090", "YARL", "Yarragadee", "50107M001",
               (-2389008.0, 5043330.0, -3078524.0), 0.7, (-1.2073, 2.5034, -1.5509)),
    SlrStation("7839", "GRZL", "Graz", "11001S002", (4194426.0, 1162694.0, 4647247.0), 0.5),
    SlrStation("7840", "HERL", "Herstmonceux", "13212S001", (4033463.0, 23663.0, 4924305.0), 0.4),
    SlrStation("7941", "MATM", "Matera", "12734S008", (4641978.0, 1393068.0, 4133250.0), 0.5),
    SlrStation("7110", "MONL", "Monument Peak", "40497M001",
               (-2386279.0, -4802354.0, 3444882.0), 0.5, (-1.2109, -2.4036, 1.7117)),
    SlrStation("7105", "GODL", "Greenbelt", "40451M105",
               (1130719.0, -4831351.0, 3994107.0), 0.5, (0.525, -2.3865, 1.9689)),
    SlrStation("7501", "HARL", "Hartebeesthoek", "30302M003",
               (5085401.0, 2668331.0, -2768688.0), 0.5, (2.5702, 1.3406, -1.4102)),
    SlrStation("7825", "STL3", "Mount Stromlo", "50119S003",
               (-4467065.0, 2683035.0, -3667007.0), 0.4),
    SlrStation("7237", "CHAL", "Changchun", "21611S001", (-2674387.0, 3757189.0, 4391508.0), 0.6),
    SlrStation("7810", "ZIML", "Zimmerwald", "14001S007", (4331283.0, 567550.0, 4633141.0), 0.4),
    SlrStation("8834", "WETL", "Wettzell", "14201S018", (4075576.0, 931786.0, 4801584.0), 0.4),
    SlrStation("7821", "SHA2", "Shanghai", "21605S010", (-2830745.0, 4676580.0, 3275073.0), 0.3),
    SlrStation("7080", "MDOL", "McDonald", "40442M006",
               (-1330021.0, -5328402.0, 3236481.0), 0.4, (-0.373, -1.471, 0.897)),
    SlrStation("7249", "BEIL", "Beijing", "21601S004", (-2148761.0, 4426759.0, 4044510.0), 0.3),
    SlrStation("7119", "HA4T", "Haleakala", "40445M004",
               (-5466066.0, -2404337.0, 2242109.0), 0.4, (-2.25, -0.9932, 0.9328)),
    SlrStation("7841", "POT3", "Potsdam", "14106S011", (3800432.0, 881692.0, 5029030.0), 0.3),
)


@dataclass(frozen=True)
class SlrSettings(Settings):
    """Settings of the simulated laser ranging (keys of ``simulate.slr`` in the campaign
    schema, which holds the defaults).

    Attributes
    ----------
    elevation_cut_off_deg : float
        Lowest elevation of a normal point [deg] (LEO tracking limits of ILRS stations are
        10–20°; 10° is a usual cut-off of LEO SLR validation).
    bin_s : float
        Normal-point bin [s]: ILRS nominal bin for 800–2000 km altitude (HY-2B, 970 km) is
        30 s (ILRS "Normal Point Data" page, table of bin sizes).
    noise_m : float
        White noise of a normal point on the one-way range [m].
    range_bias_m : Mapping[str, float]
        One-way range bias per CDP pad id [m] (stations not named: none).
    clear_sky_probability : float, optional
        Tracking probability of every pass; None uses each station's own value.
    bin_fill_probability : float
        Probability that a bin of a tracked pass yields a normal point.
    pass_gap_s : float
        Gap between visible candidates that starts a new pass [s].
    wavelength_nm : float
        Laser wavelength [nm] (frequency-doubled Nd:YAG).
    pressure_sigma_hpa, temperature_sigma_k : float
        Standard deviations of the per-pass deviations from the standard atmosphere.
    humidity_mean_pct, humidity_sigma_pct : float
        Relative humidity per pass ~ N(mean, sigma), clipped to [5, 100] %.
    satellite : str
        ILRS target name of the CRD H3 record.
    ilrs_id : str
        ILRS satellite id YYXXXPP (HY-2B: COSPAR 2018-081A -> 1808101).
    norad_id : int
        NORAD catalogue number (-1: written as "na").
    station_displacements : bool
        Displace the stations by the solid Earth tide and the pole tide.
    """

    elevation_cut_off_deg: float
    bin_s: float
    noise_m: float
    range_bias_m: Mapping[str, float]
    clear_sky_probability: float | None
    bin_fill_probability: float
    pass_gap_s: float
    wavelength_nm: float
    pressure_sigma_hpa: float
    temperature_sigma_k: float
    humidity_mean_pct: float
    humidity_sigma_pct: float
    satellite: str
    ilrs_id: str
    norad_id: int
    station_displacements: bool


# --------------------------------------------------------------------------- candidates
def _bin_epochs_utc(t_first_gps: np.datetime64, t_last_gps: np.datetime64, bin_ns: int,
                    n_stations: int, rng: np.random.Generator):
    """Bin starts (b,) and one candidate UTC epoch per station and bin (s, b), int ns."""
    utc = gps_to_utc(np.array([t_first_gps, t_last_gps])).astype(np.int64)
    day0 = utc[0] - utc[0] % _NS_PER_DAY
    k0 = -(-(utc[0] - day0) // bin_ns)
    k1 = (utc[1] - day0) // bin_ns
    starts = day0 + np.arange(k0, k1) * bin_ns
    offsets = rng.integers(0, bin_ns, size=(n_stations, starts.size))
    return starts, starts[None, :] + offsets


def _passes(time_ns: np.ndarray, visible: np.ndarray, gap_ns: int) -> list[np.ndarray]:
    """Indices (into the flattened station × bin arrays) of each pass, per station."""
    n_sta, n_bin = visible.shape
    out = []
    for s in range(n_sta):
        idx = np.flatnonzero(visible[s])
        if idx.size == 0:
            continue
        breaks = np.flatnonzero(np.diff(time_ns[s, idx]) > gap_ns) + 1
        out += [s * n_bin + part for part in np.split(idx, breaks)]
    out.sort(key=lambda p: (time_ns.flat[p[0]], p[0]))
    return out


def _standard_meteo(height_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Berg (1948) standard-atmosphere pressure [hPa] and temperature [K] at heights [m]."""
    pressure = _P0_HPA * (1.0 - _P_SCALE_PER_M * height_m) ** _P_EXP
    return pressure, _T0_K - _LAPSE_K_M * height_m


def _pass_meteo(height_m: np.ndarray, settings: SlrSettings, rng: np.random.Generator):
    """Rounded (pressure, temperature, humidity) per pass, each (n_pass,)."""
    p0, t0 = _standard_meteo(height_m)
    n = height_m.size
    pressure = p0 + rng.normal(0.0, settings.pressure_sigma_hpa, n)
    temperature = t0 + rng.normal(0.0, settings.temperature_sigma_k, n)
    humidity = np.clip(rng.normal(settings.humidity_mean_pct, settings.humidity_sigma_pct, n),
                       5.0, 100.0)
    return tuple(np.round(v, d) for v, d in zip((pressure, temperature, humidity), _MET_DECIMALS))


# ------------------------------------------------------------------------------ simulate
def simulate_normal_points(truth: xr.Dataset, retro_offset_body_m, *,
                           stations: Sequence[SlrStation] = DEFAULT_STATIONS,
                           settings: SlrSettings,
                           rng: np.random.Generator,
                           eop: EarthOrientation | None = None,
                           attitude: LeoAttitude | None = None) -> xr.Dataset:
    """Simulate the SLR normal points of a LEO over the span of its truth orbit.

    Parameters
    ----------
    truth : xarray.Dataset
        Coordinate ``time`` (datetime64[ns], GPS time), ``pos_itrf_m`` and ``vel_itrf_m_s``
        (time, xyz) [m, m/s]: ITRF centre-of-mass orbit, sampled densely enough for 10th-order
        Lagrange interpolation (≤ 60 s for a LEO).
    retro_offset_body_m : array_like, shape (3,)
        Retro-reflector offset from the centre of mass in the body frame [m].
    stations : sequence of SlrStation
        Station network (default :data:`DEFAULT_STATIONS`).
    settings : SlrSettings
    rng : numpy.random.Generator
        Source of all random draws (the result is a deterministic function of its state).
    eop : EarthOrientation, optional
        EOP of the station displacements (default: installed IERS data).
    attitude : LeoAttitude, optional
        Attitude law of the satellite (orients the reflector offset); None: nominal.

    Returns
    -------
    xarray.Dataset
        Dimension ``point`` ordered by pass and time, in the schema of
        :func:`leopod.io.crd_write.write_crd` (coordinate ``time`` = UTC transmit epoch, ``tof_s``,
        ``pass_id``, ``station``, ``station_name``, ``satellite``, ``ilrs_id``, ``norad_id``,
        ``wavelength_nm``, ``np_window_s``, ``epoch_event``, ``pressure_hpa``,
        ``temperature_k``, ``humidity_pct``) plus the truth: ``time_gps``, ``elevation_deg``,
        ``geometric_range_m``, ``tropo_delay_m``, ``relativity_delay_m``, ``range_bias_m``,
        ``noise_m`` (one-way [m]; ``c·tof/2`` is their sum), ``light_time_up_s``,
        ``pos_reflector_itrf_m`` (point, xyz) at the bounce epoch, ``pos_station_itrf_m``
        (point, xyz), the ranging reference point (marker + eccentricity + displacement) and
        ``station_displacement_itrf_m`` (point, xyz), its tide displacement.
    """
    reflector = OrbitReflector(truth, retro_offset_body_m, attitude=attitude)
    sta_pos = np.array([s.pos_itrf_m for s in stations], dtype=float)
    cand_utc, cand_s, visible = _candidates(reflector, truth, sta_pos, settings, rng)
    passes = _passes(cand_utc, visible, round(settings.pass_gap_s * _NS_PER_S))

    p_clear = np.array([s.clear_sky_probability if settings.clear_sky_probability is None
                        else settings.clear_sky_probability for s in stations])
    pass_sta = np.array([p[0] // cand_s.shape[1] for p in passes], dtype=int)
    tracked = rng.random(len(passes)) < p_clear[pass_sta]
    met = _pass_meteo(erfa.gc2gde(WGS84_A_M, 1.0 / WGS84_INV_F, sta_pos)[2][pass_sta],
                      settings, rng)
    flat = np.concatenate(passes) if passes else np.zeros(0, dtype=int)
    pid = np.repeat(np.arange(len(passes)), [p.size for p in passes])
    keep = tracked[pid] & (rng.random(flat.size) < settings.bin_fill_probability)
    noise = rng.normal(0.0, settings.noise_m, flat.size)
    flat, pid, noise = flat[keep], pid[keep], noise[keep]
    sta = pass_sta[pid]

    t_utc = cand_utc.ravel()[flat]
    ref_pos = np.array([s.reference_point_m for s in stations])[sta]
    disp = station_displacements(utc_to_gps(t_utc), ref_pos, eop=eop,
                                 solid_tide=settings.station_displacements,
                                 pole_tide=settings.station_displacements).total_m
    model = slr_range(cand_s.ravel()[flat], ref_pos + disp, reflector,
                      pressure_hpa=met[0][pid], temperature_k=met[1][pid],
                      humidity_pct=met[2][pid], wavelength_um=settings.wavelength_nm * 1e-3)
    bias = np.array([settings.range_bias_m.get(s.pad_id, 0.0) for s in stations])[sta]
    tof = 2.0 * (model.range_m + bias + noise) / C_LIGHT_M_S
    ds = _dataset(t_utc, model, tof, bias, noise, pid, sta, met, stations, settings)
    ds["pos_station_itrf_m"] = (("point", "xyz"), ref_pos + disp,
                                {"units": "m", "long_name": "ranging reference point incl. "
                                 "tide displacement (truth)"})
    ds["station_displacement_itrf_m"] = (("point", "xyz"), disp,
                                         {"units": "m", "long_name": "solid Earth and pole "
                                          "tide displacement of the station (truth)"})
    ds = _final_selection(ds, settings.elevation_cut_off_deg)
    _log_counts(ds, stations, len(passes), int(tracked.sum()))
    return ds


def _candidates(reflector: OrbitReflector, truth: xr.Dataset, sta_pos: np.ndarray,
                settings: SlrSettings, rng: np.random.Generator):
    """One candidate epoch per station and bin, and its visibility (centre of mass, no light
    time, cut-off lowered by a small margin).

    Returns
    -------
    cand_utc : ndarray of int, shape (s, b)
        UTC epochs [ns since 1970].
    cand_s : ndarray, shape (s, b)
        The same epochs in GPS seconds since ``reflector.t0``.
    visible : ndarray of bool, shape (s, b)
    """
    t_gps = truth["time"].values.astype("datetime64[ns]")
    end = t_gps[-1] - np.timedelta64(round(_END_MARGIN_S * _NS_PER_S), "ns")
    _, cand_utc = _bin_epochs_utc(t_gps[0], end, round(settings.bin_s * _NS_PER_S),
                                  len(sta_pos), rng)
    cand_s = reflector.seconds(utc_to_gps(cand_utc.ravel())).reshape(cand_utc.shape)
    inside = (cand_s >= 0.0) & (cand_s <= reflector.seconds(end)[0])
    pos_com, _ = reflector.centre_of_mass(np.where(inside, cand_s, 0.0).ravel())
    los = pos_com.reshape(cand_s.shape + (3,)) - sta_pos[:, None, :]
    el_deg = np.degrees(np.stack([elevation_rad(p, los[k]) for k, p in enumerate(sta_pos)]))
    return cand_utc, cand_s, inside & (el_deg >= settings.elevation_cut_off_deg
                                       - _SCREEN_MARGIN_DEG)


def _final_selection(ds: xr.Dataset, cut_off_deg: float) -> xr.Dataset:
    """Points at or above the cut-off, ordered by pass and time, passes numbered 0, 1, ..."""
    ds = ds.isel(point=np.flatnonzero(ds["elevation_deg"].values >= cut_off_deg))
    ds = ds.isel(point=np.lexsort((ds["time"].values, ds["pass_id"].values)))
    ds["pass_id"] = ("point", np.unique(ds["pass_id"].values, return_inverse=True)[1],
                     ds["pass_id"].attrs)
    return ds


def _dataset(time_utc_ns, model, tof, bias, noise, pid, sta, met,
             stations: Sequence[SlrStation], settings: SlrSettings) -> xr.Dataset:
    """Assemble the normal-point Dataset (unordered, before the final elevation screening)."""
    n = tof.size
    time_utc = np.asarray(time_utc_ns, dtype=np.int64).astype("datetime64[ns]")
    pad = np.array([s.pad_id for s in stations], dtype=str)
    code = np.array([s.code for s in stations], dtype=str)

    def var(values, units, title, dims=("point",)):
        return dims, values, {"units": units, "long_name": title}

    ds = xr.Dataset(
        {
            "tof_s": var(tof, "s", "two-way time of flight (simulated observation)"),
            "pass_id": var(pid.astype(np.int64), "1", "pass (CRD session) index"),
            "station": var(pad[sta], "1", "CDP pad id"),
            "station_name": var(code[sta], "1", "ILRS station code"),
            "satellite": var(np.full(n, settings.satellite), "1", "ILRS target name"),
            "ilrs_id": var(np.full(n, settings.ilrs_id), "1", "ILRS satellite id"),
            "norad_id": var(np.full(n, settings.norad_id, dtype=np.int64), "1",
                            "NORAD catalogue number (-1 = not available)"),
            "wavelength_nm": var(np.full(n, settings.wavelength_nm), "nm", "laser wavelength"),
            "np_window_s": var(np.full(n, settings.bin_s), "s", "normal point bin length"),
            "epoch_event": var(np.full(n, 2, dtype=np.int64), "1",
                               "CRD epoch event 2: ground transmit time"),
            "pressure_hpa": var(met[0][pid], "hPa", "surface pressure"),
            "temperature_k": var(met[1][pid], "K", "surface temperature"),
            "humidity_pct": var(met[2][pid], "percent", "relative humidity"),
            "time_gps": var(utc_to_gps(time_utc), "", "transmit epoch in GPS time (truth)"),
            "elevation_deg": var(np.degrees(model.elevation_rad), "degree",
                                 "geometric elevation of the uplink (truth)"),
            "geometric_range_m": var(model.geometric_range_m, "m",
                                     "vacuum one-way range, mean of the legs (truth)"),
            "tropo_delay_m": var(model.tropo_m, "m",
                                 "Mendes-Pavlis/FCULa one-way delay (truth)"),
            "relativity_delay_m": var(model.relativity_m, "m",
                                      "Shapiro one-way delay (truth)"),
            "range_bias_m": var(bias, "m", "station one-way range bias (truth)"),
            "noise_m": var(noise, "m", "one-way range noise (truth)"),
            "light_time_up_s": var(model.light_time.tau_up_s, "s", "uplink light time (truth)"),
            "pos_reflector_itrf_m": var(model.light_time.pos_reflector_m, "m",
                                        "ITRF reflector position at bounce (truth)",
                                        ("point", "xyz")),
        },
        coords={"time": ("point", time_utc), "xyz": ("xyz", ["x", "y", "z"])},
    )
    del ds["time_gps"].attrs["units"]
    ds.attrs.update({
        "title": f"simulated SLR normal points of {settings.satellite}",
        "time_system": "UTC (time); GPS (time_gps)",
        "reference_frame": "ITRF",
        "elevation_cut_off_deg": settings.elevation_cut_off_deg,
        "bin_s": settings.bin_s,
        "noise_m": settings.noise_m,
    })
    return ds


def _log_counts(ds: xr.Dataset, stations: Sequence[SlrStation], n_pass: int, n_tracked: int):
    codes, counts = np.unique(ds["station"].values, return_counts=True)
    per = ", ".join(f"{c}: {k}" for c, k in zip(codes, counts))
    logger.info("SLR: %d visible passes, %d tracked, %d normal points from %d of %d stations "
                "(%s)", n_pass, n_tracked, ds.sizes["point"], codes.size, len(stations), per)


# --------------------------------------------------------------------------------- files
def write_slr_files(nps: xr.Dataset, stations: Sequence[SlrStation], crd_path: str | Path,
                    sinex_path: str | Path, ref_epoch, ecc_path: str | Path | None = None) -> None:
    """Write normal points as CRD 2, the station coordinates and eccentricities as SINEX.

    Parameters
    ----------
    nps : xarray.Dataset
        From :func:`simulate_normal_points` (only the CRD fields are written).
    stations : sequence of SlrStation
        Stations to list in the SINEX files (marker positions fixed, no velocity).
    crd_path, sinex_path : str or Path
        Output files.
    ref_epoch : datetime64 or str
        Reference epoch of the SINEX positions (UTC).
    ecc_path : str or Path, optional
        Eccentricity SINEX (:func:`write_station_eccentricities`); not written if None.
    """
    write_normal_points(nps, crd_path, ref_epoch)
    write_station_sinex(stations, sinex_path, ref_epoch)
    if ecc_path is not None:
        write_station_eccentricities(stations, ecc_path)


def write_normal_points(nps: xr.Dataset, crd_path: str | Path, ref_epoch) -> None:
    """Write normal points as CRD 2.

    The CRD H1 production time is set to the hour of the last normal point (``ref_epoch``
    when there is none), not the wall clock, so that the file is reproducible.
    """
    last = nps["time"].values.max() if nps.sizes["point"] else np.datetime64(ref_epoch, "ns")
    production = np.datetime64(last, "h").astype(_dt.datetime)
    write_crd(nps, crd_path, version=2, production_time=production)


def write_station_sinex(stations: Sequence[SlrStation], sinex_path: str | Path,
                        ref_epoch) -> None:
    """Write the station coordinates (fixed, no velocity) at ``ref_epoch`` (UTC) as SINEX."""
    created = np.datetime64(ref_epoch, "s").astype(_dt.datetime)  # reproducible header
    write_sinex_stations(_stations_dataset(stations, ref_epoch), sinex_path, technique="L",
                         created=created)


def write_station_eccentricities(stations: Sequence[SlrStation],
                                 ecc_path: str | Path) -> None:
    """Write the stations' eccentricities (XYZ, valid for all epochs) as a SINEX file.

    Read back with :func:`leopod.io.sinex.read_sinex_eccentricities`; together with the
    marker positions of :func:`write_station_sinex` they give the ranging reference points.
    """
    ds = xr.Dataset(
        {"site": ("record", np.array([s.pad_id for s in stations], dtype=str)),
         "ref_system": ("record", np.full(len(stations), "XYZ")),
         "ecc_m": (("record", "component"), np.array([s.ecc_xyz_m for s in stations],
                                                     dtype=float).reshape(-1, 3))})
    write_sinex_eccentricities(ds, ecc_path)


def _stations_dataset(stations: Sequence[SlrStation], ref_epoch) -> xr.Dataset:
    """Dataset of :func:`leopod.io.sinex_write.write_sinex_stations` for a station list."""
    pos = np.array([s.pos_itrf_m for s in stations], dtype=float)
    lon, lat, h = erfa.gc2gde(WGS84_A_M, 1.0 / WGS84_INV_F, pos)
    n = len(stations)
    return xr.Dataset(
        {
            "site": ("solution", np.array([s.pad_id for s in stations], dtype=str)),
            "domes": ("solution", np.array([s.domes for s in stations], dtype=str)),
            "description": ("solution", np.array([f"{s.name[:17]} {s.code}"
                                                  for s in stations], dtype=str)),
            "approx_lon_deg": ("solution", np.degrees(lon)),
            "approx_lat_deg": ("solution", np.degrees(lat)),
            "approx_height_m": ("solution", h),
            "pos_m": (("solution", "xyz"), pos),
            "ref_epoch": ("solution", np.full(n, np.datetime64(ref_epoch, "ns"))),
        },
        coords={"xyz": ["x", "y", "z"]},
    )
