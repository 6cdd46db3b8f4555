"""numba's on-disk cache is keyed by the package sources (stale kernels cannot survive a change).

numba invalidates a cached kernel only when the file defining it changes, not when an
imported constant (``leopod.constants``) or a jitted function of another module changes.
"""

import hashlib
from pathlib import Path


def test_cache_dir_is_keyed_by_all_sources():
    import numba

    import leopod.dynamics.srp  # noqa: F401  (defines cached kernels)

    assert numba.config.CACHE_DIR == leopod._CACHE_DIR
    package = Path(leopod.__file__).resolve().parent
    digest = hashlib.sha1()
    for source in sorted(package.rglob("*.py")):
        digest.update(source.relative_to(package).as_posix().encode())
        digest.update(source.read_bytes())
    assert Path(leopod._CACHE_DIR).name == digest.hexdigest()[:16]
    # a constant change alters the key: constants.py is part of the digest
    assert (package / "constants.py") in set(package.rglob("*.py"))
