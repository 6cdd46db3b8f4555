"""A new campaign file from a template (``leopod init``): inputs by download family.

The campaign names every input as ``download:<family>`` of the product catalogue
(``config/catalogue.yaml``), so the ``download_<family>`` rules fetch them; the satellite's
antenna offsets, reflector offset, attitude law and a-priori mass come from the satellite
catalogue (``config/satellites.yaml``) when it knows the satellite. The file is commented for
a human and conforms to the campaign schema.

Product sets (``--products``) are the combinations of catalogue families that belong together
(orbits, clocks and, for ambiguity resolution, the biases of the same clock solution):

======== ======================================================= ====================
set      families                                                ambiguity resolution
======== ======================================================= ====================
cod      cod_orbit, cod_clock                                    no (float only)
cod-osb  cod_orbit, cod_clock, cod_osb                           code + phase OSBs
grg      grg_orbit, grg_clock, grg_wl_bias                       WL biases + integer clocks
wum      wum_orbit, wum_clock, wum_osb                           code + phase OSBs
whu      cod_orbit, whu_phase_clock, whu_abs_bias, cod_p1c1_dcb  code + phase OSBs
======== ======================================================= ====================

The ANTEX family follows the IGS antenna model of the day: IGS05 (GPS weeks 1400 to 1631,
2006-11-05 to 2011-04-16; the week-1402 version named by CODE's 2007 clock files, the
week-1627 one by the 2008 WHU products) and IGS20 (from week 2238, 2022-11-27). The catalogue
has no IGS08 (weeks 1632-1933) or IGS14 (weeks 1934-2237) family: such a campaign gets
``antex: null`` and a note to name the file.
"""

from __future__ import annotations

import datetime as _dt
import json
import re
import textwrap
from dataclasses import dataclass
from pathlib import Path

from leopod.download.catalogue import Catalogue
from leopod.io.netcdf import atomic_path
from leopod.settings import read_yaml
from leopod.workflow.downloads import PREFIX

__all__ = ["PRODUCT_SETS", "SIGNALS", "ProductSet", "antex_family", "campaign_text",
           "read_satellites", "write_campaign"]


@dataclass(frozen=True)
class ProductSet:
    """Catalogue families of one consistent GNSS product solution.

    Attributes
    ----------
    name : str
        Name given to ``leopod init --products``.
    description : str
        What the set is, for the campaign file's comment.
    families : dict of str to str
        ``products`` key of the campaign -> catalogue family.
    systems : tuple of str
        GNSS the products cover (``G``, ``C``, ``E``).
    """

    name: str
    description: str
    families: dict[str, str]
    systems: tuple[str, ...]

    @property
    def ambiguity_resolution(self) -> bool:
        """True if the set carries an AR product (WL biases or OSBs)."""
        return "wl_bias" in self.families or "osb" in self.families


PRODUCT_SETS = {s.name: s for s in (
    ProductSet("cod", "CODE final orbits and 30-s clocks (no AR product: float POD only)",
               {"gnss_orbit": "cod_orbit", "gnss_clock": "cod_clock"}, ("G",)),
    ProductSet("cod-osb", "CODE final orbits, 30-s clocks and code + phase OSBs "
               "(ambiguity resolution, Jiang et al. 2023)",
               {"gnss_orbit": "cod_orbit", "gnss_clock": "cod_clock", "osb": "cod_osb"},
               ("G", "E")),
    ProductSet("grg", "CNES/CLS integer-recovery clocks with their wide-lane biases and orbits "
               "(ambiguity resolution, Peng et al. 2021)",
               {"gnss_orbit": "grg_orbit", "gnss_clock": "grg_clock", "wl_bias": "grg_wl_bias"},
               ("G",)),
    ProductSet("wum", "WHU multi-GNSS orbits, phase clocks and OSBs (ambiguity resolution)",
               {"gnss_orbit": "wum_orbit", "gnss_clock": "wum_clock", "osb": "wum_osb"},
               ("G", "C", "E")),
    ProductSet("whu", "WHU IGS-final GPS phase clocks and OSBs of the PRIDE PPP-AR 2 era with "
               "CODE orbits and P1-C1 DCBs (ambiguity resolution; as config/whu-2008.yaml)",
               {"gnss_orbit": "cod_orbit", "gnss_clock": "whu_phase_clock",
                "osb": "whu_abs_bias", "dcb_p1c1": "cod_p1c1_dcb"}, ("G",)),
)}

#: Signals of each GNSS: the clock products' reference codes (GPS P1/P2, as the RINEX 2 BlackJack
#: and most IGS clock products; BDS-3 B1C/B2a pilots, Jiang et al. 2023; Galileo E1/E5a).
SIGNALS = {
    "G": {"phase": ["L1C", "L2W"], "code": ["C1C", "C1W", "C2W"], "pod_code": ["C1W", "C2W"]},
    "C": {"phase": ["L1P", "L5P"], "code": ["C1P", "C5P"], "pod_code": ["C1P", "C5P"],
          "exclude_geo": True},
    "E": {"phase": ["L1C", "L5Q"], "code": ["C1C", "C5Q"], "pod_code": ["C1C", "C5Q"]},
}

#: (first day, last day, ANTEX family) of the IGS antenna models the catalogue serves.
_ANTEX_PERIODS = ((_dt.date(2006, 11, 5), _dt.date(2011, 4, 16), "antex_igs05_1402"),
                  (_dt.date(2022, 11, 27), _dt.date.max, "antex_igs20"))
#: Product sets whose clocks were computed with another ANTEX version than the period's.
_ANTEX_OF_SET = {"whu": "antex_igs05_1627"}


def read_satellites(path: str | Path) -> dict[str, dict]:
    """The satellite catalogue (``config/satellites.yaml``): lower-case key -> facts."""
    data = read_yaml(path) or {}
    return {key.lower(): value for key, value in (data.get("satellites") or {}).items()}


def antex_family(product_set: str, start: _dt.date, end: _dt.date) -> str | None:
    """The catalogue's ANTEX family for a product set and a campaign span (module docstring);
    None if no family covers the whole span."""
    if product_set in _ANTEX_OF_SET:
        return _ANTEX_OF_SET[product_set]
    return next((family for first, last, family in _ANTEX_PERIODS
                 if first <= start and end <= last), None)


def _value(value) -> str:
    """A value as YAML flow text (JSON is YAML)."""
    return json.dumps(value)


def _satellite_lines(key: str, facts: dict | None) -> tuple[list[str], list[str]]:
    """The ``satellites:`` block of one satellite and the notes for the user."""
    notes = []
    facts = facts or {}
    lines = ["satellites:", f"  {key}:", f"    name: {_value(facts.get('name', key))}",
             "    source: files"]
    if facts.get("observations"):
        lines += ["    # onboard RINEX observations, fetched by the download rule of this family",
                  f"    observations: \"{PREFIX}{facts['observations']}\""]
    else:
        lines += ["    # EDIT: path template of the onboard RINEX files ({yyyy} {yy} {doy} "
                  "{gpsweek} {dow} {date} {month} {day};",
                  "    # plain, .gz, .Z or Hatanaka); no archive of the catalogue serves them",
                  f"    observations: \"rinex/{key}_{{yyyy}}{{doy}}.rnx\""]
        notes.append(f"satellites.{key}.observations: name your RINEX files (no archive of "
                     "the catalogue serves this satellite's data)")
    lines += ["    # no a-priori orbit: ingest computes a code-only one from the observations",
              "    apriori_orbit: null",
              f"    attitude: {facts.get('attitude', 'nominal')}"]
    if facts.get("yaw_steering"):
        lines.append(f"    yaw_steering: {_value(facts['yaw_steering'])}")
    if facts.get("antenna_pco_body_m"):
        lines.append("    # GNSS antenna phase centre minus centre of mass, body frame "
                     "(+X flight, +Z geocentre) [m]")
        lines.append("    antenna_pco_body_m:")
        lines += [f"      {band}: {_value(xyz)}"
                  for band, xyz in facts["antenna_pco_body_m"].items()]
    else:
        lines.append("    # EDIT: antenna_pco_body_m: {L1: [x, y, z], L2: [x, y, z]}  "
                     "(phase centre minus centre of mass, body frame [m])")
        notes.append(f"satellites.{key}.antenna_pco_body_m: unknown; without it the orbit is "
                     "that of the antenna phase centre")
    if facts.get("retro_offset_body_m"):
        lines.append(f"    retro_offset_body_m: {_value(facts['retro_offset_body_m'])}  "
                     "# laser reflector minus centre of mass [m]")
    if facts.get("slr_normal_points"):
        lines += ["    # SLR validation (needs products.slr_stations and slr_eccentricities too):",
                  f"    # slr_normal_points: \"{PREFIX}{facts['slr_normal_points']}\""]
    if facts.get("sources"):
        lines += textwrap.wrap("sources: " + " ".join(str(facts["sources"]).split()), 90,
                               initial_indent="    # ", subsequent_indent="    #   ")
    return lines, notes


def _product_lines(product_set: ProductSet, antex: str | None) -> list[str]:
    lines = ["products:", f"  # {product_set.description}"]
    lines += [f"  {key}: \"{PREFIX}{family}\"" for key, family in product_set.families.items()]
    if antex:
        lines.append(f"  antex: \"{PREFIX}{antex}\"   # the IGS antenna model of the products")
    else:
        lines += ["  # EDIT: no ANTEX family of the catalogue covers these days (IGS08 or IGS14",
                  "  # era): name the ANTEX file the products were computed with",
                  "  antex: null"]
    return lines


def _force_lines(facts: dict | None) -> list[str]:
    facts = facts or {}
    mass, area = facts.get("mass_kg"), facts.get("area_m2")
    known = ([] if mass and area else
             ["    # EDIT: area and mass (a-priori only: the scale factors are estimated)"])
    mass, area = mass or 500.0, area or 1.0
    return [
        "  forces:",
        "    # installed model files (satkit-data): no file outside the package is needed",
        "    gravity: {field: \"satkit:ITU_GRACE16.gfc\", max_degree: 120}",
        "    # ocean: a FES2004 coefficient file (IERS Conventions 2010) adds the ocean tides",
        "    tides: {ocean: null, solid: true, solid_pole: true, ocean_pole: true}",
        "    third_body: {sun: true, moon: true}",
        "    relativity: {lense_thirring: true, de_sitter: true}",
        *known,
        f"    drag: {{area_m2: {area}, mass_kg: {mass}, drag_coefficient: 2.3, density: msis,",
        "           space_weather: \"satkit:SW-All.csv\", interval_s: 10800.0}",
        f"    srp: {{area_m2: {area}, mass_kg: {mass}, reflectivity_coefficient: 1.3, "
        "estimate: true}",
        "    # once-per-revolution along- and cross-track terms every 3 h (Peng et al. 2021, "
        "Table II)",
        "    empirical: {interval_s: 10800.0, directions: [T, N], terms: [cos, sin], "
        "sigma: 1.0e-7}",
    ]


def campaign_text(name: str, satellite: str, start: _dt.date, end: _dt.date, *,
                  system: str = "G", products: str = "cod",
                  catalogue: Catalogue, satellites: dict[str, dict]) -> tuple[str, list[str]]:
    """The commented YAML of a new campaign and the notes for the user.

    Parameters
    ----------
    name : str
        Campaign name (also the file name stem).
    satellite : str
        Satellite key; facts from ``satellites`` when it is there (case-insensitive).
    start, end : datetime.date
        First and last day (GPS time, inclusive).
    system : str
        GNSS of the POD, one letter (G, C, E) or several (``GC``: a combined POD).
    products : str
        Product set (:data:`PRODUCT_SETS`).
    catalogue : Catalogue
        Product catalogue; every family written must be one of its families.
    satellites : dict
        Satellite catalogue (:func:`read_satellites`).

    Returns
    -------
    text : str
        The campaign file.
    notes : list of str
        What the user has to complete or should know.

    Raises
    ------
    ValueError
        A campaign name the schema refuses, an unknown product set or GNSS, a system the products do not cover, a family missing
        from the catalogue, or an end before the start.
    """
    if not re.fullmatch(r"[A-Za-z0-9_.-]+", name):
        raise ValueError(f"campaign name {name!r}: only letters, digits, '_', '.' and '-'")
    if products not in PRODUCT_SETS:
        raise ValueError(f"--products {products}: unknown product set "
                         f"(known: {', '.join(PRODUCT_SETS)})")
    if end < start:
        raise ValueError(f"--end {end} is before --start {start}")
    chosen = PRODUCT_SETS[products]
    systems = list(dict.fromkeys(system.upper()))
    unknown = [s for s in systems if s not in SIGNALS]
    if unknown or not systems:
        raise ValueError(f"--system {system}: each letter one of {', '.join(SIGNALS)}")
    uncovered = [s for s in systems if s not in chosen.systems]
    if uncovered:
        raise ValueError(f"--system {system}: product set {products} covers "
                         f"{', '.join(chosen.systems)} only")
    antex = antex_family(products, start, end)
    for family in [*chosen.families.values(), *([antex] if antex else [])]:
        catalogue.family(family)   # ValueError naming the known families
    key = satellite.lower()
    facts = satellites.get(key)
    sat_lines, notes = _satellite_lines(key, facts)
    if facts is None:
        notes.insert(0, f"{satellite}: not in the satellite catalogue (known: "
                     f"{', '.join(sorted(satellites))}); its facts are left to you")
    if not antex:
        notes.append("products.antex: no ANTEX family covers these days; name the file")
    if not chosen.ambiguity_resolution:
        notes.append(f"product set {products} has no AR product: the campaign computes the "
                     "float orbit only (no fixed_pod)")
    pod_system = systems[0] if len(systems) == 1 else systems
    lines = [
        f"# Campaign {name}: {facts['name'] if facts else satellite}, {start} to {end}.",
        "# Written by `leopod init`. Every key is described (unit, default, bounds) in",
        "# config/README.md; keys left out take the schema's defaults.",
        "#   leopod check <this file>     schema and input files",
        "#   leopod run <this file>       the whole campaign (a target path runs less: "
        "-- results/<campaign>/...)",
        f"campaign: {name}",
        "# who produces the products (the CF 'institution' of every netCDF file); null: none",
        "institution: null",
        "",
        "# days to process (GPS time, inclusive), quoted: YYYY-MM-DD",
        f"start_date: \"{start.isoformat()}\"",
        f"end_date: \"{end.isoformat()}\"",
        "",
        *sat_lines,
        "",
        "# GNSS products: \"download:<family>\" of config/catalogue.yaml, fetched into",
        "# resources/download/ (or a path template of your own files)",
        *_product_lines(chosen, antex),
        "",
        "# signal pairs per GNSS: the codes of the clock products (pod_code) and their phases",
        "signals:",
        *[f"  {s}: {_value(SIGNALS[s])}" for s in systems],
        "",
        "quality: {}   # data-quality thresholds: the schema's defaults",
        "",
        "# reduced-dynamic POD: 30-h arcs centred on each day (6-h overlaps between days),",
        "# 30-s sampling, 15-min pulses (Wang et al. 2024), orbit written every 10 s",
        "pod:",
        f"  system: {_value(pod_system)}",
        "  sampling_s: 30.0",
        "  output_step_s: 10.0",
        "  pulse_interval_s: 900.0",
        "  pulse_sigma_m_s: [1.0e-5, 1.0e-5, 1.0e-5]",
        *_force_lines(facts),
        "",
        "# downloads: archives are tried in the catalogue's order; archive_urls points an",
        "# archive at a mirror (name -> URL or directory), offline: true forbids the network",
        "download:",
        "  retries: 3",
        "  timeout_s: 60.0",
        "",
    ]
    return "\n".join(lines), notes


def write_campaign(path: str | Path, text: str, *, overwrite: bool = False) -> Path:
    """Write a campaign file atomically; refuse to replace one unless ``overwrite``.

    Raises
    ------
    FileExistsError
        If ``path`` exists and ``overwrite`` is false.
    """
    path = Path(path)
    if path.exists() and not overwrite:
        raise FileExistsError(f"{path} exists (use --force to replace it)")
    with atomic_path(path) as tmp:
        tmp.write_text(text)
    return path
