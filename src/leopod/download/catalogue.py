"""The product catalogue: which archives exist and where each product family lies in them.

A catalogue is a mapping (read from ``config/catalogue.yaml``) with two sections::

    archives:                 # name -> base URL; the protocol comes from the scheme
      cddis: {url: "https://cddis.nasa.gov/archive/gnss/products", auth: netrc}
      code:  {url: "http://ftp.aiub.unibe.ch/CODE"}
      local: {url: "../shared/data"}          # a plain directory (or file://...) is a local mirror
    families:                 # product family -> how to get one file of it
      cod_orbit:
        description: CODE final GNSS orbits (SP3)
        kind: sp3             # the check of leopod.download.checks that validates it
        period: day           # day (date placeholders) | static (one file, no placeholders)
        suffix: .sp3          # extension of the decompressed file the workflow reads
        sources:              # in order of preference
          - {archive: code, path: "{yyyy}/COD0OPSFIN_{yyyy}{doy}0000_01D_05M_ORB.SP3.gz"}
          - {archive: cddis, path: "{gpsweek}/cod{gpsweek}{dow}.sp3.Z",
             checksums: "{gpsweek}/SHA512SUMS"}

Per source, ``checksums`` is the path template of a checksum list of the archive (lines
``<hex digest>  <file name>``, md5/sha256/sha512) and ``sha256`` a fixed digest of the file as
downloaded (for static files). Placeholders are those of :func:`leopod.time.template_fields`
(``{yyyy} {yy} {doy} {gpsweek} {dow} {date} {month} {day}``). Everything is validated when the
catalogue is built, so a typo fails at start-up with the family and key named, not in the middle
of a campaign.
"""

from __future__ import annotations

import datetime as _dt
import re
import string
from dataclasses import dataclass, replace
from pathlib import Path, PurePosixPath
from urllib.parse import quote, urlsplit
from urllib.request import url2pathname

from leopod.download.checks import KINDS
from leopod.settings import read_yaml
from leopod.time.calendar import parse_date_id, template_fields

__all__ = ["PERIODS", "PLACEHOLDERS", "Archive", "Catalogue", "Family", "Location", "Source",
           "local_path"]

#: Periods of a family: one file per day, or one file for all days.
PERIODS = ("day", "static")
#: Placeholders allowed in the path templates of daily families.
PLACEHOLDERS = tuple(template_fields(_dt.date(2000, 1, 1)))
_SCHEMES = ("http", "https", "ftp", "file")
_AUTH = (None, "netrc")
_HEX = re.compile(r"^[0-9a-fA-F]{64}$")
_ARCHIVE_KEYS = {"url", "auth"}
_FAMILY_KEYS = {"description", "kind", "period", "suffix", "sources"}
_SOURCE_KEYS = {"archive", "path", "checksums", "sha256"}


@dataclass(frozen=True)
class Archive:
    """One archive: a base URL (http, https, ftp, file) or a local directory.

    Attributes
    ----------
    name : str
        Name used by the sources of the families.
    url : str
        Base URL without trailing slash, or a directory path (a local mirror).
    auth : str or None
        ``"netrc"``: log in with the credentials of ``~/.netrc`` (or ``$NETRC``) for the host
        (FTP) or for every host of a redirect chain that asks for them (HTTP basic auth).
    """

    name: str
    url: str
    auth: str | None = None

    @property
    def scheme(self) -> str:
        """``http``, ``https``, ``ftp`` or ``file`` (a plain directory is ``file``)."""
        scheme = urlsplit(self.url).scheme.lower()
        return scheme if scheme in _SCHEMES else "file"

    @property
    def is_local(self) -> bool:
        """True for ``file://`` URLs and plain directories (no network)."""
        return self.scheme == "file"

    def join(self, relative: str) -> str:
        """Full URL (or path) of a file of the archive given its relative path."""
        if self.is_local and "://" not in self.url:
            return str(Path(self.url) / relative)
        return self.url.rstrip("/") + "/" + quote(relative, safe="/+:@")


@dataclass(frozen=True)
class Source:
    """One place where a family's file may be found: an archive and a path template."""

    archive: str
    path: str
    checksums: str | None = None
    sha256: str | None = None


@dataclass(frozen=True)
class Family:
    """A product family: what the file is, how it is checked and where it can come from."""

    name: str
    description: str
    kind: str
    period: str
    suffix: str
    sources: tuple[Source, ...]


@dataclass(frozen=True)
class Location:
    """One candidate of a family for one day: a source with its placeholders expanded.

    Attributes
    ----------
    archive : Archive
    path : str
        Path relative to the archive root (e.g. ``"1419/cod14193.sp3.Z"``).
    url : str
        Full URL (or local path for directory archives).
    checksums_url : str or None
        URL of the archive's checksum list for this file, if the source names one.
    sha256 : str or None
        Expected SHA-256 of the downloaded file, if the source gives one.
    """

    archive: Archive
    path: str
    url: str
    checksums_url: str | None
    sha256: str | None

    @property
    def name(self) -> str:
        """File name as in the archive (compression suffixes included)."""
        return PurePosixPath(self.path).name


def _placeholders(template: str, where: str) -> set[str]:
    """Names of the ``{...}`` fields of a template; format specs and conversions are refused."""
    try:
        parsed = list(string.Formatter().parse(template))
    except ValueError as err:
        raise ValueError(f"{where}: template '{template}' is malformed ({err})") from None
    names = set()
    for _, name, spec, conversion in parsed:
        if name is None:
            continue
        if spec or conversion or not name:
            raise ValueError(f"{where}: template '{template}' uses '{{{name}...}}'; only plain "
                             f"placeholders {{name}} are allowed")
        names.add(name)
    return names


def _check_template(template: str, period: str, where: str) -> None:
    """Reject unknown placeholders, placeholders in static families, absolute or '..' paths."""
    if not isinstance(template, str) or not template.strip():
        raise ValueError(f"{where}: the path template must be a non-empty string")
    names = _placeholders(template, where)
    unknown = names - set(PLACEHOLDERS)
    if unknown:
        raise ValueError(f"{where}: template '{template}' has unknown placeholder(s) "
                         f"{sorted(unknown)}; known: {', '.join(PLACEHOLDERS)}")
    if period == "static" and names:
        raise ValueError(f"{where}: template '{template}' of a static family must not contain "
                         f"date placeholders {sorted(names)}")
    parts = PurePosixPath(template).parts
    if template.startswith("/") or ".." in parts:
        raise ValueError(f"{where}: template '{template}' must be a relative path inside the "
                         "archive (no leading '/', no '..')")


def _require_keys(mapping, allowed: set[str], required: set[str], where: str) -> None:
    if not isinstance(mapping, dict):
        raise ValueError(f"{where}: expected a mapping, got {type(mapping).__name__}")
    missing = required - set(mapping)
    if missing:
        raise ValueError(f"{where}: missing key(s) {sorted(missing)}")
    extra = set(mapping) - allowed
    if extra:
        raise ValueError(f"{where}: unknown key(s) {sorted(extra)} (allowed: {sorted(allowed)})")


def _archive(name: str, spec) -> Archive:
    where = f"catalogue archive '{name}'"
    _require_keys(spec, _ARCHIVE_KEYS, {"url"}, where)
    url, auth = spec["url"], spec.get("auth")
    if not isinstance(url, str) or not url.strip():
        raise ValueError(f"{where}: 'url' must be a non-empty string")
    scheme = urlsplit(url).scheme.lower()
    if "://" in url and scheme not in _SCHEMES:
        raise ValueError(f"{where}: unsupported URL scheme '{scheme}' (use {', '.join(_SCHEMES)} "
                         "or a directory)")
    if auth not in _AUTH:
        raise ValueError(f"{where}: 'auth' must be 'netrc' or absent, not '{auth}'")
    return Archive(name, url.rstrip("/") if "://" in url else url, auth)


def _source(spec, family: str, index: int, period: str, archives: dict) -> Source:
    where = f"catalogue family '{family}' source {index + 1}"
    _require_keys(spec, _SOURCE_KEYS, {"archive", "path"}, where)
    if spec["archive"] not in archives:
        raise ValueError(f"{where}: unknown archive '{spec['archive']}' (known: "
                         f"{', '.join(sorted(archives))})")
    _check_template(spec["path"], period, f"{where} 'path'")
    if spec.get("checksums") is not None:
        _check_template(spec["checksums"], period, f"{where} 'checksums'")
    digest = spec.get("sha256")
    if digest is not None and not (isinstance(digest, str) and _HEX.match(digest)):
        raise ValueError(f"{where}: 'sha256' must be 64 hexadecimal characters")
    return Source(spec["archive"], spec["path"], spec.get("checksums"),
                  digest.lower() if digest else None)


def _family(name: str, spec, archives: dict) -> Family:
    where = f"catalogue family '{name}'"
    _require_keys(spec, _FAMILY_KEYS, _FAMILY_KEYS, where)
    if spec["kind"] not in KINDS:
        raise ValueError(f"{where}: unknown kind '{spec['kind']}' (known: {', '.join(KINDS)})")
    if spec["period"] not in PERIODS:
        raise ValueError(f"{where}: period must be one of {PERIODS}, not '{spec['period']}'")
    suffix = spec["suffix"]
    if not isinstance(suffix, str) or not suffix.startswith("."):
        raise ValueError(f"{where}: 'suffix' must be a file extension starting with '.'")
    sources = spec["sources"]
    if not isinstance(sources, list) or not sources:
        raise ValueError(f"{where}: 'sources' must be a non-empty list")
    return Family(name, str(spec["description"]), spec["kind"], spec["period"], suffix,
                  tuple(_source(s, name, k, spec["period"], archives)
                        for k, s in enumerate(sources)))


class Catalogue:
    """Archives and product families, validated.

    Parameters
    ----------
    archives : dict of str to Archive
    families : dict of str to Family
    """

    def __init__(self, archives: dict[str, Archive], families: dict[str, Family]):
        self.archives = dict(archives)
        self.families = dict(families)

    @classmethod
    def from_config(cls, mapping) -> Catalogue:
        """Build and validate a catalogue from its mapping (see the module docstring).

        Raises
        ------
        ValueError
            Naming the archive or family (and source) and the key that is wrong: missing or
            unknown keys, unknown archive, kind or period, unknown placeholders, bad URL.
        """
        _require_keys(mapping, {"archives", "families"}, {"archives", "families"}, "catalogue")
        if not isinstance(mapping["archives"], dict) or not isinstance(mapping["families"], dict):
            raise ValueError("catalogue: 'archives' and 'families' must be mappings")
        archives = {name: _archive(name, spec) for name, spec in mapping["archives"].items()}
        families = {name: _family(name, spec, archives)
                    for name, spec in mapping["families"].items()}
        return cls(archives, families)

    @classmethod
    def from_yaml(cls, path: str | Path) -> Catalogue:
        """Read and validate a catalogue YAML file (e.g. ``config/catalogue.yaml``)."""
        mapping = read_yaml(path)
        try:
            return cls.from_config(mapping)
        except ValueError as err:
            raise ValueError(f"{path}: {err}") from None

    def family(self, name: str) -> Family:
        """The family called ``name``; ValueError listing the known ones otherwise."""
        try:
            return self.families[name]
        except KeyError:
            raise ValueError(f"unknown product family '{name}' (known: "
                             f"{', '.join(sorted(self.families))})") from None

    def with_archive_urls(self, urls: dict[str, str]) -> Catalogue:
        """A copy whose archives ``urls`` (name -> URL) point elsewhere, e.g. to a mirror.

        Raises
        ------
        ValueError
            If a name is not an archive of the catalogue or the URL is not supported.
        """
        archives = dict(self.archives)
        for name, url in urls.items():
            if name not in archives:
                raise ValueError(f"unknown archive '{name}' (known: {', '.join(sorted(archives))})")
            archives[name] = replace(_archive(name, {"url": url}), auth=archives[name].auth)
        return Catalogue(archives, self.families)

    def locations(self, family: str, date: str | None) -> list[Location]:
        """Every candidate location of one file of ``family``, in order of preference.

        Parameters
        ----------
        family : str
            Family name.
        date : str or None
            Day ``YYYY-DDD`` (or ``YYYY-MM-DD``); required for daily families, ignored by
            static ones.

        Returns
        -------
        list of Location
        """
        fam = self.family(family)
        if fam.period == "day":
            if date is None:
                raise ValueError(f"family '{family}' is daily: a date YYYY-DDD is required")
            fields = template_fields(parse_date_id(date))
        else:
            fields = {}
        out = []
        for src in fam.sources:
            archive = self.archives[src.archive]
            path = src.path.format(**fields)
            checksums = (archive.join(src.checksums.format(**fields))
                         if src.checksums else None)
            out.append(Location(archive, path, archive.join(path), checksums, src.sha256))
        return out


def local_path(url: str) -> Path:
    """Filesystem path of a ``file://`` URL or of a plain path."""
    parts = urlsplit(url)
    if parts.scheme.lower() == "file":
        return Path(url2pathname(parts.path))
    return Path(url)
