"""Campaign configuration helpers used by the workflow (kept here so they are unit-tested).

The Snakefile's ``common.smk`` only calls these functions; file-name templates, the list of
days and the code files a rule depends on are computed here.
"""

from __future__ import annotations

import copy
import datetime as _dt
import functools
import re
from pathlib import Path

from leopod.gnss.signal_bias import signal_bias_mode
from leopod.time.calendar import date_id, days_between, parse_date_id, template_fields
from leopod.workflow.layout import DOWNLOAD_ROOT, Layout

__all__ = ["arc_days", "campaign_days", "campaign_inputs", "excluded_days", "expand_template",
           "produced_kind", "input_references", "input_templates", "is_daily_template",
           "library_root", "locate_inputs", "located_source", "next_days", "pod_days",
           "satellite_ids", "script_library_files", "signal_bias_inputs"]

#: Folder that holds the imported ``leopod`` package (``src`` of a checkout, or site-packages).
_ROOT = Path(__file__).resolve().parents[2]


def campaign_days(config: dict) -> list[str]:
    """Day identifiers ``YYYY-DDD`` of the campaign (start to end inclusive), without the
    days of ``exclude_days`` (:func:`excluded_days`): the days whose data the steps use."""
    excluded = _excluded(config, "exclude_days")
    return [d for d in days_between(config["start_date"], config["end_date"])
            if d not in excluded]


def pod_days(config: dict) -> list[str]:
    """The campaign days whose orbits the campaign computes: :func:`campaign_days` without the
    days of ``exclude_pod_days`` (their data still serve the arcs of their neighbours and the
    code-bias maps)."""
    excluded = _excluded(config, "exclude_pod_days")
    return [d for d in campaign_days(config) if d not in excluded]


def _excluded(config: dict, key: str) -> dict[str, str]:
    """Day ``YYYY-DDD`` -> reason of the config key ``key`` (``exclude_days`` or
    ``exclude_pod_days``: day ``YYYY-DDD`` or ``YYYY-MM-DD`` -> reason).

    Raises
    ------
    ValueError
        If a key is no day or lies outside the campaign.
    """
    days = set(days_between(config["start_date"], config["end_date"]))
    out = {}
    for day, reason in (config.get(key) or {}).items():
        found = date_id(parse_date_id(str(day)))
        if found not in days:
            raise ValueError(f"{key}: {day} is not a day of the campaign "
                             f"({config['start_date']} to {config['end_date']})")
        out[found] = str(reason)
    return out


def excluded_days(config: dict) -> dict[str, str]:
    """Days left out of the campaign, with the reason, in time order: those of
    ``exclude_days`` (their data unusable: no job, the arcs of their neighbours end at their
    midnight, code-bias periods and overlaps do without them) and of ``exclude_pod_days``
    (their data usable, their POD not: no POD job, their data serve the arcs of their
    neighbours). The campaign summary lists them; ``leopod run --exclude-failed`` writes them.

    Raises
    ------
    ValueError
        If a key is no day or lies outside the campaign.
    """
    both = {**_excluded(config, "exclude_days"), **_excluded(config, "exclude_pod_days")}
    return dict(sorted(both.items()))


def next_days(config: dict) -> dict[str, str]:
    """Day -> the next day with an orbit (:func:`pod_days`), for the days whose next calendar
    day is one (their arcs overlap); the last day and a day before an excluded one have
    none."""
    days = pod_days(config)
    present = set(days)
    out = {}
    for day in days:
        later = date_id(parse_date_id(day) + _dt.timedelta(days=1))
        if later in present:
            out[day] = later
    return out


def satellite_ids(config: dict) -> list[str]:
    """Short ids of the campaign's LEO satellites, in config order."""
    return list(config["satellites"])


def expand_template(template: str, date: str, sat: str | None = None) -> str:
    """Fill a path template for one day (and satellite).

    Parameters
    ----------
    template : str
        Path with placeholders ``{yyyy} {yy} {doy} {gpsweek} {dow} {date} {month} {day}`` and
        ``{sat}``.
    date : str
        Day identifier ``YYYY-DDD``.
    sat : str, optional
        Satellite id for ``{sat}``.

    Raises
    ------
    ValueError
        If the template has an unknown placeholder (names it).
    """
    fields = template_fields(parse_date_id(date))
    if sat is not None:
        fields["sat"] = sat
    try:
        return template.format(**fields)
    except KeyError as err:
        raise ValueError(f"unknown placeholder {{{err.args[0]}}} in path template '{template}' "
                         f"(known: {', '.join('{' + k + '}' for k in fields)})") from None


#: Config entries that hold input path templates: products.<key> and satellites.<sat>.<key>.
PRODUCT_INPUTS = ("gnss_orbit", "gnss_clock", "wl_bias", "osb", "dcb_p1c1", "antex",
                  "slr_stations", "slr_eccentricities")
SATELLITE_INPUTS = ("observations", "apriori_orbit", "slr_normal_points", "reference_orbit")
_DATE_FIELDS = ("yyyy", "yy", "doy", "gpsweek", "dow", "date", "month", "day")


def input_references(config: dict):
    """Yield ``(entry, container, key)`` of every config value that names an input file.

    ``entry`` is the dotted config path (``products.gnss_orbit``,
    ``satellites.grace-a.observations``); ``container[key]`` is the value (path template,
    ``download:<family>`` or None).
    """
    products = config.get("products") or {}
    for key in PRODUCT_INPUTS:
        yield f"products.{key}", products, key
    for sat, block in (config.get("satellites") or {}).items():
        for key in SATELLITE_INPUTS:
            yield f"satellites.{sat}.{key}", block, key
        # the attitude files of the 'file' law: satellites.<sat>.attitude_file.path
        if isinstance(block.get("attitude_file"), dict):
            yield f"satellites.{sat}.attitude_file", block["attitude_file"], "path"
        # the ANTEX file of the LEO antenna: satellites.<sat>.antenna.antex
        if isinstance(block.get("antenna"), dict):
            yield f"satellites.{sat}.antenna", block["antenna"], "antex"
        # the simulator's own ANTEX antenna: satellites.<sat>.simulate_antenna.antex
        if isinstance(block.get("simulate_antenna"), dict):
            yield (f"satellites.{sat}.simulate_antenna", block["simulate_antenna"], "antex")


def campaign_inputs(config: dict) -> dict:
    """A copy of a campaign with ``{campaign}`` filled in its input path templates
    (:mod:`leopod.workflow.layout`: ``resources/{campaign}/simulate/...``).

    Parameters
    ----------
    config : dict
        The validated campaign (not modified).

    Raises
    ------
    ValueError
        If an input names the folder of simulated files without the campaign
        (``resources/simulate/``, the layout before one folder per campaign), naming the
        config entry and the template to write instead.
    """
    name = Layout.of(config).campaign
    config = copy.deepcopy(config)
    for entry, container, key in input_references(config):
        value = container.get(key)
        if not isinstance(value, str):
            continue
        if value.startswith("resources/simulate/"):
            raise ValueError(f"{entry}: {value!r}: simulated files are the campaign's own; "
                             f"write 'resources/{{campaign}}/{value[len('resources/'):]}'")
        container[key] = value.replace("{campaign}", name)
    return config


def produced_kind(template: str, config: dict) -> str | None:
    """``"simulated"`` or ``"downloaded"`` if an input path template (``{campaign}`` filled,
    downloads resolved) names a file that a rule writes (the simulate rules:
    ``resources/<campaign>/simulate/``; the download rules: ``resources/download/``), else
    None (a file the campaign locates)."""
    if template.startswith(f"{Layout.of(config).resources}/simulate/"):
        return "simulated"
    return "downloaded" if template.startswith(f"{DOWNLOAD_ROOT}/") else None


def is_daily_template(template: str) -> bool:
    """True if a path template names one file per day (it has a date placeholder)."""
    return any(f"{{{field}}}" in template for field in _DATE_FIELDS)


def locate_inputs(config: dict) -> tuple[dict, dict[str, str]]:
    """Route the inputs named by path through the ``locate`` rule.

    A missing input file would otherwise stop the whole campaign before any job runs
    (Snakemake's missing-input check); the ``locate`` job of that file fails instead, with a
    message naming the file and the config entry, and the other days go on. Every path
    template (not a file written by a rule, :func:`produced_kind`) is replaced by
    ``resources/<campaign>/locate/<entry>/{date}/<file name>`` (daily) or
    ``resources/<campaign>/locate/<entry>/<file name>`` (one file), which the rule links to
    the file.

    Parameters
    ----------
    config : dict
        The validated campaign config (not modified), ``{campaign}`` filled
        (:func:`campaign_inputs`) and downloads resolved.

    Returns
    -------
    config : dict
        A copy with the path templates replaced.
    located : dict
        ``{entry: original template}`` of every replaced value.
    """
    root = f"{Layout.of(config).resources}/locate"
    config = copy.deepcopy(config)
    located = {}
    for entry, container, key in input_references(config):
        template = container.get(key)
        if not template or produced_kind(template, config):
            continue
        name = Path(template).name
        folder = f"{root}/{entry}"
        container[key] = f"{folder}/{{date}}/{name}" if is_daily_template(template) \
            else f"{folder}/{name}"
        located[entry] = template
    return config, located


def input_templates(config: dict) -> dict[str, str]:
    """``{entry: path template}`` of every input file the config names (unset entries left out).

    ``entry`` is the dotted config path of :func:`input_references` (``products.gnss_orbit``,
    ``satellites.grace-a.observations``). Applied to the config returned by
    :func:`locate_inputs`, the templates are those the rules read.
    """
    return {entry: container[key] for entry, container, key in input_references(config)
            if container.get(key)}


def located_source(located: dict[str, str], entry: str, path: str) -> str:
    """The file a located input stands for.

    Parameters
    ----------
    located : dict
        ``{entry: original template}`` from :func:`locate_inputs`.
    entry : str
        Config entry (``products.gnss_orbit``).
    path : str
        The located file's path below ``resources/<campaign>/locate/<entry>/``
        (``YYYY-DDD/<name>`` for daily inputs).
    """
    template = located[entry]
    sat = entry.split(".")[1] if entry.startswith("satellites.") else None
    if is_daily_template(template):
        return expand_template(template, path.split("/", 1)[0], sat)
    return template.replace("{sat}", sat) if sat else template


def _module_file(name: str, root: Path) -> Path | None:
    """Source file of the leopod module ``name`` (dotted) below ``root``, or None if it is
    not one."""
    parts = name.split(".")
    if parts[0] != "leopod":
        return None
    base = root.joinpath(*parts)
    for path in (base.with_suffix(".py"), base / "__init__.py"):
        if path.is_file():
            return path
    return None


#: ``import leopod.x [as y]`` and ``from leopod.x import a, b`` (names in parentheses across
#: lines too), at any indentation: imports inside functions count.
_LEOPOD_IMPORT = re.compile(
    r"^[ \t]*(?:from[ \t]+(leopod[\w.]*)[ \t]+import[ \t]+(\([^)]*\)|[^\n]*)"
    r"|import[ \t]+(leopod[\w.]*))", re.MULTILINE)


@functools.cache
def _imported_modules(path: Path) -> frozenset[str]:
    """Dotted names of every leopod module ``path`` imports (also inside functions), with the
    packages whose ``__init__`` the import runs.

    A scan of the import statements' text rather than of a parsed syntax tree (4 times
    faster, 0.4 instead of 1.7 s for the scripts and benchmarks; every Snakemake start lists
    the files of every rule; both give the same lists): a line of a docstring that reads like
    an import only adds a file, so a rule reruns for more changes, never fewer.
    """
    names: set[str] = set()
    for match in _LEOPOD_IMPORT.finditer(path.read_text()):
        module, imported, plain = match.groups()
        if plain:
            found = [plain]
        else:
            # "from leopod.io import sp3" imports the module leopod.io.sp3
            items = re.sub(r"#[^\n]*", "", imported).strip("()\n \\").split(",")
            found = [module] + [f"{module}.{item.split()[0]}" for item in items
                                if item.strip()]
        for name in found:
            parts = name.split(".")
            names.update(".".join(parts[:k]) for k in range(1, len(parts) + 1))
    return frozenset(names)


def library_root(basedir: str | Path) -> Path | None:
    """Folder of the leopod sources that belong to a workflow: ``<basedir>/src`` when it holds
    the ``leopod`` package (a checkout), else None (the imported package).

    Parameters
    ----------
    basedir : str or Path
        Folder of the Snakefile (``workflow.basedir``).
    """
    src = Path(basedir) / "src"
    return src if (src / "leopod" / "__init__.py").is_file() else None


def script_library_files(script: str | Path, root: str | Path | None = None) -> list[str]:
    """Every leopod source file a workflow script imports, directly or transitively.

    Used as rule inputs, so that a change in any library code a step runs makes Snakemake
    rerun that step (and only the steps that run it).

    Parameters
    ----------
    script : str or Path
        The rule's script (``scripts/<rule>.py``).
    root : str or Path, optional
        Folder that holds the ``leopod`` package whose files are listed (the ``src`` folder of
        the checkout the workflow runs from, :func:`library_root`); default: the folder of the
        imported package.

    Returns
    -------
    list of str
        Sorted absolute paths of the ``.py`` files, ``leopod/__init__.py`` included.

    Raises
    ------
    ValueError
        If ``root`` holds no ``leopod`` package.
    """
    root = _ROOT if root is None else Path(root).resolve()
    if not (root / "leopod" / "__init__.py").is_file():
        raise ValueError(f"{root} holds no leopod package (leopod/__init__.py)")
    seen: set[Path] = set()
    todo = [Path(script)]
    while todo:
        for name in _imported_modules(todo.pop()):
            path = _module_file(name, root)
            if path is not None and path not in seen:
                seen.add(path)
                todo.append(path)
    return sorted(str(p) for p in seen)


def arc_days(config: dict, date: str) -> list[str]:
    """Campaign days whose data an arc centred on ``date`` uses (the day and, when the arc
    reaches into them, its neighbours inside the campaign)."""
    day = parse_date_id(date)
    pod = config.get("pod", {})
    days = set(campaign_days(config))
    out = []
    if pod.get("arc_before_s", 0) > 0:
        out.append(date_id(day - _dt.timedelta(days=1)))
    out.append(date)
    if pod.get("arc_after_s", 0) > 0:
        out.append(date_id(day + _dt.timedelta(days=1)))
    return [d for d in out if d in days]


def code_bias_period(config: dict, date: str, section: str = "code_bias") -> str:
    """Period of a day: ``YYYY-MM`` (``<section>.period: month``) or ``campaign``; the
    section is ``code_bias`` (code-bias maps) or ``pcv`` (PCV maps)."""
    if config.get(section, {}).get("period", "month") == "campaign":
        return "campaign"
    return parse_date_id(date).strftime("%Y-%m")


def code_bias_periods(config: dict, section: str = "code_bias") -> list[str]:
    """Periods of the campaign of ``section`` (:func:`code_bias_period`), in time order."""
    return list(dict.fromkeys(code_bias_period(config, d, section)
                              for d in campaign_days(config)))


def period_days(config: dict, period: str, section: str = "code_bias") -> list[str]:
    """Campaign days of a period of ``section`` (:func:`code_bias_period`)."""
    return [d for d in campaign_days(config) if code_bias_period(config, d, section) == period]


def applied_code_bias_period(config: dict, date: str) -> str | None:
    """Period of the map that corrects the codes of ``date`` (None: no code is corrected).

    Raises
    ------
    ValueError
        If ``code_bias.apply_period`` is not a period of the campaign.
    """
    cb = config.get("code_bias", {})
    if not cb.get("apply"):
        return None
    fixed = cb.get("apply_period")
    if fixed is None:
        return code_bias_period(config, date)
    if fixed not in code_bias_periods(config):
        raise ValueError(f"code_bias.apply_period {fixed!r} is not a period of the campaign "
                         f"({', '.join(code_bias_periods(config))})")
    return fixed


#: Products whose satellite biases are removed from the observations of every step
#: (:mod:`leopod.gnss.signal_bias`) -> the input key of the steps.
SIGNAL_BIAS_PRODUCTS = {"osb": "signal_bias_osb", "dcb_p1c1": "signal_bias_dcb"}


def signal_bias_inputs(templates: dict, located: dict, date: str, days: list[str],
                       exists=None) -> tuple[dict, dict]:
    """Bias-product files of the days of a step and the spec its script needs.

    Parameters
    ----------
    templates : dict
        ``{entry: template the rules read}`` (:func:`input_templates`).
    located : dict
        ``{entry: original template}`` (:func:`locate_inputs`): the files a located input
        stands for.
    date : str
        The step's day (the arc's central day): its products are required.
    days : list of str
        The days whose observations the step uses (the arc's days).
    exists : callable, optional
        ``exists(path) -> bool`` for a located source (default: :meth:`pathlib.Path.is_file`).
        A neighbouring day whose product file does not exist (campaign ends, a product not
        published) is left out; its epochs then use the central day's products with a
        logged warning (:meth:`leopod.gnss.signal_bias.SignalBiases.for_day`). Files that
        rules write (simulation, downloads) are taken as existing.

    Returns
    -------
    files : dict
        ``signal_bias_osb`` / ``signal_bias_dcb`` -> list of paths (keys with no file left
        out).
    spec : dict
        ``mode`` (:func:`leopod.gnss.signal_bias.signal_bias_mode`), ``central_day``,
        ``osb_days``, ``dcb_days`` (the day of each listed file).
    """
    exists = exists or (lambda path: Path(path).is_file())
    spec = {"mode": signal_bias_mode(wl_bias=bool(templates.get("products.wl_bias")),
                                     osb=bool(templates.get("products.osb"))),
            "central_day": date, "osb_days": [], "dcb_days": []}
    files: dict[str, list[str]] = {}
    for key, input_key in SIGNAL_BIAS_PRODUCTS.items():
        entry = f"products.{key}"
        template = templates.get(entry)
        if not template:
            continue
        listed = spec["osb_days" if key == "osb" else "dcb_days"]
        for day in days:
            if day != date and entry in located and not exists(
                    expand_template(located[entry], day)):
                continue
            files.setdefault(input_key, []).append(expand_template(template, day))
            listed.append(day)
    return files, spec
