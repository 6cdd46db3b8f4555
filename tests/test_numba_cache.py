"""The numba cache directory of leopod (leopod._numba_cache_dir).

Authority: the rule it states — one directory per version of the sources, the same for a
process and the processes it starts (Snakemake imports leopod, then runs each job's script in
a child process that inherits ``NUMBA_CACHE_DIR``).
"""

import os
import subprocess
import sys

import leopod


def test_a_child_process_uses_the_same_cache_directory():
    child = subprocess.run(
        [sys.executable, "-c", "import os, leopod; print(os.environ['NUMBA_CACHE_DIR'])"],
        env={**os.environ, "NUMBA_CACHE_DIR": leopod._CACHE_DIR}, capture_output=True,
        text=True, check=True)
    assert child.stdout.strip() == leopod._CACHE_DIR


def test_the_directory_is_keyed_below_a_given_base(monkeypatch, tmp_path):
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    key = os.path.basename(leopod._CACHE_DIR)
    assert leopod._numba_cache_dir() == os.path.join(str(tmp_path), key)
