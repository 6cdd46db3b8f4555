"""The warm worker (leopod.workflow.worker): a job handed to it behaves as the job on its own.

Authority: the behaviour of ``python script.py`` that Snakemake's ``script:`` jobs rely on (exit
status, standard streams, working directory, environment, signals) and the worker's contract in
its module docstring. Each job here is a script shaped like the ones Snakemake writes (a
preamble that defines ``snakemake`` and ``__real_file__``, then the script).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from leopod.workflow import worker

_PREAMBLE = """\
import sys, types
snakemake = types.SimpleNamespace(threads={threads})
__real_file__ = __file__
from leopod.workflow.worker import hand_off
hand_off(globals())
import os
"""


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    """A worker server for this module's jobs; yields the environment that points jobs at it."""
    saved = dict(os.environ)
    process = worker.start(tmp_path_factory.mktemp("worker") / "worker.log")
    env = dict(os.environ)  # start() pointed this process's future jobs at the worker
    os.environ.clear()
    os.environ.update(saved)
    deadline = time.monotonic() + 300
    while not os.path.exists(env[worker.SOCKET_ENV]):  # imports and kernels first
        assert process.poll() is None and time.monotonic() < deadline, "worker never ready"
        time.sleep(0.2)
    try:
        yield env
    finally:
        worker.stop(process)
    assert not os.path.exists(os.path.dirname(env[worker.SOCKET_ENV]))  # cleaned up


def _job(tmp_path: Path, body: str, threads: int = 1) -> Path:
    script = tmp_path / f"tmpjob{len(list(tmp_path.glob('tmpjob*.py')))}.py"
    script.write_text(_PREAMBLE.format(threads=threads) + textwrap.dedent(body))
    return script


def _run(script: Path, env: dict, **kwargs) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(script)], env=env, capture_output=True, text=True,
                          timeout=120, **kwargs)


def test_a_job_runs_in_a_fork_with_its_directory_environment_and_streams(server, tmp_path):
    # in the fork xarray is already imported (the server preloads it) and the job's marker set
    script = _job(tmp_path, """
        print("in worker", os.environ.get("LEOPOD_WORKER_JOB"), "xarray" in sys.modules)
        print("cwd", os.getcwd(), "color", os.environ["JOB_COLOR"], "argv", sys.argv[1:])
        print("to stderr", file=sys.stderr)
        open("written.txt", "w").write(sys.stdin.read())
    """)
    work = tmp_path / "work"
    work.mkdir()
    proc = subprocess.run([sys.executable, str(script), "--flag"], env={**server, "JOB_COLOR": "red"},
                          cwd=work, input="from stdin", capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "in worker 1 True" in proc.stdout
    assert f"cwd {work} color red argv ['--flag']" in proc.stdout
    assert proc.stderr.strip() == "to stderr"
    assert (work / "written.txt").read_text() == "from stdin"


@pytest.mark.parametrize("body,status,message", [
    ("sys.exit(3)", 3, ""),
    ("sys.exit('a message')", 1, "a message"),
    ("raise ValueError('bad field in line 7')", 1, "ValueError: bad field in line 7"),
    ("pass", 0, ""),
])
def test_the_exit_status_and_traceback_are_the_jobs(server, tmp_path, body, status, message):
    script = _job(tmp_path, f"""
        assert os.environ.get("LEOPOD_WORKER_JOB") == "1"
        {body}
    """)
    proc = _run(script, server)
    assert proc.returncode == status
    assert message in proc.stderr


def test_without_a_worker_or_with_threads_the_job_runs_in_its_own_process(server, tmp_path):
    body = """
        print("in worker", os.environ.get("LEOPOD_WORKER_JOB"))
    """
    alone = {k: v for k, v in server.items() if k != worker.SOCKET_ENV}
    for script, env in ((_job(tmp_path, body), alone), (_job(tmp_path, body, threads=2), server),
                        (_job(tmp_path, body), {**server, worker.SOCKET_ENV: "off"}),
                        (_job(tmp_path, body), {**server, worker.PYTHON_ENV: "/other/python"})):
        proc = _run(script, env)
        assert proc.returncode == 0 and "in worker None" in proc.stdout, proc.stderr


def _started(tmp_path: Path, env: dict) -> tuple[subprocess.Popen, int]:
    """A job that writes its process id and then sleeps; returns (job process, fork's pid)."""
    script = _job(tmp_path, """
        open("pid", "w").write(str(os.getpid()))
        import time
        time.sleep(100)
    """)
    job = subprocess.Popen([sys.executable, str(script)], env=env, cwd=tmp_path,
                           stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not (tmp_path / "pid").exists() or not (tmp_path / "pid").read_text():
        assert job.poll() is None and time.monotonic() < deadline
        time.sleep(0.1)
    pid = int((tmp_path / "pid").read_text())
    assert pid != job.pid  # the job runs in the fork
    return job, pid


def _gone(pid: int, seconds: float = 30) -> bool:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return True
        time.sleep(0.1)
    return False


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_cancelling_the_job_ends_its_fork(server, tmp_path, signum):
    # Snakemake cancels a job by signalling the job process; the fork must end with it
    job, pid = _started(tmp_path, server)
    job.send_signal(signum)
    assert job.wait(timeout=60) != 0
    assert _gone(pid)


def test_a_killed_job_process_ends_its_fork(server, tmp_path):
    # SIGKILL cannot be passed on: the fork notices that its job process is gone
    job, pid = _started(tmp_path, server)
    job.kill()
    job.wait(timeout=60)
    assert _gone(pid)


def test_the_server_ends_with_the_run_that_started_it(tmp_path):
    # a Snakemake run killed outright cannot stop its worker; the worker notices its parent
    # is gone and removes its socket
    code = textwrap.dedent(f"""
        import sys, time
        from leopod.workflow import worker
        server = worker.start({str(tmp_path / 'worker.log')!r})
        print(server.pid, worker.os.environ[worker.SOCKET_ENV], flush=True)
        time.sleep(100)
    """)
    run = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    pid, path = run.stdout.readline().split()
    deadline = time.monotonic() + 300
    while not os.path.exists(path):
        assert time.monotonic() < deadline, "worker never ready"
        time.sleep(0.2)
    run.kill()
    run.wait()
    assert _gone(int(pid))
    assert not os.path.exists(os.path.dirname(path))
