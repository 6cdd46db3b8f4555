"""Fetch one product file: from what is already there, local mirrors, then each source in turn.

:func:`fetch_product` is what a ``download_*`` rule calls. Its order of preference:

1. ``dest`` itself, if it exists and passes the check of its kind (no network);
2. each local mirror directory (no network), looking for every source's file under
   ``<mirror>/<archive name>/<path>``, ``<mirror>/<path>`` and ``<mirror>/<file name>``, as
   published, already decompressed, or compressed otherwise (``.gz``/``.Z``);
3. each source of the family's catalogue entry, in order (local archives too when offline).

Any failure of a candidate (HTTP error, timeout, refused connection, checksum mismatch,
decompression error, failed check) is logged and the next candidate tried. The destination
appears only complete and checked (decompressed and checked in a temporary file in the same
directory, then renamed); after a failure only the resumable ``<dest>.part`` (and its
``.part.json`` record) of an interrupted transfer may remain. If every candidate fails,
:class:`DownloadError` names the product and every URL or path tried with its reason.
"""

from __future__ import annotations

import logging
import os
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from leopod.download.catalogue import Catalogue, Family, Location
from leopod.download.checks import CheckError, check_file
from leopod.download.checksums import ChecksumError, file_digest, listed_digest, verify_digest
from leopod.download.decompress import DecompressError, decompress_file, decompressed_name, layers
from leopod.download.fetch import FetchError, discard_part, download, read_url
from leopod.io.netcdf import atomic_path
from leopod.time.calendar import date_id, parse_date_id

__all__ = ["DownloadError", "FetchReport", "fetch_product"]

logger = logging.getLogger(__name__)

_CANDIDATE_ERRORS = (FetchError, ChecksumError, DecompressError, CheckError)


@dataclass
class FetchReport:
    """What :func:`fetch_product` did.

    Attributes
    ----------
    family : str
    date : str or None
        ``YYYY-DDD``.
    dest : Path
    origin : str
        URL or local path the file came from (``dest`` itself if it was already valid).
    attempts : list of (str, str)
        Every URL or path tried, with its outcome, in order.
    bytes : int
        Size of ``dest`` [bytes].
    sha256 : str
        SHA-256 of ``dest`` (the decompressed file delivered).
    used_network : bool
        True if any network archive was contacted.
    summary : str
        One line from the check (epochs, satellites, ...).
    """

    family: str
    date: str | None
    dest: Path
    origin: str
    attempts: list[tuple[str, str]] = field(default_factory=list)
    bytes: int = 0
    sha256: str = ""
    used_network: bool = False
    summary: str = ""


class DownloadError(RuntimeError):
    """No candidate delivered a usable file; the message lists every one tried and why.

    Attributes
    ----------
    family, date : str
    attempts : list of (str, str)
    """

    def __init__(self, family: Family, date: str | None, dest: Path,
                 attempts: list[tuple[str, str]]):
        self.family = family.name
        self.date = date
        self.attempts = list(attempts)
        lines = "\n".join(f"  {where}: {why}" for where, why in attempts) or "  (nothing to try)"
        super().__init__(f"cannot fetch product '{family.name}' for {date or '(static)'} "
                         f"({family.description}) to {dest}; tried:\n{lines}")


def _normalise_date(family: Family, date: str | None) -> str | None:
    """``YYYY-DDD`` of the date (ISO accepted); required for daily families."""
    if date is None:
        if family.period == "day":
            raise ValueError(f"family '{family.name}' is daily: a date YYYY-DDD is required")
        return None
    return date_id(parse_date_id(date))


def _part_path(dest: Path) -> Path:
    return dest.with_name(dest.name + ".part")


def _display(name: str) -> str:
    return f"{name} (decompressed)" if layers(name) else name


def _install(raw: Path, name: str, family: Family, date: str | None, dest: Path) -> str:
    """Decompress ``raw`` (named ``name``) into a temporary file, check it, rename it to dest."""
    with atomic_path(dest) as tmp:
        decompress_file(raw, tmp, name)
        summary = check_file(tmp, family.kind, date, display=_display(name))
    return summary


def _mirror_candidates(mirror: Path, loc: Location) -> list[Path]:
    """Paths under a mirror where the file of ``loc`` may be: under the archive's name, the
    archive's relative path or flat; as published, decompressed, or compressed otherwise
    (``.gz`` / ``.Z``), in this order of preference."""
    rel = PurePosixPath(loc.path)
    plain = decompressed_name(rel.name)
    names = [rel.name, plain, plain + ".gz", plain + ".Z"]
    out: list[Path] = []
    for base in (mirror / loc.archive.name / rel.parent, mirror / rel.parent, mirror):
        for name in names:
            if base / name not in out:
                out.append(base / name)
    return out


def _from_mirrors(mirrors, locations: list[Location], family: Family, date: str | None,
                  dest: Path, attempts: list, log: logging.Logger) -> tuple[str, str] | None:
    """Install the first valid mirror copy; returns (origin, summary) or None."""
    for mirror in map(Path, mirrors):
        found = False
        for loc in locations:
            for path in _mirror_candidates(mirror, loc):
                if not path.is_file():
                    continue
                found = True
                try:
                    if loc.sha256 and path.name == loc.name:
                        verify_digest(path, "sha256", loc.sha256, f"{path} (catalogue sha256)")
                    summary = _install(path, path.name, family, date, dest)
                except _CANDIDATE_ERRORS as err:
                    attempts.append((str(path), str(err)))
                    log.warning("%s: mirror copy rejected: %s", path, err)
                    continue
                attempts.append((str(path), "ok"))
                return str(path), summary
        if not found:
            names = sorted({loc.name for loc in locations})
            reason = (f"no copy in the mirror (looked for {', '.join(names)}, also "
                      "decompressed or otherwise compressed)")
            attempts.append((str(mirror), reason))
    return None


def _verify(transfer_path: Path, loc: Location, dest: Path, fetch_kw: dict) -> None:
    """Fixed SHA-256 of the catalogue and checksum list of the archive, when configured."""
    if loc.sha256:
        verify_digest(transfer_path, "sha256", loc.sha256, f"{loc.name} (catalogue sha256)")
    if loc.checksums_url:
        try:
            listing = read_url(loc.checksums_url, dest.with_name(dest.name + ".sums.part"),
                               auth=loc.archive.auth, **fetch_kw)
        except FetchError as err:
            raise ChecksumError(f"checksum list {loc.checksums_url}: {err.reason}") from None
        algorithm, expected = listed_digest(listing, loc.name, loc.checksums_url)
        verify_digest(transfer_path, algorithm, expected, f"{loc.name} ({loc.checksums_url})")


def _from_location(loc: Location, family: Family, date: str | None, dest: Path,
                   fetch_kw: dict, log) -> str:
    """Download (or take the local file of) one source, verify, install; returns the summary."""
    part = _part_path(dest)
    log.info("%s %s: fetching %s", family.name, date or "(static)", loc.url)
    transfer = download(loc.url, part, auth=loc.archive.auth, **fetch_kw)
    if transfer.resumed_from:
        log.info("%s: resumed at byte %d of %d", loc.url, transfer.resumed_from, transfer.size)
    try:
        _verify(transfer.path, loc, dest, fetch_kw)
        summary = _install(transfer.path, loc.name, family, date, dest)
    except (ChecksumError, DecompressError, CheckError):
        if transfer.network:
            discard_part(part)  # complete but unusable: never resume it
        raise
    return summary


def _report(family, date, dest, origin, attempts, network, summary, log) -> FetchReport:
    """Report of a success; a ``.part`` left by an earlier interrupted source is now useless."""
    discard_part(_part_path(dest))
    report = FetchReport(family.name, date, dest, origin, attempts, dest.stat().st_size,
                         file_digest(dest), network, summary)
    log.info("%s %s: %s from %s (%d bytes, sha256 %s): %s", family.name, date or "(static)",
             dest, origin, report.bytes, report.sha256[:16], summary)
    return report


def fetch_product(catalogue: Catalogue, family: str, date: str | None, dest: str | Path, *,
                  mirrors=(), offline: bool = False, retries: int = 3,
                  retry_delay_s: float = 2.0, timeout_s: float = 60.0,
                  log: logging.Logger | None = None) -> FetchReport:
    """Make ``dest`` a valid, decompressed file of product ``family`` for ``date``.

    Parameters
    ----------
    catalogue : Catalogue
        Archives and families (e.g. ``Catalogue.from_yaml("config/catalogue.yaml")``).
    family : str
        Product family name.
    date : str or None
        Day ``YYYY-DDD`` (ISO ``YYYY-MM-DD`` accepted). Required for daily families; for a
        static family it is optional and, if given, the file must cover that day (e.g. an
        EOP or space-weather table).
    dest : str or Path
        Final (decompressed) file.
    mirrors : iterable of str or Path
        Local directories mirroring archives, tried first (see the module docstring).
    offline : bool
        Use only ``dest``, the mirrors and local (``file://``/directory) archives.
    retries : int
        Further attempts per URL after a transient failure.
    retry_delay_s : float
        Delay before the first retry [s], doubled at each retry.
    timeout_s : float
        Timeout of each connection and read [s].
    log : logging.Logger, optional
        Logger for progress (default: this module's).

    Returns
    -------
    FetchReport

    Raises
    ------
    DownloadError
        If no candidate delivers a file that passes the check; the message names the product
        and every URL or path tried, one per line, with its reason.
    ValueError
        For an unknown family or a missing/invalid date.
    """
    log = log or logger
    fam = catalogue.family(family)
    day = _normalise_date(fam, date)
    dest = Path(dest)
    attempts: list[tuple[str, str]] = []
    if dest.exists():
        try:
            summary = check_file(dest, fam.kind, day)
        except CheckError as err:
            attempts.append((str(dest), f"present but not usable ({err})"))
            log.warning("%s: present but not usable, fetching again: %s", dest, err)
        else:
            attempts.append((str(dest), "present and valid"))
            return _report(fam, day, dest, str(dest), attempts, False, summary, log)
    locations = catalogue.locations(family, day)
    found = _from_mirrors(mirrors, locations, fam, day, dest, attempts, log)
    if found:
        return _report(fam, day, dest, found[0], attempts, False, found[1], log)
    fetch_kw = {"retries": retries, "retry_delay_s": retry_delay_s, "timeout_s": timeout_s}
    network = False
    for loc in locations:
        if offline and not loc.archive.is_local:
            attempts.append((loc.url, "not tried (offline)"))
            continue
        network |= not loc.archive.is_local
        try:
            summary = _from_location(loc, fam, day, dest, fetch_kw, log)
        except _CANDIDATE_ERRORS as err:
            reason = err.reason if isinstance(err, FetchError) else str(err)
            attempts.append((loc.url, reason))
            log.warning("%s: %s", loc.url, reason)
            continue
        attempts.append((loc.url, "ok"))
        return _report(fam, day, dest, loc.url, attempts, network, summary, log)
    if dest.exists():  # a stale or broken file must not pass for the product
        aside = dest.with_name(dest.name + ".invalid")
        os.replace(dest, aside)
        attempts.append((str(dest), f"moved aside to {aside.name}"))
    raise DownloadError(fam, day, dest, attempts)
