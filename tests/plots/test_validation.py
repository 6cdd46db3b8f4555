"""Figures of the orbit validation: PNGs written, byte-identical on reruns, robust to NaN."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from leopod.plots.validation import (
    plot_daily_statistics,
    plot_overlaps,
    plot_reference_differences,
)
from leopod.validation.orbit_statistics import COMPONENTS, orbit_statistics

pytestmark = pytest.mark.filterwarnings("error")

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"   # PNG specification (ISO/IEC 15948), section 5.2


def _summary(scale: float, pairs=("2023-01-02", "2023-01-03", "2023-01-04")) -> xr.Dataset:
    """Overlap summary in the overlap_summary schema with RMS growing per component."""
    rms = scale * np.array([[0.004, 0.012, 0.006, 0.015], [0.005, 0.02, 0.007, 0.022],
                            [np.nan] * 4])[: len(pairs)]
    good = rms[np.isfinite(rms).all(axis=1)]
    comp = ("pair", "component")
    return xr.Dataset({"rms_m": (comp, rms), "mean_m": (comp, 0.1 * rms), "std_m": (comp, rms),
                       "campaign_rms_mean_m": ("component", good.mean(axis=0)),
                       "campaign_rms_std_m": ("component", good.std(axis=0))},
                      coords={"pair": list(pairs), "component": list(COMPONENTS)})


def _differences(scale: float) -> xr.Dataset:
    """Two days at 60 s of R/T/N differences with a gap."""
    t = np.datetime64("2023-01-01T00:00", "ns") + np.arange(2 * 1440) * np.timedelta64(60, "s")
    rng = np.random.default_rng(3)
    d = scale * rng.normal(0.0, [0.01, 0.03, 0.015], (t.size, 3))
    d[300:400] = np.nan
    return xr.Dataset({"diff_rtn_m": (("time", "rtn"), d)},
                      coords={"time": t, "rtn": ["R", "T", "N"]})


def _check_png(path) -> bytes:
    data = path.read_bytes()
    assert data.startswith(PNG_SIGNATURE)
    assert len(data) > 5_000
    return data


def test_overlap_figure_float_and_fixed(tmp_path):
    sols = {"float": _summary(1.0), "fixed": _summary(0.8, pairs=("2023-01-02", "2023-01-03"))}
    first, second = tmp_path / "a.png", tmp_path / "b.png"
    plot_overlaps(sols, first, title="L47 2023-001/003")
    plot_overlaps(sols, second, title="L47 2023-001/003")
    assert _check_png(first) == _check_png(second)


def test_overlap_figure_single_solution(tmp_path):
    plot_overlaps(_summary(1.0), tmp_path / "one.png")
    _check_png(tmp_path / "one.png")
    with pytest.raises(ValueError, match="no solutions"):
        plot_overlaps({}, tmp_path / "none.png")


def test_reference_difference_series(tmp_path):
    sols = {"float": _differences(1.0), "fixed": _differences(0.6)}
    plot_reference_differences(sols, tmp_path / "diff.png", title="L47")
    plot_reference_differences(_differences(1.0), tmp_path / "diff1.png")
    _check_png(tmp_path / "diff.png")
    _check_png(tmp_path / "diff1.png")


def test_daily_statistics_bars(tmp_path):
    sols = {"float": orbit_statistics(_differences(1.0)),
            "fixed": orbit_statistics(_differences(0.6))}
    first, second = tmp_path / "a.png", tmp_path / "b.png"
    plot_daily_statistics(sols, first)
    plot_daily_statistics(sols, second)
    assert _check_png(first) == _check_png(second)
