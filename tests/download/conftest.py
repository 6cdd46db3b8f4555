"""Fixtures of the download tests: local servers, netrc, and a guard against real network use.

No test here may reach a real archive: :func:`no_external_network` (autouse) makes every
socket connection or name lookup outside the loopback interface fail the test.
"""

from __future__ import annotations

import ipaddress
import socket

import pytest
from _download_servers import FTP_USER, FtpArchive, HttpArchive

_LOOPBACK_NAMES = {"localhost", "localhost.localdomain"}
_PROXY_VARIABLES = ("http_proxy", "https_proxy", "ftp_proxy", "all_proxy", "no_proxy")


def _is_loopback(host) -> bool:
    if not isinstance(host, str):
        return False
    if host.lower() in _LOOPBACK_NAMES:
        return True
    try:
        return ipaddress.ip_address(host.split("%")[0]).is_loopback
    except ValueError:
        return False


@pytest.fixture(autouse=True)
def no_external_network(monkeypatch):
    """Fail the test on any connection or name lookup outside the loopback interface.

    The blocked call also raises (ConnectionRefusedError / gaierror) so nothing leaves the
    machine; since the library would treat that as a failed source and go on, the recorded
    violation is what fails the test, at teardown. Yields the list of violations.
    """
    violations: list = []
    real_connect = socket.socket.connect
    real_connect_ex = socket.socket.connect_ex
    real_getaddrinfo = socket.getaddrinfo

    def blocked(sock, address) -> bool:
        if sock.family in (socket.AF_INET, socket.AF_INET6) and not _is_loopback(address[0]):
            violations.append(address)
            return True
        return False

    def connect(sock, address):
        if blocked(sock, address):
            raise ConnectionRefusedError(f"test guard: connection to {address} blocked")
        return real_connect(sock, address)

    def connect_ex(sock, address):
        if blocked(sock, address):
            raise ConnectionRefusedError(f"test guard: connection to {address} blocked")
        return real_connect_ex(sock, address)

    def getaddrinfo(host, *args, **kwargs):
        if host is not None and not _is_loopback(host if isinstance(host, str)
                                                 else host.decode()):
            violations.append(host)
            raise socket.gaierror(socket.EAI_NONAME, f"test guard: lookup of {host} blocked")
        return real_getaddrinfo(host, *args, **kwargs)

    monkeypatch.setattr(socket.socket, "connect", connect)
    monkeypatch.setattr(socket.socket, "connect_ex", connect_ex)
    monkeypatch.setattr(socket, "getaddrinfo", getaddrinfo)
    yield violations
    if violations:
        pytest.fail(f"a test tried to reach a non-loopback address: {violations}")


@pytest.fixture(autouse=True)
def isolated_environment(monkeypatch, tmp_path):
    """No proxy variables, and no netrc of the user: NETRC points to a missing file."""
    for name in _PROXY_VARIABLES:
        monkeypatch.delenv(name, raising=False)
        monkeypatch.delenv(name.upper(), raising=False)
    monkeypatch.setenv("NETRC", str(tmp_path / "no-netrc"))


@pytest.fixture
def netrc_file(monkeypatch, tmp_path):
    """Write a netrc file with the given ``{host: (login, password)}`` and point $NETRC to it."""

    def write(entries: dict[str, tuple[str, str]]):
        path = tmp_path / "test.netrc"
        path.write_text("".join(f"machine {host} login {user} password {password}\n"
                                for host, (user, password) in entries.items()))
        path.chmod(0o600)
        monkeypatch.setenv("NETRC", str(path))
        return path

    return write


@pytest.fixture
def http_archive(tmp_path):
    """An HTTP archive on 127.0.0.1 serving ``tmp_path / "http"``."""
    root = tmp_path / "http"
    root.mkdir()
    server = HttpArchive(root)
    yield server
    server.close()


@pytest.fixture
def ftp_archive(tmp_path):
    """An FTP archive on 127.0.0.1: anonymous tree ``ftp_public``, user tree ``ftp_private``."""
    public, private, scratch = (tmp_path / name for name in ("ftp_public", "ftp_private",
                                                              "ftp_scratch"))
    for folder in (public, private, scratch):
        folder.mkdir()
    server = FtpArchive(public, private, FTP_USER, scratch)
    server.public, server.private = public, private
    yield server
    server.close()


@pytest.fixture
def refused_url():
    """An http URL on 127.0.0.1 whose port has no listener (connection refused)."""
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    return f"http://127.0.0.1:{port}"
