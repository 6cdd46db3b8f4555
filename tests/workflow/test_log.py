"""Logging of a step (leopod.workflow.log): a bad-input error is one line naming the file, any
other exception keeps its traceback.

Authority: the project's error contract (DESIGN.md, Conventions: bad input gets a clear error
that names the file, line and field) and issue 24, item 4 (a damaged file fails its day with a
message naming the cause, never a traceback).
"""

import logging
import sys
from types import SimpleNamespace

import pytest

from leopod.io._text import FormatError
from leopod.io.provenance import set_job
from leopod.workflow.log import configure_logging


@pytest.fixture
def step_log(tmp_path):
    hook, root = sys.excepthook, logging.getLogger()
    handlers, level = list(root.handlers), root.level
    path = tmp_path / "step.log"
    configure_logging(SimpleNamespace(log=[path], rule="float_pod",
                                      wildcards={"sat": "hy2b-sim", "date": "2019-001"},
                                      input={}, params={}, config={"campaign": "c"}))
    yield path, sys.excepthook
    set_job(None)
    for h in root.handlers:
        h.close()
    root.handlers[:] = handlers
    root.setLevel(level)
    sys.excepthook = hook


def _raised(exc):
    try:
        raise exc
    except Exception:
        return sys.exc_info()


def test_format_error_is_its_message(step_log):
    path, hook = step_log
    hook(*_raised(FormatError("results/ingest/x.nc", None, "netCDF", "cannot read it")))
    text = path.read_text()
    assert "step float_pod failed: results/ingest/x.nc: field 'netCDF': cannot read it" in text
    assert "Traceback" not in text


def test_other_errors_keep_their_traceback(step_log):
    path, hook = step_log
    hook(*_raised(ZeroDivisionError("division by zero")))
    text = path.read_text()
    assert "step float_pod failed" in text and "Traceback" in text


def test_the_step_declares_its_job_and_logs_the_campaign_hash(step_log):
    # the writers' provenance (leopod.io.provenance) is the job's; the hash is that of the
    # campaign as given, SHA-256 of its canonical JSON '{"campaign":"c"}' (hashlib's
    # sha256 of the same bytes, FIPS 180-4)
    import hashlib

    from leopod.io.provenance import current_job

    path, _ = step_log
    digest = hashlib.sha256(b'{"campaign":"c"}').hexdigest()
    job = current_job()
    assert job.rule == "float_pod" and job.config_sha256 == digest
    assert job.script == "scripts/float_pod.py" and job.inputs == ()
    assert f"campaign config sha256 {digest}" in path.read_text()


def test_the_job_s_inputs_leave_out_the_library_code_and_the_script():
    # the code a step runs is named by the version (source) and the script (history); the
    # data files are listed in the order of the rule's inputs, each once
    from leopod.workflow.provenance import job_provenance

    sm = SimpleNamespace(rule="float_pod", params={"pod": {"a": 1}}, config={},
                         input={"obs": ["o1.nc", "o2.nc"], "code": ["/src/leopod/x.py"],
                                "script": "/repo/scripts/float_pod.py", "leo": "o1.nc"})
    job = job_provenance(sm)
    assert job.inputs == ("o1.nc", "o2.nc")
    assert job.settings == '{"pod": {"a": 1}}'
