"""``leopod init``: the campaign template, the satellite catalogue and the product sets.

Authorities: the campaign schema (the written file conforms), the product catalogue (every
family written exists), the GRACE Level-1B vector products in ../shared (antenna and reflector
offsets, MANIFEST.md), the published tables of Peng et al. (2021, Table I: HY-2B) and Jiang et
al. (2023, Table 1: HY-2D), and the IGS antenna-model periods (leopod.workflow.init).
"""

from __future__ import annotations

import datetime as dt
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

from leopod.download.catalogue import Catalogue
from leopod.workflow.config import campaign_problems, read_campaign, validated
from leopod.workflow.downloads import resolve_downloads
from leopod.workflow.init import PRODUCT_SETS, antex_family, campaign_text, read_satellites

REPO = Path(__file__).resolve().parents[2]
CATALOGUE = Catalogue.from_yaml(REPO / "config" / "catalogue.yaml")
SATELLITES = read_satellites(REPO / "config" / "satellites.yaml")
LEOPOD = str(Path(sys.executable).with_name("leopod"))
DAY = dt.date(2007, 3, 21)


def _write(tmp_path: Path, **kwargs) -> tuple[Path, list[str]]:
    args = dict(name="c", satellite="grace-a", start=DAY, end=DAY) | kwargs
    text, notes = campaign_text(args.pop("name"), args.pop("satellite"), args.pop("start"),
                                args.pop("end"), catalogue=CATALOGUE, satellites=SATELLITES,
                                **args)
    path = tmp_path / "c.yaml"
    path.write_text(text)
    return path, notes


@pytest.mark.parametrize("products, system, day", [
    ("cod", "G", DAY), ("cod-osb", "GE", dt.date(2023, 7, 8)), ("grg", "G", DAY),
    ("wum", "GC", dt.date(2023, 7, 8)), ("whu", "G", dt.date(2008, 10, 5))])
def test_every_product_set_gives_a_conforming_campaign_of_catalogue_families(
        tmp_path, products, system, day):
    path, _ = _write(tmp_path, products=products, system=system, start=day, end=day)
    raw = read_campaign(path)
    assert campaign_problems(raw) == []
    config, families = resolve_downloads(validated(raw), CATALOGUE)
    assert set(PRODUCT_SETS[products].families.values()) <= set(families)
    assert config["pod"]["system"] == (system if len(system) == 1 else list(system))
    assert set(config["signals"]) == set(system)
    # AR products exactly for the sets that carry them: fixed_pod is planned only then
    assert bool(config["products"]["wl_bias"] or config["products"]["osb"]) == (
        products != "cod")


def test_grace_a_gets_its_l1b_offsets_and_download_families(tmp_path):
    path, notes = _write(tmp_path)
    text = path.read_text()
    config = validated(read_campaign(path))
    sat = config["satellites"]["grace-a"]
    assert sat["observations"] == "download:grace_a_obs"
    assert sat["antenna_pco_body_m"] == {"L1": [-0.0004, -0.0004, -0.4514],
                                         "L2": [-0.0004, -0.0004, -0.4756]}
    assert config["products"]["antex"] == "download:antex_igs05_1402"
    assert config["products"]["gnss_clock"] == "download:cod_clock"
    # commented for a human: where the values come from, what to run next
    assert "VGN1B" in text and "leopod check" in text and text.count("\n#") >= 5
    assert notes == ["product set cod has no AR product: the campaign computes the float "
                     "orbit only (no fixed_pod)"]


def _l1b_vector(path: Path) -> list[np.ndarray]:
    """Magnitude x unit vector of each record of a GRACE L1B vector product (VGN1B, VSL1B)."""
    body = path.read_text().split("END OF HEADER", 1)[1].split("\n")
    return [float(f[2]) * np.array(f[3:6], float) for f in map(str.split, body) if len(f) > 6]


@pytest.mark.shared
@pytest.mark.parametrize("sat, letter", [("grace-a", "A"), ("grace-b", "B")])
def test_grace_offsets_are_those_of_the_l1b_vector_products(shared_data, sat, letter):
    folder = shared_data / "grace_l1b_fixture_2003-09-14"
    l1, l2 = _l1b_vector(folder / f"VGN1B_2003-09-14_{letter}_00.asc")
    (lra,) = _l1b_vector(folder / f"VSL1B_2003-09-14_{letter}_00.asc")
    facts = SATELLITES[sat]
    np.testing.assert_allclose(facts["antenna_pco_body_m"]["L1"], l1, atol=5e-5)
    np.testing.assert_allclose(facts["antenna_pco_body_m"]["L2"], l2, atol=5e-5)
    np.testing.assert_allclose(facts["retro_offset_body_m"], lra, atol=5e-5)
    mass = float((folder / f"MAS1B_2003-09-14_{letter}_00.asc").read_text()
                 .split("END OF HEADER", 1)[1].split()[6])
    assert abs(facts["mass_kg"] - mass) < 0.05


def test_hy2_offsets_are_the_published_tables():
    # Peng et al. (2021) Table I [mm], mechanical frame: phase centres and LRA minus centre
    # of mass (1383.44, 6.85, 2.35)
    com = np.array([1383.44, 6.85, 2.35])
    hy2b = SATELLITES["hy-2b"]
    for key, table in (("L1", [346.74, -179.75, -1375.25]), ("L2", [347.34, -177.75, -1396.65])):
        np.testing.assert_allclose(hy2b["antenna_pco_body_m"][key],
                                   (np.array(table) - com) / 1000, atol=5e-5)
    np.testing.assert_allclose(hy2b["retro_offset_body_m"],
                               (np.array([311.29, -215.43, 986.53]) - com) / 1000, atol=5e-5)
    # Jiang et al. (2023) Table 1 [m] and the flip threshold of its section 2
    hy2d = SATELLITES["hy-2d"]
    assert hy2d["antenna_pco_body_m"] == {
        "L1": [-0.9802, -0.1772, -1.3832], "L2": [-0.9800, -0.1763, -1.4018],
        "B1C": [-0.9000, 0.1824, -1.3842], "B2a": [-0.8989, 0.1826, -1.4114]}
    assert hy2d["attitude"] == "yaw_steering"
    assert hy2d["yaw_steering"]["flip_beta_deg"] == -1.5


def test_a_satellite_unknown_to_the_catalogue_gets_placeholders_that_check_names(tmp_path):
    path, notes = _write(tmp_path, satellite="MySat-1", products="wum", system="G",
                         start=dt.date(2015, 6, 1), end=dt.date(2015, 6, 2))
    assert any("not in the satellite catalogue" in n for n in notes)
    assert any("antenna_pco_body_m: unknown" in n for n in notes)
    assert any("products.antex: no ANTEX family" in n for n in notes)   # IGS08 era
    proc = subprocess.run([LEOPOD, "check", str(path), "-d", str(tmp_path)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert ("satellites.mysat-1.observations: 2 file(s) missing: rinex/mysat-1_2015152.rnx"
            in proc.stdout)


def test_antex_follows_the_igs_antenna_model_of_the_days():
    d = dt.date
    assert antex_family("cod", d(2007, 3, 21), d(2007, 3, 23)) == "antex_igs05_1402"
    assert antex_family("whu", d(2008, 10, 5), d(2008, 10, 5)) == "antex_igs05_1627"
    assert antex_family("cod", d(2022, 11, 27), d(2023, 1, 1)) == "antex_igs20"
    assert antex_family("cod", d(2022, 11, 26), d(2022, 11, 27)) is None   # IGS14 -> IGS20
    assert antex_family("cod", d(2011, 4, 17), d(2011, 4, 17)) is None     # IGS08


@pytest.mark.parametrize("args, message", [
    (["--start", "2007-3-21"], "--start/--end: Invalid isoformat string"),
    (["--products", "igs"], "--products igs: unknown product set (known: cod, cod-osb"),
    (["--system", "C"], "--system C: product set cod covers G only"),
    (["--end", "2007-03-20"], "--end 2007-03-20 is before --start 2007-03-21"),
])
def test_init_refuses_bad_arguments_with_one_line(tmp_path, args, message):
    base = {"--satellite": "grace-a", "--start": "2007-03-21", "--end": "2007-03-21"}
    base.update(zip(args[::2], args[1::2]))
    proc = subprocess.run([LEOPOD, "init", "c", "-d", str(tmp_path),
                           *[x for kv in base.items() for x in kv]],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert message in proc.stderr and len(proc.stderr.splitlines()) == 1
    assert not (tmp_path / "c.yaml").exists()


def test_init_does_not_replace_a_campaign_without_force(tmp_path):
    cmd = [LEOPOD, "init", "c", "--satellite", "grace-b", "--start", "2010-07-27", "--end",
           "2010-07-27", "-d", str(tmp_path)]
    assert subprocess.run(cmd, capture_output=True, timeout=120).returncode == 0
    (tmp_path / "c.yaml").write_text("kept")
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2 and "exists (use --force" in proc.stderr
    assert (tmp_path / "c.yaml").read_text() == "kept"
    assert subprocess.run([*cmd, "--force"], capture_output=True, timeout=120).returncode == 0
    assert yaml.safe_load((tmp_path / "c.yaml").read_text())["satellites"]["grace-b"][
        "observations"] == "download:grace_b_obs"
