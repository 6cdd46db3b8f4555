"""Mutation fuzzing of every reader in CI (issue 24 item 3): a few hundred cases per reader.

Authority: the reader contract (leopod.io._fields, leopod.io.FormatError): bad input gives a
FormatError naming the file, never another exception, never a hang, and never a silently
non-finite or out-of-range value (verdicts of ``tests/io/_fuzz.py``). Seeds are built from
../shared/data at test time (skipped when absent). ``benchmarks/fuzz_readers.py`` runs the
same cases at >= 10 000 per reader.
"""

from __future__ import annotations

import _fuzz
import pytest

CASES = range(300)
READERS = list(_fuzz._readers())


@pytest.fixture(scope="module")
def seeds(shared_data, tmp_path_factory):
    return _fuzz.build_seeds(shared_data, tmp_path_factory.mktemp("seeds"))


@pytest.mark.shared
@pytest.mark.parametrize("reader", READERS)
def test_reader_survives_mutations(seeds, reader, tmp_path):
    res = _fuzz.fuzz_reader(seeds[reader], CASES, tmp_path, timeout_s=10.0)
    assert res["crash"] == [] and res["hang"] == [] and res["suspect"] == []
    assert len(res["refused"]) > len(CASES) // 4  # the mutations do reach the parsers
