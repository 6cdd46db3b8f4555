"""Transfers of one file: HTTP(S), FTP and local paths, with retries and resume.

Only the standard library is used (:mod:`urllib.request`, :mod:`ftplib`).

- **Resume.** A transfer writes into a ``.part`` file beside its destination and records the
  URL (and the HTTP validator, ETag or Last-Modified) in ``<part>.json``. A later attempt on
  the same URL continues from the ``.part`` size: HTTP ``Range: bytes=N-`` with ``If-Range``
  (RFC 9110, 14.2 and 13.1.5), FTP ``REST N`` (RFC 3659, 5). If the server ignores the range
  (status 200), refuses it or the file changed, the transfer restarts from byte 0. A ``.part``
  of another URL is never continued.
- **Completeness.** A transfer is complete when it delivered the announced length (HTTP
  ``Content-Length``/``Content-Range``, FTP ``SIZE``); a connection closed early is a
  transient failure and is retried (continuing the ``.part``).
- **Retries.** Transient failures (connection refused or reset, timeout, HTTP 408/429/5xx,
  FTP 4xx, incomplete transfer) are retried ``retries`` times with exponential backoff
  ``retry_delay_s * 2**k``; permanent ones (HTTP 401/403/404, FTP 5xx such as 550 "no such
  file" or 530 "login incorrect") fail at once.
- **Credentials.** For archives with ``auth: netrc``, logins come from the netrc file
  ``$NETRC`` or ``~/.netrc`` looked up by host: for FTP the server's host, for HTTP every
  host of a redirect chain that answers 401 with a Basic challenge (e.g. CDDIS redirecting
  to the NASA Earthdata login host); cookies are kept for the chain.
"""

from __future__ import annotations

import ftplib
import http.client
import json
import logging
import netrc
import os
import socket
import time
import urllib.error
import urllib.request
from dataclasses import dataclass
from http.cookiejar import CookieJar
from pathlib import Path
from urllib.parse import unquote, urlsplit

from leopod import __version__
from leopod.download.catalogue import local_path

__all__ = ["FetchError", "Transfer", "discard_part", "download", "netrc_credentials", "read_url"]

logger = logging.getLogger(__name__)

_USER_AGENT = f"leopod/{__version__} (precise orbit determination; python urllib)"
_BLOCK = 1 << 16
_TRANSIENT_HTTP = {408, 425, 429, 500, 502, 503, 504}
_MAX_SMALL_BYTES = 64 << 20  # checksum lists and other files read into memory


class FetchError(Exception):
    """A transfer failed.

    Attributes
    ----------
    url : str
    reason : str
        What went wrong, in words (``"HTTP 404 Not Found"``, ``"timed out after 5 s"``).
    transient : bool
        True if trying again may help (the transfer is retried).
    """

    def __init__(self, url: str, reason: str, *, transient: bool):
        self.url = url
        self.reason = reason
        self.transient = transient
        super().__init__(f"{url}: {reason}")


@dataclass(frozen=True)
class Transfer:
    """Outcome of :func:`download`.

    Attributes
    ----------
    url : str
    path : Path
        The complete file (the ``.part`` file, or the source itself for local paths).
    size : int
        Its size [bytes].
    resumed_from : int
        Bytes already present when the successful attempt started (0 = full transfer).
    network : bool
        False for local paths.
    """

    url: str
    path: Path
    size: int
    resumed_from: int
    network: bool


# ----------------------------------------------------------------------------- credentials

def netrc_credentials(host: str) -> tuple[str, str] | None:
    """Login and password for ``host`` from ``$NETRC`` (if set) or ``~/.netrc``; None if absent.

    Raises
    ------
    FetchError
        If the netrc file exists but cannot be parsed (not transient).
    """
    path = Path(os.environ.get("NETRC") or Path.home() / ".netrc").expanduser()
    if not path.is_file():
        return None
    try:
        entry = netrc.netrc(str(path)).authenticators(host)
    except (netrc.NetrcParseError, OSError) as err:
        raise FetchError(str(path), f"cannot read netrc file ({err})", transient=False) from None
    if entry is None:
        return None
    login, _, password = entry
    return login, password or ""


class _NetrcPasswords(urllib.request.HTTPPasswordMgr):
    """Password manager answering every host's Basic-auth challenge from the netrc file."""

    def find_user_password(self, realm, authuri):
        host = urlsplit(authuri if "://" in authuri else "//" + authuri).hostname or ""
        found = netrc_credentials(host)
        if found is None:
            logger.warning("no netrc entry for host %s (asked for credentials, realm %s)",
                           host, realm)
            return None, None
        return found


# ------------------------------------------------------------------------------ resume state

def _state_path(part: Path) -> Path:
    return part.with_name(part.name + ".json")


def _read_state(part: Path) -> dict:
    try:
        return json.loads(_state_path(part).read_text())
    except (OSError, ValueError):
        return {}


def _resume_offset(part: Path, url: str) -> tuple[int, str | None]:
    """Bytes of ``part`` that may be continued for ``url`` and the recorded HTTP validator."""
    state = _read_state(part)
    if state.get("url") != url or not part.is_file():
        return 0, None
    return part.stat().st_size, state.get("validator")


def _start_part(part: Path, url: str, validator: str | None) -> None:
    """Begin a fresh ``.part`` for ``url`` (truncating any previous content)."""
    part.parent.mkdir(parents=True, exist_ok=True)
    part.write_bytes(b"")
    _state_path(part).write_text(json.dumps({"url": url, "validator": validator}))


def discard_part(part: Path) -> None:
    """Remove a ``.part`` file and its resume record."""
    part.unlink(missing_ok=True)
    _state_path(part).unlink(missing_ok=True)


# ------------------------------------------------------------------------------------- HTTP

def _opener(auth: str | None) -> urllib.request.OpenerDirector:
    handlers: list = [urllib.request.HTTPCookieProcessor(CookieJar())]
    if auth == "netrc":
        handlers.append(urllib.request.HTTPBasicAuthHandler(_NetrcPasswords()))
    opener = urllib.request.build_opener(*handlers)
    opener.addheaders = [("User-Agent", _USER_AGENT)]
    return opener


def _content_range(header: str | None) -> tuple[int | None, int | None]:
    """(first byte, total length) of a ``Content-Range`` header (``bytes a-b/n`` or ``*/n``)."""
    if not header or not header.startswith("bytes "):
        return None, None
    span, _, total = header[6:].partition("/")
    first = int(span.split("-")[0]) if span[:1].isdigit() else None
    return first, int(total) if total.strip().isdigit() else None


def _validator(headers) -> str | None:
    """Validator for a later If-Range: a strong ETag, else Last-Modified (RFC 9110, 13.1.5)."""
    etag = headers.get("ETag")
    if etag and not etag.startswith("W/"):
        return etag
    return headers.get("Last-Modified")


def _http_once(url: str, part: Path, auth: str | None, timeout_s: float) -> int:
    """One HTTP(S) attempt; returns the byte offset it continued from."""
    offset, validator = _resume_offset(part, url)
    request = urllib.request.Request(url, headers={"Accept-Encoding": "identity"})
    if offset:
        request.add_header("Range", f"bytes={offset}-")
        if validator:
            request.add_header("If-Range", validator)
    try:
        response = _opener(auth).open(request, timeout=timeout_s)
    except urllib.error.HTTPError as err:
        with err:
            if err.code == 416 and offset:
                _, total = _content_range(err.headers.get("Content-Range"))
                if total == offset:
                    logger.info("%s: already complete in %s (%d bytes)", url, part.name, offset)
                    return offset
                logger.info("%s: range not satisfiable; restarting from byte 0", url)
                discard_part(part)
                return _http_once(url, part, auth, timeout_s)
            raise FetchError(url, f"HTTP {err.code} {err.reason}",
                             transient=err.code in _TRANSIENT_HTTP) from None
    with response:
        first, total = _content_range(response.headers.get("Content-Range"))
        if response.status == 206:
            if not offset or first != offset:
                discard_part(part)
                raise FetchError(url, f"server sent a range from byte {first} when asked from "
                                 f"byte {offset}", transient=True)
            mode = "ab"
        else:
            if offset:
                logger.info("%s: server sent the whole file (status %d); restarting from byte 0",
                            url, response.status)
            offset, mode = 0, "wb"
            _start_part(part, url, _validator(response.headers))
            length = response.headers.get("Content-Length")
            total = int(length) if length and length.isdigit() else None
        with open(part, mode) as out:
            while block := response.read(_BLOCK):
                out.write(block)
    size = part.stat().st_size
    if total is not None and size != total:
        raise FetchError(url, f"connection closed after {size} of {total} bytes",
                         transient=True)
    return offset


# -------------------------------------------------------------------------------------- FTP

def _ftp_login(url: str, auth: str | None, timeout_s: float) -> ftplib.FTP:
    parts = urlsplit(url)
    host = parts.hostname or ""
    user, password = "anonymous", "anonymous@"
    if auth == "netrc":
        found = netrc_credentials(host)
        if found is None:
            raise FetchError(url, f"no netrc entry for host {host}", transient=False)
        user, password = found
    ftp = ftplib.FTP(timeout=timeout_s)
    try:
        ftp.connect(host, parts.port or 21)
        ftp.login(user, password)
        ftp.voidcmd("TYPE I")
    except BaseException:
        ftp.close()
        raise
    return ftp


def _ftp_once(url: str, part: Path, auth: str | None, timeout_s: float) -> int:
    """One FTP attempt (passive mode, binary); returns the byte offset it continued from."""
    offset, _ = _resume_offset(part, url)
    path = unquote(urlsplit(url).path)
    ftp = _ftp_login(url, auth, timeout_s)
    try:
        try:
            total = ftp.size(path)
        except ftplib.error_perm:
            total = None  # SIZE unsupported (or no such file: RETR will say)
        if offset and total is not None and offset >= total:
            if offset == total:
                logger.info("%s: already complete in %s (%d bytes)", url, part.name, offset)
                return offset
            offset = 0
        try:
            conn = ftp.transfercmd(f"RETR {path}", rest=offset or None)
        except ftplib.error_perm:
            if not offset:
                raise
            logger.info("%s: server refused REST %d; restarting from byte 0", url, offset)
            offset = 0
            conn = ftp.transfercmd(f"RETR {path}")
        if not offset:
            _start_part(part, url, None)
        with conn, open(part, "ab") as out:
            while block := conn.recv(_BLOCK):
                out.write(block)
        ftp.voidresp()
    finally:
        ftp.close()
    size = part.stat().st_size
    if total is not None and size != total:
        raise FetchError(url, f"transfer ended after {size} of {total} bytes", transient=True)
    return offset


# ---------------------------------------------------------------------------------- attempts

def _classify(url: str, err: BaseException, timeout_s: float) -> FetchError:
    """A FetchError (with transient flag) for an exception raised by a transfer."""
    if isinstance(err, FetchError):
        return err
    if isinstance(err, ftplib.error_perm):
        return FetchError(url, f"FTP {str(err).strip()}", transient=False)
    if isinstance(err, ftplib.error_temp):
        return FetchError(url, f"FTP {str(err).strip()}", transient=True)
    if isinstance(err, (TimeoutError, socket.timeout)):
        return FetchError(url, f"timed out after {timeout_s:g} s", transient=True)
    if isinstance(err, urllib.error.URLError):
        reason = err.reason
        if isinstance(reason, (TimeoutError, socket.timeout)):
            return FetchError(url, f"timed out after {timeout_s:g} s", transient=True)
        if isinstance(reason, socket.gaierror):
            return FetchError(url, f"host not found ({reason.strerror})", transient=True)
        text = getattr(reason, "strerror", None) or str(reason)
        return FetchError(url, f"cannot connect ({text})", transient=True)
    if isinstance(err, http.client.IncompleteRead):
        return FetchError(url, f"connection closed after {len(err.partial)} more bytes "
                          f"({err.expected} missing)", transient=True)
    if isinstance(err, (OSError, EOFError, http.client.HTTPException, ftplib.Error)):
        text = getattr(err, "strerror", None) or str(err) or type(err).__name__
        return FetchError(url, f"transfer failed ({text})", transient=True)
    raise err


def _attempt(url: str, scheme: str, part: Path, auth: str | None, timeout_s: float) -> int:
    once = _ftp_once if scheme == "ftp" else _http_once
    try:
        return once(url, part, auth, timeout_s)
    except Exception as err:  # classified: transport errors become FetchError, others re-raise
        raise _classify(url, err, timeout_s) from err


def download(url: str, part: str | Path, *, auth: str | None = None, retries: int = 3,
             retry_delay_s: float = 2.0, timeout_s: float = 60.0) -> Transfer:
    """Fetch ``url`` into ``part`` (continuing it if it holds the start of the same URL).

    Parameters
    ----------
    url : str
        ``http://``, ``https://``, ``ftp://``, ``file://`` URL or a plain local path.
    part : str or Path
        The ``.part`` file to write (its resume record is ``<part>.json``). Not used for local
        files, which are returned in place.
    auth : {None, "netrc"}
        Credentials from the netrc file (see the module docstring).
    retries : int
        Further attempts after a transient failure (0 = one attempt).
    retry_delay_s : float
        Delay before the first retry [s]; doubled at each retry.
    timeout_s : float
        Timeout of each connection and read [s].

    Returns
    -------
    Transfer

    Raises
    ------
    FetchError
        After the last attempt, or at once for a permanent failure.
    """
    scheme = urlsplit(url).scheme.lower()
    if scheme in ("", "file") or "://" not in url:
        path = local_path(url)
        if not path.is_file():
            raise FetchError(url, "no such file", transient=False)
        return Transfer(url, path, path.stat().st_size, 0, False)
    if scheme not in ("http", "https", "ftp"):
        raise FetchError(url, f"unsupported protocol '{scheme}'", transient=False)
    part = Path(part)
    for attempt in range(retries + 1):
        try:
            resumed = _attempt(url, scheme, part, auth, timeout_s)
            return Transfer(url, part, part.stat().st_size, resumed, True)
        except FetchError as err:
            if not err.transient or attempt == retries:
                raise
            delay = retry_delay_s * 2**attempt
            logger.warning("%s; retry %d/%d in %.3g s", err, attempt + 1, retries, delay)
            time.sleep(delay)
    raise AssertionError("unreachable")  # pragma: no cover


def read_url(url: str, part: str | Path, *, auth: str | None = None, retries: int = 3,
             retry_delay_s: float = 2.0, timeout_s: float = 60.0) -> bytes:
    """Content of a small file (e.g. a checksum list) as bytes; ``part`` is a scratch file.

    Raises
    ------
    FetchError
        As :func:`download`, or if the file exceeds 64 MiB.
    """
    part = Path(part)
    discard_part(part)
    try:
        transfer = download(url, part, auth=auth, retries=retries, retry_delay_s=retry_delay_s,
                            timeout_s=timeout_s)
        if transfer.size > _MAX_SMALL_BYTES:
            raise FetchError(url, f"{transfer.size} bytes: too large for a list", transient=False)
        return transfer.path.read_bytes()
    finally:
        discard_part(part)
