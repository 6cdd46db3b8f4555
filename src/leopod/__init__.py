"""leopod: precise orbit determination of low-Earth-orbit satellites from onboard GNSS."""

import hashlib as _hashlib
import os as _os
import sys as _sys
from pathlib import Path as _Path

__version__ = "0.1.0"


def _numba_cache_dir() -> str:
    """A numba cache directory keyed by a hash of all leopod sources.

    numba's on-disk cache (``cache=True``) is invalidated only by changes to the file that
    defines a kernel: it keeps stale machine code when a constant imported from
    ``leopod.constants`` or a jitted function of another module changes. Keying the cache
    directory on the whole package makes any source change start from a clean cache.
    The base is ``$NUMBA_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/leopod/numba``; a base
    that already is this directory (inherited from a parent process that imported leopod, such
    as Snakemake running a job's script) is kept, so that jobs share the cache of ``make setup``.
    """
    package = _Path(__file__).resolve().parent
    digest = _hashlib.sha1()
    for source in sorted(package.rglob("*.py")):
        digest.update(source.relative_to(package).as_posix().encode())
        digest.update(source.read_bytes())
    base = _os.environ.get("NUMBA_CACHE_DIR") or _os.path.join(
        _os.environ.get("XDG_CACHE_HOME", _os.path.join(_os.path.expanduser("~"), ".cache")),
        "leopod", "numba")
    key = digest.hexdigest()[:16]
    return base if _os.path.basename(_os.path.normpath(base)) == key else _os.path.join(base, key)


_CACHE_DIR = _numba_cache_dir()
if "numba" in _sys.modules:
    _sys.modules["numba"].config.CACHE_DIR = _CACHE_DIR
else:
    _os.environ["NUMBA_CACHE_DIR"] = _CACHE_DIR
