"""Local archive servers for the download tests: HTTP and FTP on 127.0.0.1 with faults on demand.

:class:`HttpArchive` serves the files of a directory and, per URL path, a *rule*:

- ``status``: answer with this HTTP status (an HTML error page);
- ``body``: serve these bytes instead of the file (a corrupt or HTML body);
- ``cut_after`` (with ``cut_times``, default 1): send only the first N bytes of the body and
  close the connection, the first ``cut_times`` times;
- ``ignore_range``: answer a Range request with the whole file (status 200);
- ``redirect``: answer 302 with this Location;
- ``auth``: (user, password) required as HTTP basic auth (401 with a Basic challenge);
- ``delay_s``: wait before answering.

Ranges (``bytes=N-``) are honoured with status 206, ``If-Range`` against the ETag, and 416 past
the end. Every request is recorded (path, Host, Range, Authorization).

:class:`FtpArchive` is a pyftpdlib server with an anonymous tree and a user tree; it records
REST and RETR commands and can truncate the first transfer(s) of a file.
"""

from __future__ import annotations

import base64
import hashlib
import logging
import os
import shutil
import threading
import time
import warnings
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from urllib.parse import unquote, urlsplit

with warnings.catch_warnings():  # pyftpdlib imports asyncore/asynchat (deprecated in 3.11)
    warnings.simplefilter("ignore", DeprecationWarning)
    from pyftpdlib.authorizers import DummyAuthorizer
    from pyftpdlib.handlers import FTPHandler
    from pyftpdlib.servers import FTPServer

logging.getLogger("pyftpdlib").setLevel(logging.WARNING)

#: Login and password of the FTP user tree (written into the temporary netrc of the tests).
FTP_USER = ("alice", "s3cret")


class _HttpHandler(BaseHTTPRequestHandler):
    def log_message(self, format, *args):
        logging.getLogger(__name__).debug("http: " + format, *args)

    def do_GET(self):
        archive = self.server.archive
        path = unquote(urlsplit(self.path).path)
        archive.requests.append({key: self.headers.get(key) for key in
                                 ("Host", "Range", "If-Range", "Authorization")} | {"path": path})
        rule = archive.rules.get(path, {})
        if "redirect" in rule:
            self.send_response(302)
            self.send_header("Location", rule["redirect"])
            self.send_header("Content-Length", "0")
            self.end_headers()
            return
        if "auth" in rule and not self._authorised(rule["auth"]):
            self.send_response(401)
            self.send_header("WWW-Authenticate", 'Basic realm="leopod-test"')
            self.send_header("Content-Length", "0")
            self.end_headers()
            return
        if "delay_s" in rule:
            time.sleep(rule["delay_s"])
        if "status" in rule:
            self.send_error(rule["status"])
            return
        body = rule.get("body")
        if body is None:
            file = archive.root / path.lstrip("/")
            if not file.is_file():
                self.send_error(404)
                return
            body = file.read_bytes()
        self._send_body(body, rule)

    def _authorised(self, credentials) -> bool:
        token = base64.b64encode(f"{credentials[0]}:{credentials[1]}".encode()).decode()
        return self.headers.get("Authorization") == f"Basic {token}"

    def _send_body(self, body: bytes, rule: dict) -> None:
        etag = '"' + hashlib.sha1(body).hexdigest()[:16] + '"'
        start, status = 0, 200
        ranged = self.headers.get("Range")
        if_range = self.headers.get("If-Range")
        if ranged and not rule.get("ignore_range") and if_range in (None, etag):
            start = int(ranged.removeprefix("bytes=").split("-")[0])
            if start >= len(body):
                self.send_response(416)
                self.send_header("Content-Range", f"bytes */{len(body)}")
                self.send_header("Content-Length", "0")
                self.end_headers()
                return
            status = 206
        payload = body[start:]
        self.send_response(status)
        self.send_header("Content-Type", "application/octet-stream")
        self.send_header("Content-Length", str(len(payload)))
        self.send_header("ETag", etag)
        if status == 206:
            self.send_header("Content-Range", f"bytes {start}-{len(body) - 1}/{len(body)}")
        self.end_headers()
        if rule.get("cut_after") is not None and rule.get("cut_times", 1) > 0:
            rule["cut_times"] = rule.get("cut_times", 1) - 1
            self.wfile.write(payload[:rule["cut_after"]])
            self.wfile.flush()
            self.close_connection = True
            return
        self.wfile.write(payload)


class _QuietHTTPServer(ThreadingHTTPServer):
    daemon_threads = True

    def handle_error(self, request, client_address):
        """Clients of the tests hang up on purpose (timeouts): log, do not print tracebacks."""
        logging.getLogger(__name__).debug("http: request from %s aborted", client_address,
                                          exc_info=True)


class HttpArchive:
    """A threaded HTTP server on 127.0.0.1 serving ``root`` (see the module docstring)."""

    def __init__(self, root: Path):
        self.root = Path(root)
        self.rules: dict[str, dict] = {}
        self.requests: list[dict] = []
        self._httpd = _QuietHTTPServer(("127.0.0.1", 0), _HttpHandler)
        self._httpd.archive = self
        self._thread = threading.Thread(target=self._httpd.serve_forever,
                                        kwargs={"poll_interval": 0.02}, daemon=True)
        self._thread.start()

    @property
    def port(self) -> int:
        return self._httpd.server_address[1]

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    def paths(self) -> list[str]:
        """URL paths requested so far, in order."""
        return [r["path"] for r in self.requests]

    def close(self) -> None:
        self._httpd.shutdown()
        self._httpd.server_close()
        self._thread.join(timeout=5)


class _FtpHandler(FTPHandler):
    use_sendfile = False
    archive: FtpArchive  # set on the per-server subclass

    def ftp_REST(self, line):
        self.archive.commands.append(("REST", line))
        return super().ftp_REST(line)

    def ftp_RETR(self, file):
        self.archive.commands.append(("RETR", os.path.basename(file)))
        name = os.path.basename(file)
        left = self.archive.truncate.get(name, (0, 0))
        if left[1] > 0:
            self.archive.truncate[name] = (left[0], left[1] - 1)
            short = self.archive.scratch / name
            short.write_bytes(Path(file).read_bytes()[:left[0]])
            return super().ftp_RETR(str(short))
        return super().ftp_RETR(file)


class FtpArchive:
    """pyftpdlib on 127.0.0.1: anonymous read access to ``public``, user access to ``private``.

    Parameters
    ----------
    public, private : Path
        Roots of the anonymous and of the user tree.
    user : (str, str)
        Login and password of the user.
    scratch : Path
        Directory for the truncated copies served by :meth:`truncate_next`.
    """

    def __init__(self, public: Path, private: Path, user: tuple[str, str], scratch: Path):
        self.commands: list[tuple[str, str]] = []
        self.truncate: dict[str, tuple[int, int]] = {}
        self.scratch = Path(scratch)
        authorizer = DummyAuthorizer()
        authorizer.add_anonymous(str(public))
        authorizer.add_user(user[0], user[1], str(private), perm="elr")
        handler = type("Handler", (_FtpHandler,), {"archive": self, "authorizer": authorizer})
        self._server = FTPServer(("127.0.0.1", 0), handler)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._serve, daemon=True)
        self._thread.start()

    def _serve(self) -> None:
        while not self._stop.is_set():
            self._server.serve_forever(timeout=0.01, blocking=False, handle_exit=False)
        self._server.close_all()

    @property
    def url(self) -> str:
        return f"ftp://127.0.0.1:{self._server.address[1]}"

    def truncate_next(self, name: str, n_bytes: int, times: int = 1) -> None:
        """Serve only the first ``n_bytes`` of file ``name`` for its next ``times`` RETR."""
        self.truncate[name] = (n_bytes, times)

    def close(self) -> None:
        self._stop.set()
        self._thread.join(timeout=5)


def copy_into(src: Path, root: Path, relative: str) -> Path:
    """Copy ``src`` to ``root / relative`` (creating folders); returns the copy."""
    dst = root / relative
    dst.parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(src, dst)
    return dst
