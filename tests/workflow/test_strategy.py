"""Pulse strategy study (leopod.workflow.strategy): the grid as solution variants and the
table of Xu et al. (2023, Table 3).

Authorities: the campaign schema (each generated variant is validated like a hand-written
one), the layout of Xu et al. (2023, Table 3: rows a-priori sigma x R/T/N/3D, columns pulse
interval), and the workflow's own dry run (jobs per POD line).
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from leopod.settings import read_yaml
from leopod.workflow.config import validated
from leopod.workflow.strategy import GridCell, strategy_table, strategy_variants, variant_name
from leopod.workflow.variants import variant_config

REPO = Path(__file__).resolve().parents[2]
DEFAULT = REPO / "config" / "config.yaml"


def test_variant_names_are_schema_names_and_readable():
    assert variant_name(GridCell(900.0, 1e-8, None)) == "i900s1em08"
    assert variant_name(GridCell(3600.0, 2e-5, 1e-9)) == "i3600s2em05e1em09"
    assert re.fullmatch(r"[A-Za-z0-9]+", variant_name(GridCell(360.0, 1e-4, 1e-7)))


def test_each_cell_is_a_valid_variant_that_changes_only_its_keys():
    raw = read_yaml(DEFAULT)
    campaign = validated(read_yaml(DEFAULT))
    grid = strategy_variants(campaign["pod"], [360, 900], [1e-5, 1e-8], [1e-9])
    assert len(grid) == 4
    raw["variants"] = {name: keys for name, (_, keys) in grid.items()}
    cfg = variant_config(raw, "i360s1em08e1em09")
    assert cfg["pod"]["pulse_interval_s"] == 360.0
    assert cfg["pod"]["pulse_sigma_m_s"] == [1e-8] * 3
    assert cfg["pod"]["forces"]["empirical"]["sigma"] == 1e-9
    # the rest of the forces as in the campaign (a variant replaces the whole 'forces' key)
    for key in set(campaign["pod"]["forces"]) - {"empirical"}:
        assert cfg["pod"]["forces"][key] == campaign["pod"]["forces"][key], key
    assert cfg["ambiguity"] == campaign["ambiguity"]


def test_an_empirical_grid_needs_empirical_accelerations():
    pod = {"pulse_interval_s": 900.0, "forces": {"gravity": {}}}
    with pytest.raises(ValueError, match="empirical"):
        strategy_variants(pod, [900], [1e-6], [1e-9])


def test_the_table_has_the_layout_of_table_3():
    # a comparison of two intervals x two sigmas with known means: each value lands in the
    # row (sigma, figure) and the column of its interval in minutes
    cells = {variant_name(c): c for c in (GridCell(i, s, None) for i in (360.0, 900.0)
                                          for s in (1e-5, 1e-8))}
    figures = ["reference_r_rms_cm", "reference_3d_rms_cm"]
    columns, values = [], []
    for k, name in enumerate(cells):
        for stat in ("mean", "std"):
            columns.append((f"sat_{name}", "fixed_pod", stat))
            values.append([k + 0.1, k + 0.3] if stat == "mean" else [0.0, 0.0])
    comparison = pd.DataFrame(np.array(values).T, index=figures,
                              columns=pd.MultiIndex.from_tuples(columns))
    table = strategy_table(comparison, "sat", cells, "fixed_pod",
                           figures=[*figures, "slr_std_cm"])
    assert list(table.columns) == [6.0, 15.0]
    # sigmas from loose to tight as in the paper, figures in the order asked
    assert [i[0] for i in table.index] == [1e-5, 1e-5, 1e-8, 1e-8]
    assert [i[2] for i in table.index] == figures * 2
    k = list(cells).index(variant_name(GridCell(900.0, 1e-8, None)))
    assert table.loc[(1e-8, np.nan, "reference_3d_rms_cm"), 15.0] == pytest.approx(k + 0.3)
    with pytest.raises(ValueError, match="float_pod"):
        strategy_table(comparison, "sat", cells, "float_pod")


def test_the_study_runs_the_grid_as_one_campaign(tmp_path):
    # two cells on the first day of the default campaign: its own line and two variants
    proc = subprocess.run(
        [sys.executable, "-m", "leopod.workflow.strategy", str(DEFAULT), "--directory",
         str(tmp_path), "--intervals", "900", "--sigmas", "1e-6", "1e-8", "--days", "1",
         "--dry-run"], capture_output=True, text=True, timeout=600, cwd=REPO)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    overlay = yaml.safe_load((tmp_path / "strategy.yaml").read_text())
    assert list(overlay["variants"]) == ["i900s1em06", "i900s1em08"]
    assert overlay["end_date"] == validated(read_yaml(DEFAULT))["start_date"]
    stats = dict(re.findall(r"^(\w+)\s+(\d+)$", proc.stdout, flags=re.M))
    assert stats["float_pod"] == stats["fixed_pod"] == "3"
    assert stats["simulate"] == "1" and stats["variant_comparison"] == "1"
