"""Checksums of downloaded files: digests and archive checksum lists.

A checksum list is the text file an archive keeps beside its files (``MD5SUMS``,
``SHA256SUMS``, ``SHA512SUMS``), one file per line, in the format of GNU coreutils
``md5sum``/``sha*sum`` (``<hex digest>  <name>``, or ``<hex digest> *<name>`` for binary mode)
or BSD ``<ALGO> (<name>) = <hex digest>``. The algorithm follows from the digest length
(32 hex digits MD5, 64 SHA-256, 128 SHA-512). Names are matched on their last path component.
"""

from __future__ import annotations

import hashlib
import re
from pathlib import Path, PurePosixPath

__all__ = ["ChecksumError", "file_digest", "listed_digest", "verify_digest"]

_ALGORITHMS = {32: "md5", 64: "sha256", 128: "sha512"}
_GNU = re.compile(r"^([0-9a-fA-F]{32}|[0-9a-fA-F]{64}|[0-9a-fA-F]{128})\s+\*?(\S.*)$")
_BSD = re.compile(r"^(MD5|SHA256|SHA512)\s*\((.+)\)\s*=\s*([0-9a-fA-F]+)$", re.IGNORECASE)
_BLOCK = 1 << 20


class ChecksumError(ValueError):
    """A file's digest differs from the expected one, or no digest is listed for it."""


def file_digest(path: str | Path, algorithm: str = "sha256") -> str:
    """Hexadecimal digest of a file (``md5``, ``sha256``, ``sha512``), read in 1 MiB blocks."""
    digest = hashlib.new(algorithm)
    with open(path, "rb") as f:
        while block := f.read(_BLOCK):
            digest.update(block)
    return digest.hexdigest()


def listed_digest(listing: bytes, name: str, source: str) -> tuple[str, str]:
    """Algorithm and digest of file ``name`` in a checksum list.

    Parameters
    ----------
    listing : bytes
        Content of the checksum list.
    name : str
        File name to look up (its last path component is compared).
    source : str
        Where the list came from, for messages.

    Returns
    -------
    (str, str)
        Algorithm (``md5``, ``sha256``, ``sha512``) and lower-case hex digest.

    Raises
    ------
    ChecksumError
        If the list has no entry for the file.
    """
    wanted = PurePosixPath(name).name
    for line in listing.decode("latin-1").splitlines():
        line = line.strip()
        gnu, bsd = _GNU.match(line), _BSD.match(line)
        if gnu:
            digest, listed = gnu.group(1), gnu.group(2)
        elif bsd and len(bsd.group(3)) in _ALGORITHMS:
            digest, listed = bsd.group(3), bsd.group(2)
        else:
            continue
        if PurePosixPath(listed.strip()).name == wanted:
            return _ALGORITHMS[len(digest)], digest.lower()
    raise ChecksumError(f"checksum list {source} has no entry for {wanted}")


def verify_digest(path: str | Path, algorithm: str, expected: str, what: str) -> None:
    """Raise :class:`ChecksumError` unless ``path`` has digest ``expected``.

    ``what`` names the file and the origin of the expected value in the message.
    """
    actual = file_digest(path, algorithm)
    if actual != expected.lower():
        raise ChecksumError(f"{algorithm} mismatch for {what}: got {actual}, expected {expected}")
