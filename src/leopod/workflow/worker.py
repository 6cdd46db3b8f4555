"""A warm worker for the workflow's script jobs: one process imports once, every job is a fork.

Every ``script:`` job of Snakemake is a new Python interpreter that imports numpy, xarray,
matplotlib, scipy, numba and leopod and loads the compiled force model before it does any
work: 1–2 s per job, about 40 % of the job time of the default campaign (issue 18). With the
worker, the Snakefile's ``onstart`` handler starts one server process (:func:`start`) that
imports all of that once and loads the compiled kernels; each job's script then begins with

.. code-block:: python

    from leopod.workflow.worker import hand_off

    hand_off(globals())

which sends the job (its script, working directory, environment and standard streams) to the
server and waits. The server forks; the fork runs the job's script exactly as ``python
script.py`` would (the same file Snakemake wrote, preamble included), with the job's streams,
directory and environment, and reports its exit status, which the job process exits with.
Signals the job process receives (Snakemake cancelling a job) are passed on to the fork.

The job runs where it always ran whenever the worker cannot take it: no worker for this run
(a run by hand, a test, ``LEOPOD_WORKER=off``, a cluster executor), a job with more than one
thread (the server limits BLAS to one), a different Python (a conda environment), or a server
not yet ready or gone. A job in the worker gives the same files as a job on its own: the fork
starts from a process that only imported modules and loaded compiled code.

Snakemake's benchmark files measure the job process, not the fork: their wall time is the
job's, their memory and CPU columns are not. The fork logs its own wall time and peak memory
as the last line of the job's log (:data:`FINISHED`).
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

__all__ = ["FINISHED", "hand_off", "preload", "serve", "start", "stop"]

SOCKET_ENV = "LEOPOD_WORKER"
"""Environment variable with the server's socket path; ``off`` disables the worker."""
PYTHON_ENV = "LEOPOD_WORKER_PYTHON"
"""Environment variable with the server's ``sys.prefix`` (a job of another Python runs alone)."""
CHILD_ENV = "LEOPOD_WORKER_JOB"
"""Set in a fork that runs a job, so that the job's own :func:`hand_off` call returns."""
FINISHED = "worker job finished: exit %d, %.2f s, peak memory %.0f MB"
"""Format of the fork's last log line (exit status, wall time [s], peak RSS [MB])."""
_ONE_THREAD = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
               "GOTO_NUM_THREADS", "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")
"""Thread counts the server sets to 1 before importing numpy (Snakemake's ``threads: 1``)."""
_PRELOAD = ("numpy", "pandas", "xarray", "netCDF4", "erfa", "numba", "scipy.linalg",
            "scipy.sparse", "scipy.sparse.csgraph", "scipy.special", "scipy.optimize",
            "scipy.interpolate", "matplotlib.pyplot", "snakemake.logging",
            "snakemake.iocontainers", "snakemake.script")
"""Third-party modules the jobs import (leopod's own modules are all imported)."""
_LOGGER = "leopod.workflow.worker"
"""This module's name (also when the server runs it as ``__main__``)."""
_POLL_S = 2.0
"""How often the server checks that the Snakemake process that started it is alive [s]."""


# --- the job side -------------------------------------------------------------------------------

def hand_off(namespace: dict) -> None:
    """Run this script job in the warm worker and exit with its status, if the worker can.

    Returns without doing anything (the job then runs in this process) when there is no
    worker for this run or it cannot take the job; see the module docstring.

    Parameters
    ----------
    namespace : dict
        The script's ``globals()``: Snakemake's preamble put ``snakemake``, ``__file__`` (the
        script) and ``__real_file__`` (the temporary file Snakemake runs) there.
    """
    path = os.environ.get(SOCKET_ENV, "")
    job = namespace.get("snakemake")
    if (os.environ.get(CHILD_ENV) or not path or path == "off" or job is None
            or "__real_file__" not in namespace or getattr(job, "threads", 1) != 1
            or os.environ.get(PYTHON_ENV) != sys.prefix):
        return
    conn = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        conn.connect(path)
        request = {"script": namespace["__real_file__"], "cwd": os.getcwd(),
                   "env": dict(os.environ), "argv": sys.argv}
        message = _frame(request)
        sent = socket.send_fds(conn, [message], [0, 1, 2])
        conn.sendall(message[sent:])
        reader = conn.makefile("rb")
        started = _read(reader)
    except OSError:
        started = None
    if started is None:  # the server never started the job: run it here
        conn.close()
        return
    pid = started["pid"]

    def _forward(signum, _frame_):
        try:
            os.kill(pid, signum)
        except ProcessLookupError:
            pass

    for signum in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
        signal.signal(signum, _forward)
    ended = _read(reader)
    if ended is None:
        sys.stderr.write(f"leopod worker: the job's process {pid} ended without a status\n")
    sys.stdout.flush()
    sys.stderr.flush()
    # this process only waited: no interpreter teardown (Snakemake's modules are loaded)
    os._exit(1 if ended is None else ended["exit"])


def _frame(message: dict) -> bytes:
    """One protocol message: a JSON object on one line."""
    return json.dumps(message).encode() + b"\n"


def _read(reader) -> dict | None:
    """The next message from ``reader``; None at the end of the stream."""
    line = reader.readline()
    return json.loads(line) if line else None


# --- the server side ----------------------------------------------------------------------------

def start(log_path: str | os.PathLike) -> subprocess.Popen | None:
    """Start a server for this Snakemake run and point its jobs at it (Snakefile ``onstart``).

    Sets :data:`SOCKET_ENV` and :data:`PYTHON_ENV` in this process's environment, which the
    jobs inherit. Does nothing when ``LEOPOD_WORKER=off``.

    Parameters
    ----------
    log_path : path
        The server's log file (its imports, the jobs it forked, its end).

    Returns
    -------
    subprocess.Popen or None
        The server process (stop it with :func:`stop`); None if the worker is off.
    """
    if os.environ.get(SOCKET_ENV) == "off":
        return None
    path = Path(tempfile.mkdtemp(prefix="leopod-worker-")) / "socket"
    env = dict(os.environ, **{name: "1" for name in _ONE_THREAD})
    Path(log_path).parent.mkdir(parents=True, exist_ok=True)
    with open(log_path, "w") as log:
        server = subprocess.Popen(
            [sys.executable, "-m", "leopod.workflow.worker", str(path), str(os.getpid())],
            env=env, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
            start_new_session=True)
    os.environ[SOCKET_ENV] = str(path)
    os.environ[PYTHON_ENV] = sys.prefix
    return server


def stop(server: subprocess.Popen | None) -> None:
    """Stop a server :func:`start` started (Snakefile ``onsuccess`` and ``onerror``)."""
    for name in (SOCKET_ENV, PYTHON_ENV):
        os.environ.pop(name, None)
    if server is not None and server.poll() is None:
        server.terminate()
        server.wait()


def serve(path: str, parent: int) -> None:
    """Import, load the compiled kernels, then fork one process per job sent to ``path``.

    Runs until SIGTERM or until process ``parent`` (the Snakemake run) is gone; removes its
    socket and the socket's directory at the end.

    Parameters
    ----------
    path : str
        Socket path; it appears only when the server is ready (bound under another name,
        then renamed), so that a job never waits for the imports.
    parent : int
        Process id of the Snakemake run.
    """
    tic = time.perf_counter()
    preload()
    print(f"leopod worker {os.getpid()}: ready in {time.perf_counter() - tic:.1f} s", flush=True)
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    listener.bind(path + ".binding")
    listener.listen(16)
    os.rename(path + ".binding", path)
    listener.settimeout(_POLL_S)
    signal.signal(signal.SIGCHLD, signal.SIG_IGN)  # forks are reaped by the kernel
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))
    try:
        while os.getppid() == parent:
            try:
                conn, _ = listener.accept()
            except TimeoutError:
                continue
            _fork_job(listener, conn)
    finally:
        listener.close()
        for leftover in (path, path + ".binding"):
            if os.path.exists(leftover):
                os.unlink(leftover)
        os.rmdir(os.path.dirname(path))


def preload() -> None:
    """Import the jobs' modules, load the compiled force model and integrator, the Earth
    orientation table and matplotlib's fonts (all read-only)."""
    import importlib
    import io
    import pkgutil

    import matplotlib

    matplotlib.use("Agg")
    for name in _PRELOAD:
        importlib.import_module(name)
    import leopod

    for module in pkgutil.walk_packages(leopod.__path__, "leopod."):
        if module.name not in (_LOGGER, "leopod.__main__"):
            importlib.import_module(module.name)
    from leopod.dynamics.compiled import warm_up
    from leopod.time.eop import default_earth_orientation

    warm_up()
    default_earth_orientation()
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots()
    axes.set_title("$\\sigma$ [mm]")
    figure.savefig(io.BytesIO(), format="png")
    plt.close(figure)


def _fork_job(listener: socket.socket, conn: socket.socket) -> None:
    """Receive one job from ``conn`` and run it in a fork; the server keeps no part of it."""
    try:
        message, fds, _, _ = socket.recv_fds(conn, 1 << 16, 3)
        while not message.endswith(b"\n"):
            chunk = conn.recv(1 << 16)
            if not chunk:
                raise OSError("request cut short")
            message += chunk
        request = json.loads(message)
    except (OSError, ValueError) as error:
        print(f"leopod worker: unreadable request ({error})", flush=True)
        conn.close()
        return
    sys.stdout.flush()
    sys.stderr.flush()
    pid = os.fork()
    if pid:
        for fd in fds:
            os.close(fd)
        conn.close()
        print(f"leopod worker: job {Path(request['script']).name} in process {pid}", flush=True)
        return
    listener.close()
    os._exit(_run_job(conn, request, fds))


def _run_job(conn: socket.socket, request: dict, fds: list[int]) -> int:
    """In the fork: become the job (streams, directory, environment), run its script.

    Returns
    -------
    int
        The exit status the job process exits with.
    """
    import logging
    import resource
    import runpy

    for signum in (signal.SIGCHLD, signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
        signal.signal(signum, signal.SIG_DFL)
    for target, fd in enumerate(fds):
        os.dup2(fd, target)
        os.close(fd)
    os.chdir(request["cwd"])
    os.environ.clear()
    os.environ.update(request["env"], **{CHILD_ENV: "1"})
    sys.argv = list(request["argv"])
    sys.path.insert(0, os.path.dirname(request["script"]))
    conn.sendall(_frame({"pid": os.getpid()}))
    threading.Thread(target=_end_with_client, args=(conn,), daemon=True).start()
    tic = time.perf_counter()
    try:
        runpy.run_path(request["script"], run_name="__main__")
        status = 0
    except SystemExit as stop_:
        status = _exit_status(stop_.code)
    except BaseException:
        sys.excepthook(*sys.exc_info())
        status = 1
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    logging.getLogger(_LOGGER).info(FINISHED, status, time.perf_counter() - tic, peak_mb)
    logging.shutdown()
    sys.stdout.flush()
    sys.stderr.flush()
    try:
        conn.sendall(_frame({"exit": status}))
    except OSError:
        pass
    return status


def _exit_status(code) -> int:
    """The exit status of ``sys.exit(code)``, as the interpreter would give it."""
    if code is None:
        return 0
    if isinstance(code, int):
        return code & 0xFF
    print(code, file=sys.stderr)
    return 1


def _end_with_client(conn: socket.socket) -> None:
    """In the fork: end the job when its job process is gone (killed by Snakemake)."""
    try:
        while conn.recv(1):
            pass
    except OSError:
        pass
    os.kill(os.getpid(), signal.SIGTERM)


if __name__ == "__main__":
    serve(sys.argv[1], int(sys.argv[2]))
