"""Decompression of downloaded files by name: gzip, Unix compress and Hatanaka compact RINEX.

The layers are read from the file name as archives publish it, outermost first:

- ``.gz`` gzip (RFC 1952), ``.Z`` Unix ``compress`` (LZW, through ``unlzw3``);
- then Hatanaka compact RINEX (Hatanaka 2008, "A Compression Format and Tools for GNSS
  Observation Data", Bull. GSI 55) when the remaining name ends in ``.crx`` (RINEX 3 long
  names) or ``.yyd`` (RINEX 2 short names, e.g. ``GRCB2080.10D``), through ``hatanaka``.

A file whose bytes do not match its name (an HTML error page called ``.gz``, a truncated gzip
stream, a ``.10D`` file that is not compact RINEX) raises :class:`DecompressError`, so the
caller can try the next source.
"""

from __future__ import annotations

import gzip
import logging
import re
import shutil
import warnings
import zlib
from pathlib import Path

__all__ = ["DecompressError", "decompress_file", "decompressed_name", "layers"]

logger = logging.getLogger(__name__)

_GZIP_MAGIC = b"\x1f\x8b"
_COMPRESS_MAGIC = b"\x1f\x9d"
_CRX_MARK = b"COMPACT RINEX FORMAT"
_RINEX2_CRX = re.compile(r"\.\d\d[dD]$")
_COPY_BLOCK = 1 << 20


class DecompressError(ValueError):
    """The bytes of a file do not decompress as its name says."""


def layers(name: str) -> list[str]:
    """Compression layers of a file name, outermost first.

    Examples: ``"a.sp3.Z"`` -> ``["compress"]``, ``"a.crx.gz"`` -> ``["gzip", "hatanaka"]``,
    ``"GRCB2080.10D"`` -> ``["hatanaka"]``, ``"igs20.atx"`` -> ``[]``.
    """
    out = []
    while True:
        if name.endswith(".gz"):
            out.append("gzip")
            name = name[:-3]
        elif name.endswith(".Z"):
            out.append("compress")
            name = name[:-2]
        else:
            break
    if name.lower().endswith(".crx") or _RINEX2_CRX.search(name):
        out.append("hatanaka")
    return out


def decompressed_name(name: str) -> str:
    """File name after removing every layer: ``.gz``/``.Z`` dropped, ``.crx`` -> ``.rnx``,
    ``.yyd`` -> ``.yyo`` (case kept)."""
    while name.endswith((".gz", ".Z")):
        name = name[:-3] if name.endswith(".gz") else name[:-2]
    if name.lower().endswith(".crx"):
        return name[:-3] + ("RNX" if name[-3:].isupper() else "rnx")
    if _RINEX2_CRX.search(name):
        return name[:-1] + ("O" if name[-1] == "D" else "o")
    return name


def _describe(head: bytes) -> str:
    text = head.lstrip()[:40].decode("latin-1", "replace")
    if text.lower().startswith(("<!doctype", "<html", "<?xml")):
        return "an HTML/XML page"
    return f"bytes {head[:8]!r}"


def _gunzip(src: Path, dst: Path) -> None:
    with open(src, "rb") as f:
        head = f.read(64)
    if head[:2] != _GZIP_MAGIC:
        raise DecompressError(f"named .gz but not gzip data ({_describe(head)})")
    try:
        with gzip.open(src, "rb") as fin, open(dst, "wb") as fout:
            shutil.copyfileobj(fin, fout, _COPY_BLOCK)
    except (EOFError, OSError, zlib.error) as err:
        raise DecompressError(f"corrupt or truncated gzip stream ({err})") from None


def _uncompress(src: Path, dst: Path) -> None:
    import unlzw3

    raw = src.read_bytes()
    if raw[:2] != _COMPRESS_MAGIC:
        raise DecompressError(f"named .Z but not Unix compress data ({_describe(raw[:64])})")
    try:
        dst.write_bytes(unlzw3.unlzw(raw))
    except Exception as err:  # noqa: BLE001 - unlzw3 raises several plain exception types
        raise DecompressError(f"corrupt .Z stream ({err})") from None


def _crx2rnx(src: Path, dst: Path) -> None:
    import hatanaka

    raw = src.read_bytes()
    if _CRX_MARK not in raw[:200]:
        raise DecompressError(f"named as compact RINEX but the first line is not a "
                              f"'COMPACT RINEX FORMAT' header ({_describe(raw[:64])})")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            text = hatanaka.crx2rnx(raw)
        except Exception as err:  # noqa: BLE001 - HatanakaException or its parser's ValueError
            raise DecompressError(f"cannot decompress compact RINEX ({err})") from None
    for w in caught:
        logger.warning("%s: crx2rnx: %s", src.name, w.message)
    dst.write_bytes(text)


_DECODERS = {"gzip": _gunzip, "compress": _uncompress, "hatanaka": _crx2rnx}


def decompress_file(src: str | Path, dst: str | Path, name: str) -> list[str]:
    """Write the fully decompressed content of ``src`` to ``dst``.

    Parameters
    ----------
    src : str or Path
        The file as downloaded (left untouched).
    dst : str or Path
        Output file (overwritten). Intermediate layers go to ``dst`` + ``.layer<k>``, removed.
    name : str
        The file's name in the archive, which tells the layers (see :func:`layers`).

    Returns
    -------
    list of str
        The layers removed (empty if the file was copied as is).

    Raises
    ------
    DecompressError
        If a layer is not what the name says or its stream is corrupt.
    """
    src, dst = Path(src), Path(dst)
    todo = layers(name)
    if not todo:
        shutil.copyfile(src, dst)
        return todo
    current = src
    temps = []
    try:
        for k, layer in enumerate(todo):
            out = dst if k == len(todo) - 1 else dst.with_name(f"{dst.name}.layer{k}")
            if out is not dst:
                temps.append(out)
            _DECODERS[layer](current, out)
            current = out
    finally:
        for tmp in temps:
            tmp.unlink(missing_ok=True)
    return todo
