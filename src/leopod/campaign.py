"""Campaign configuration helpers used by the workflow (kept here so they are unit-tested).

The Snakefile's ``common.smk`` only calls these functions; file-name templates, the list of
days and the code files a rule depends on are computed here.
"""

from __future__ import annotations

from pathlib import Path

from leopod.time import days_between, parse_date_id, template_fields

__all__ = ["campaign_days", "expand_template", "library_files", "satellite_ids"]

_PACKAGE = Path(__file__).resolve().parent


def campaign_days(config: dict) -> list[str]:
    """Day identifiers ``YYYY-DDD`` of the campaign (start to end inclusive)."""
    return days_between(config["start_date"], config["end_date"])


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


def library_files(*parts: str) -> list[str]:
    """Source files of leopod sub-packages/modules a rule depends on (for rerun tracking).

    Parameters
    ----------
    *parts : str
        Module or package paths relative to the package, e.g. ``"io"``, ``"gnss/quality.py"``.

    Returns
    -------
    list of str
        Sorted absolute paths of the ``.py`` files.
    """
    files: set[Path] = set()
    for part in parts:
        p = _PACKAGE / part
        if p.is_dir():
            files.update(p.rglob("*.py"))
        elif p.with_suffix(".py").exists():
            files.add(p.with_suffix(".py"))
        else:
            raise FileNotFoundError(f"no leopod module or package '{part}'")
    return sorted(str(f) for f in files)
