"""The yaw-flip campaign of Jiang et al. (2023) (issue 22): maps per attitude mode and the orbit
across the flip, for a finished run of config/hy2d-sim.yaml + config/hy2d-sim-flip.yaml.

HY-2D flips by 180° about +Z when β crosses −1.5°; in the simulated campaign that happens at
2021-07-14 18:01:43 (``satellites.hy2d-sim.yaw_flips`` of the overlay). Printed:

- per code and attitude mode, the estimated code-bias map (nodes with at least
  ``code_bias.min_count`` observations) minus the simulated truth of that mode (the maps without
  a ``yaw_branch`` plus those of the mode's branch of the yaw-steering law; mode 0 is the
  branch at the first epoch), as RMS about the mean and the mean (the map's datum is a zero
  mean, the truth's is not), and the map's own RMS;
- per code, mode 0 minus mode 1 over the nodes both modes fill, beside the same difference of
  the truths, the RMS of the two differences' difference and their correlation, and beside
  the truth minus the truth turned by 180° in azimuth: maps estimated in a frame that missed
  the flip would differ between the modes by about that much;
- per solution (float, fixed), orbit minus truth [cm] around the flip: the R/T/N RMS in the
  2 h before and after, the change of the 10-min mean across the flip, the 10-s step of the
  difference at the flip against the largest step of the arc; and, for the fixed orbit, the
  change of the 10-min mean across every 10-min boundary of the arc (RMS and largest), the
  scale of that statistic without a flip.

    .venv/bin/snakemake --cores 2 --directory ../hy2d-flip \\
        --configfile config/hy2d-sim.yaml config/hy2d-sim-flip.yaml
    .venv/bin/python benchmarks/yaw_flip.py ../hy2d-flip
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.codebias.products import grid_of, node_vector
from leopod.frames.leo_attitude import YawSteering, below_flip, beta_angle_ef
from leopod.simulate.code_bias_map import CodeBiasMap
from leopod.validation.compare import difference_rtn
from leopod.workflow.campaign import campaign_days, code_bias_periods
from leopod.workflow.config import load_campaign

REPO = Path(__file__).resolve().parents[1]
CONFIGS = (REPO / "config" / "hy2d-sim.yaml", REPO / "config" / "hy2d-sim-flip.yaml")
TEN_MIN = np.timedelta64(10, "m")


def _truths(cfg: dict, first_below_flip: bool) -> dict:
    """(signal, mode) -> the simulated map of that attitude mode (a function of az, el)."""
    maps = [CodeBiasMap.from_config(m) for m in cfg["simulate"]["code_bias_maps"]]
    branch = {0: "below_flip" if first_below_flip else "above_flip"}
    branch[1] = "above_flip" if first_below_flip else "below_flip"

    def truth(signal, mode):
        parts = [m for m in maps if m.signal == signal and m.yaw_branch in (None, branch[mode])]
        return lambda az, el: sum(m(az, el) for m in parts)

    return {(m.signal, mode): truth(m.signal, mode) for m in maps for mode in (0, 1)}


def _maps(results: Path, cfg: dict, sat: str, truths: dict) -> None:
    (period,) = code_bias_periods(cfg)
    maps = xr.load_dataset(results / "code_bias" / sat / f"{period}.nc")
    grid = grid_of(maps)
    az, el = grid.node_directions()
    min_count = cfg["code_bias"]["min_count"]
    for sig in map(str, maps.signal.values):
        est = {}
        for mode in map(int, maps.mode.values):
            v = node_vector(maps, sig, mode)
            n = grid.from_grid(maps["count"].sel(signal=sig, mode=mode).values)
            ok = np.isfinite(v) & (n >= min_count)
            err = v[ok] - truths[sig, mode](az[ok], el[ok])
            est[mode] = (v, ok)
            print(f"{sig} mode {mode}: {ok.sum()} nodes >= {min_count} obs ({int(n.sum())} obs), "
                  f"map - truth RMS {100 * np.std(err):.2f} cm (mean {100 * err.mean():+.2f} cm), "
                  f"map RMS {100 * np.std(v[ok]):.2f} cm")
        if len(est) == 2:
            (v0, ok0), (v1, ok1) = est[0], est[1]
            both = ok0 & ok1
            a, e = az[both], el[both]
            d_est = v0[both] - v1[both]
            d_true = truths[sig, 0](a, e) - truths[sig, 1](a, e)
            turned = truths[sig, 0](a, e) - truths[sig, 0](a + 180.0, e)
            print(f"{sig}: mode 0 - mode 1 over {both.sum()} nodes: RMS {100 * np.std(d_est):.2f} "
                  f"cm, of the truths {100 * np.std(d_true):.2f} cm, their difference "
                  f"{100 * np.std(d_est - d_true):.2f} cm, correlation "
                  f"{np.corrcoef(d_est, d_true)[0, 1] if np.std(d_true) > 0 else np.nan:.2f}; "
                  f"truth - truth turned by 180 deg: "
                  f"{100 * np.std(turned):.2f} cm")


def _mean_change(t: np.ndarray, x: np.ndarray, epoch) -> np.ndarray:
    """Mean of ``x`` in the 10 min after ``epoch`` minus the mean in the 10 min before."""
    before = (t >= epoch - TEN_MIN) & (t < epoch)
    after = (t > epoch) & (t <= epoch + TEN_MIN)
    return x[after].mean(0) - x[before].mean(0)


def _orbits(results: Path, truth: xr.Dataset, sat: str, days: list[str], flip) -> None:
    for solution in ("float_pod", "fixed_pod"):
        for day in days:
            d = difference_rtn(xr.load_dataset(results / solution / sat / f"{day}_orbit.nc"),
                               truth)
            t, x = d.time.values, 100 * d.diff_rtn_m.values
            if not t[0] < flip < t[-1]:
                continue
            window = np.timedelta64(2, "h")

            def rms(m):
                return np.round(np.sqrt(np.mean(x[m] ** 2, axis=0)), 2)

            k = np.searchsorted(t, flip)
            print(f"{solution} {day}: R/T/N RMS 2 h before {rms((t >= flip - window) & (t < flip))}"
                  f", after {rms((t > flip) & (t <= flip + window))} cm; 10-min mean after - "
                  f"before {np.round(_mean_change(t, x, flip), 3)} cm; 10-s step at the flip "
                  f"{np.round(np.abs(x[k] - x[k - 1]), 3)}, largest of the arc "
                  f"{np.round(np.abs(np.diff(x, axis=0)).max(0), 3)} cm; arc 3D RMS "
                  f"{np.sqrt(np.mean(np.sum(x ** 2, 1))):.2f} cm")
            if solution == "fixed_pod":
                edges = np.arange(t[0] + TEN_MIN, t[-1] - TEN_MIN, TEN_MIN)
                jumps = np.array([_mean_change(t, x, e) for e in edges])
                print(f"fixed_pod {day}: 10-min mean after - before at {len(edges)} boundaries of "
                      f"the arc: RMS {np.round(np.sqrt(np.mean(jumps ** 2, 0)), 3)}, largest "
                      f"{np.round(np.abs(jumps).max(0), 3)} cm")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="working directory of the finished campaign")
    args = parser.parse_args()
    cfg = load_campaign(*CONFIGS)
    (sat,) = cfg["satellites"]
    (flip,) = (np.datetime64(e, "ns") for e in cfg["satellites"][sat]["yaw_flips"])
    days = campaign_days(cfg)
    results = args.run / "results" / cfg["campaign"]
    resources = args.run / "resources" / cfg["campaign"] / "simulate" / sat
    truth = xr.concat([xr.load_dataset(resources / f"{d}_truth.nc")[["pos_itrf_m", "vel_itrf_m_s"]]
                       for d in days], "time").drop_duplicates("time")
    first = truth.isel(time=[0])
    beta = beta_angle_ef(first.time.values, first.pos_itrf_m.values, first.vel_itrf_m_s.values)
    law = YawSteering.from_config(cfg["satellites"][sat]["yaw_steering"])
    _maps(results, cfg, sat, _truths(cfg, bool(below_flip(beta[0], law))))
    _orbits(results, truth, sat, days, flip)


if __name__ == "__main__":
    main()
