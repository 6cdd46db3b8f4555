"""Figures of the code-bias maps: PNGs written and deterministic, orientation of Peng et al. (2021),
robust to empty maps and a single signal, statistics of the map difference."""

from __future__ import annotations

import struct

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr

from leopod.plots import codebias

pytestmark = pytest.mark.filterwarnings("error")

SIGNALS = ["C1C", "C2W"]
MODES = [0, 1]
STEP_DEG = 5.0
MIN_COUNT = 200
BAND_DEG = 10.0


def _maps(signals=SIGNALS, modes=MODES, seed: int = 3) -> xr.Dataset:
    """Synthetic map Dataset in the layout of leopod.codebias on a 5° × 5° grid.

    value = 0.3 m · cos(az) · cos(el) (+ 5 cm per mode, + noise); the 90° row repeats one
    zenith value; counts fall towards the rim and below ``MIN_COUNT`` under 10° elevation and
    in the azimuth sector 180–215° (empty, value NaN).
    """
    rng = np.random.default_rng(seed)
    el = np.arange(0.0, 90.0 + STEP_DEG / 2, STEP_DEG)
    az = np.arange(0.0, 360.0, STEP_DEG)
    shape = (len(signals), len(modes), el.size, az.size)
    e, a = np.meshgrid(np.radians(el), np.radians(az), indexing="ij")
    value = (0.3 * np.cos(a) * np.cos(e))[None, None] + rng.normal(0.0, 0.01, shape)
    value += 0.05 * np.arange(len(modes))[None, :, None, None]
    value[:, :, -1, :] = value[:, :, -1, :1]  # the zenith node, repeated for every azimuth
    count = np.broadcast_to((50.0 + 2000.0 * np.sin(e)).astype(int), shape).copy()
    count[:, :, :, 36:43] = 120
    count[:, :, -1, :] = count[:, :, -1, :1]
    empty = count < MIN_COUNT
    value[empty] = np.nan
    sigma = np.where(empty, np.nan, 0.5 / np.sqrt(count))
    bands = np.arange(0.0, 90.0, BAND_DEG)
    rms_before = np.broadcast_to(0.9 - 0.008 * bands, (len(signals), bands.size))
    dims = ("signal", "mode", "elevation_deg", "azimuth_deg")
    band_dims = ("signal", "el_band_deg")
    return xr.Dataset(
        {"value_m": (dims, value), "sigma_m": (dims, sigma), "count": (dims, count),
         "empty": (dims, empty), "mp_rms_before_m": (band_dims, rms_before),
         "mp_rms_after_m": (band_dims, 0.5 * rms_before),
         "mp_mean_before_m": (band_dims, -0.1 * rms_before),
         "mp_mean_after_m": (band_dims, 0.0 * rms_before),
         "mp_rms_all_before_m": ("signal", np.full(len(signals), 0.6)),
         "mp_rms_all_after_m": ("signal", np.full(len(signals), 0.3))},
        coords={"signal": signals, "mode": modes, "elevation_deg": el, "azimuth_deg": az,
                "el_band_deg": bands},
        attrs={"period": "2021-04", "satellite": "HY2B", "az_step_deg": STEP_DEG,
               "el_step_deg": STEP_DEG, "min_count": MIN_COUNT, "band_width_deg": BAND_DEG})


def _samples(signals=SIGNALS, n: int = 50_000) -> dict:
    """MP samples per signal: el uniform in [0, 90) deg, MP ~ N(0, 0.6 m) before, halved after."""
    rng = np.random.default_rng(7)
    out = {}
    for signal in signals:
        el = rng.uniform(0.0, 90.0, n)
        before = rng.normal(0.0, 0.6, n)
        before[::97] = np.nan
        out[signal] = (el, before, 0.5 * before)
    return out


def _all_empty(maps: xr.Dataset) -> xr.Dataset:
    out = maps.copy(deep=True)
    out["empty"][:] = True
    out["count"][:] = 0
    out["value_m"][:] = np.nan
    out["sigma_m"][:] = np.nan
    return out


def _png_size(data: bytes) -> tuple[int, int]:
    """Width and height from the IHDR chunk (PNG specification, ISO/IEC 15948, 11.2.2)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert data[12:16] == b"IHDR"
    return struct.unpack(">II", data[16:24])


PLOTS = {
    "maps": lambda m, p: codebias.plot_code_bias_maps(m, p, title="HY2B 2021-04"),
    "sigma": lambda m, p: codebias.plot_code_bias_maps(m, p, title="HY2B", field="sigma_m",
                                                       units="mm"),
    "counts": lambda m, p: codebias.plot_code_bias_counts(m, p, title="HY2B 2021-04"),
    "difference": lambda m, p: codebias.plot_map_difference(
        m, _maps(list(m.signal.values), list(m.mode.values), seed=4), p, title="A − B"),
    "mp": lambda m, p: codebias.plot_mp_elevation(_samples(list(m.signal.values)), m, p,
                                                  title="HY2B 2021-04"),
}


@pytest.mark.parametrize("kind", ["maps", "counts", "difference", "mp"])
def test_png_written_deterministic(kind, tmp_path):
    maps = _maps()
    first, second = tmp_path / "a.png", tmp_path / "b.png"
    PLOTS[kind](maps, first)
    PLOTS[kind](maps, second)
    data = first.read_bytes()
    width, height = _png_size(data)
    # 2 × 2 panels (or two MP panels) at 110 dpi: several hundred pixels each way
    assert 500 <= width <= 2000 and 400 <= height <= 2000
    assert len(data) > 20_000
    assert data == second.read_bytes()
    assert plt.get_fignums() == []  # the figure was closed


@pytest.mark.parametrize("kind", ["maps", "sigma", "counts", "difference", "mp"])
def test_all_empty_map_and_single_signal(kind, tmp_path):
    single = _maps(signals=["C1W"], modes=[0])
    PLOTS[kind](single, tmp_path / "single.png")
    PLOTS[kind](_all_empty(single), tmp_path / "empty.png")
    for name in ("single.png", "empty.png"):
        assert _png_size((tmp_path / name).read_bytes())[0] > 300


def test_azimuth_clockwise_from_top():
    fig = codebias._maps_figure(_maps(), title="", field="value_m", units="cm")
    ax = fig.axes[0]
    assert ax.get_theta_offset() == pytest.approx(np.pi / 2)
    assert ax.get_theta_direction() == -1
    # geometry: in display coordinates (y up) azimuth 0° at zenith distance 45° lies straight
    # above the centre and azimuth 90° straight to its right (Peng et al. 2021, Figs. 7–11
    # orientation)
    fig.canvas.draw()
    centre, north, east = ax.transData.transform([(0.0, 0.0), (0.0, 45.0), (np.pi / 2, 45.0)])
    up, right = north - centre, east - centre
    assert up[1] > 0 and abs(up[0]) < 1e-6 * up[1]
    assert right[0] > 0 and abs(right[1]) < 1e-6 * right[0]
    assert right[0] == pytest.approx(up[1], rel=1e-9)
    # the rim is the 0° elevation ring, the zenith at the centre
    assert ax.get_rmin() == 0.0 and ax.get_rmax() == pytest.approx(90.0)
    plt.close(fig)


def test_cells_centred_on_nodes_and_empty_blank():
    maps = _maps()
    fig = codebias._maps_figure(maps, title="", field="value_m", units="cm")
    mesh = fig.axes[0].collections[0]
    cells = mesh.get_array()
    node = maps.value_m.sel(signal="C1C", mode=0).transpose("elevation_deg", "azimuth_deg")
    # drawn cells are the node values in cm, masked exactly where the node is empty
    np.testing.assert_array_equal(np.ma.getmaskarray(cells).reshape(node.shape),
                                  maps.empty.sel(signal="C1C", mode=0).values)
    np.testing.assert_allclose(cells.filled(np.nan).reshape(node.shape), 100.0 * node.values,
                               rtol=1e-12)
    # geometry: the cell of azimuth node 0° spans −2.5° .. 2.5°, elevation node 5° spans
    # zenith distance 82.5° .. 87.5°; node 0° is clipped at the horizon, the zenith at 0
    theta, r = codebias._mesh(maps)
    np.testing.assert_allclose(np.degrees(theta[:2]), [-2.5, 2.5], atol=1e-12)
    np.testing.assert_allclose(r[:3], [90.0, 87.5, 82.5])
    assert r[-1] == 0.0 and r[-2] == pytest.approx(2.5)
    plt.close(fig)


def test_colour_scale_symmetric_and_shared_by_all_signals():
    # issue 23 item 5: the maps of the codes are compared, so every panel has one scale
    maps = _maps()
    fig = codebias._maps_figure(maps, title="", field="value_m", units="cm")
    meshes = [ax.collections[0] for ax in fig.axes if ax.name == "polar"]
    limits = {(m.norm.vmin, m.norm.vmax) for m in meshes}
    assert len(meshes) == 4 and len(limits) == 1
    (low, high), = limits
    assert low == -high > -100.0
    # independent computation: 98th percentile of |value| [cm] over the unique non-empty nodes
    # of all signals
    v = maps.value_m.values[..., :-1, :].ravel()                  # all rings but the zenith row
    v = np.concatenate([v, maps.value_m.values[..., -1, 0].ravel()])
    v = 100.0 * np.abs(v[np.isfinite(v)])
    assert high == pytest.approx(np.percentile(v, 98.0), rel=1e-12)
    assert sum(ax.name != "polar" for ax in fig.axes) == 1         # one colour bar
    plt.close(fig)


def test_counts_log_scale_over_non_empty_nodes():
    maps = _maps()
    fig = codebias._counts_figure(maps, title="")
    norm = fig.axes[0].collections[0].norm
    shown = maps["count"].where(~maps.empty)
    # one LogNorm from the smallest to the largest count of the non-empty nodes of all codes
    assert norm.__class__.__name__ == "LogNorm"
    assert norm.vmin == float(shown.min()) >= MIN_COUNT
    assert norm.vmax == float(shown.max())
    plt.close(fig)


def test_difference_statistics_hand_computed():
    maps = _maps(signals=["C1C"], modes=[0])
    shift = maps.copy(deep=True)
    # b = a − 0.02 m everywhere, plus +0.03 m at one ring node and at the zenith; one more
    # node empty in b only
    shift["value_m"] -= 0.02
    shift["value_m"][0, 0, 10, 5] += 0.03
    shift["value_m"][0, 0, -1, :] += 0.03
    shift["empty"][0, 0, 12, 7] = True
    a, b = codebias._common_maps(maps, shift)
    diff = codebias._difference(a, b) * 100.0
    mean, rms, n = codebias._difference_stats(diff.sel(signal="C1C", mode=0),
                                              codebias._unique_nodes(a))
    # analytic truth: unique common nodes n = non-empty ring nodes (zenith counted once) − 1;
    # differences b − a = −2 cm except two nodes at +1 cm
    n_nonempty = int((~maps.empty[0, 0, :-1]).sum()) + 1
    assert n == n_nonempty - 1
    d = np.full(n, -2.0)
    d[:2] = 1.0
    assert mean == pytest.approx(d.mean(), abs=1e-9)
    assert rms == pytest.approx(d.std(), abs=1e-9)


def test_difference_rejects_other_grid_and_no_common_signal():
    maps = _maps()
    with pytest.raises(ValueError, match="azimuth_deg"):
        codebias._common_maps(maps, maps.assign_coords(azimuth_deg=maps.azimuth_deg + 1.0))
    with pytest.raises(ValueError, match="share no"):
        codebias._common_maps(maps, maps.assign_coords(signal=["C1X", "C5X"]))


def test_difference_matches_labels_not_positions():
    maps = _maps()
    swapped = maps.isel(signal=[1, 0])
    a, b = codebias._common_maps(maps, swapped)
    diff = codebias._difference(a, b)
    # the same map with its signals in another order differs by exactly zero
    assert float(np.nanmax(np.abs(diff.values))) == 0.0


def test_mp_scatter_subsampled_deterministically():
    # arithmetic: 50 000 points with at most 20 000 shown -> every 3rd (16 667 points)
    assert codebias._subsample_step(50_000, 20_000) == 3
    assert codebias._subsample_step(20_000, 20_000) == 1
    assert codebias._subsample_step(0, 20_000) == 1
    fig = codebias._mp_figure(_samples(["C1C"]), _maps(), title="", max_points=20_000)
    ax = fig.axes[0]
    before = ax.collections[0].get_offsets()
    # every 3rd sample minus the NaN ones (every 97th, i.e. every 291st of the thinned set)
    assert before.shape == (16_667 - len(range(0, 50_000, 291)), 2)
    # band lines at band centres, RMS from the map dataset (first line: RMS before)
    np.testing.assert_allclose(ax.lines[0].get_xdata(), np.arange(5.0, 90.0, 10.0))
    assert "0.600 m before, 0.300 m after" in ax.get_title(loc="left")
    plt.close(fig)


def test_band_width_from_attributes_or_spacing():
    maps = _maps()
    assert codebias._band_width(maps) == BAND_DEG  # Dataset attribute
    maps["el_band_deg"].attrs["band_width_deg"] = 15.0
    assert codebias._band_width(maps) == 15.0  # the coordinate's attribute comes first
    del maps.attrs["band_width_deg"]
    del maps["el_band_deg"].attrs["band_width_deg"]
    assert codebias._band_width(maps) == BAND_DEG  # arithmetic: spacing of 0, 10, ..., 80


def test_mp_without_map_statistics_and_bad_input(tmp_path):
    samples = _samples(["C5X"], n=1000)
    codebias.plot_mp_elevation(samples, None, tmp_path / "mp.png")
    assert _png_size((tmp_path / "mp.png").read_bytes())[0] > 300
    with pytest.raises(ValueError, match="C5X"):
        codebias.plot_mp_elevation({"C5X": (np.ones(3), np.ones(3), np.ones(2))}, None,
                                   tmp_path / "bad.png")
    with pytest.raises(ValueError):
        codebias.plot_mp_elevation({}, None, tmp_path / "none.png")
    with pytest.raises(ValueError, match="units"):
        codebias.plot_code_bias_maps(_maps(), tmp_path / "m.png", units="inch")
