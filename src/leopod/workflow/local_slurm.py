"""A one-node SLURM cluster on this machine, to run a campaign through ``profiles/slurm``.

The SLURM profile is otherwise only ever rendered with ``-n``. Debian packages a complete
SLURM (``apt-get install slurmctld slurmd slurm-client munge``); this module writes a minimal
``slurm.conf`` for the local host (its CPUs and memory from ``slurmd -C``), starts ``munged``,
``slurmctld`` and ``slurmd`` with their state, spool, log and pid files in one folder, waits
until the node is idle, and stops them again::

    python -m leopod.workflow.local_slurm up /tmp/leopod-slurm     # prints: export SLURM_CONF=…
    SLURM_CONF=/tmp/leopod-slurm/slurm.conf leopod run config/config.yaml --profile slurm \\
        -- --slurm-status-command squeue --slurm-no-account
    python -m leopod.workflow.local_slurm down /tmp/leopod-slurm

Every SLURM command finds the cluster through the environment variable ``SLURM_CONF``; nothing
under /etc is changed but munge's key, which the munge package creates at installation. The
cluster has no accounting database (``accounting_storage/none``), so job states come from
``squeue`` (``--slurm-status-command squeue``); ``MinJobAge`` keeps finished jobs visible to it
for an hour. ``slurmctld`` and ``slurmd`` run as root (SlurmUser=root): the cluster is for
tests on a machine of one's own, not for users.
"""

from __future__ import annotations

import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

__all__ = ["available", "node_line", "slurm_conf", "start", "stop"]

#: The SLURM daemons and clients a local cluster needs (Debian packages slurmctld, slurmd,
#: slurm-client, munge).
PROGRAMS = ("munged", "slurmctld", "slurmd", "sbatch", "squeue", "scontrol", "srun")
_SBIN = ("/usr/sbin", "/usr/bin")
#: munge's default socket (Debian's munge package).
MUNGE_SOCKET = "/run/munge/munge.socket.2"


def _which(name: str) -> str | None:
    return shutil.which(name) or next(
        (str(Path(d) / name) for d in _SBIN if (Path(d) / name).is_file()), None)


def available() -> bool:
    """Whether the SLURM and munge programs are installed and this process is root."""
    return os.geteuid() == 0 and all(_which(p) for p in PROGRAMS)


def node_line() -> str:
    """The ``NodeName=…`` line of this host as ``slurmd -C`` reports it (CPUs, sockets,
    cores, threads, RealMemory [MiB]), with ``NodeAddr=127.0.0.1``."""
    out = subprocess.run([_which("slurmd"), "-C"], capture_output=True, text=True,
                         check=True).stdout
    line = next(x for x in out.splitlines() if x.startswith("NodeName="))
    return f"{line} NodeAddr=127.0.0.1 State=UNKNOWN"


def slurm_conf(folder: Path, node: str) -> str:
    """The ``slurm.conf`` text of a one-node cluster whose files live in ``folder``.

    Parameters
    ----------
    folder : Path
        State, spool, log and pid files of the daemons.
    node : str
        The node's line (:func:`node_line`).
    """
    name = re.match(r"NodeName=(\S+)", node).group(1)
    return "\n".join([
        "# one-node SLURM cluster of leopod.workflow.local_slurm (tests only)",
        "ClusterName=leopod",
        "SlurmctldParameters=enable_configless",
        f"SlurmctldHost={name}(127.0.0.1)",
        "SlurmUser=root",
        "SlurmdUser=root",
        "AuthType=auth/munge",
        "CredType=cred/munge",
        "MpiDefault=none",
        "ProctrackType=proctrack/linuxproc",
        "TaskPlugin=task/none",
        "SchedulerType=sched/backfill",
        "SelectType=select/cons_tres",
        "SelectTypeParameters=CR_Core_Memory",
        "AccountingStorageType=accounting_storage/none",
        "JobAcctGatherType=jobacct_gather/none",
        "JobCompType=jobcomp/none",
        "ReturnToService=2",
        "MinJobAge=3600",
        "SlurmctldPort=6817",
        "SlurmdPort=6818",
        f"StateSaveLocation={folder / 'state'}",
        f"SlurmdSpoolDir={folder / 'spool'}",
        f"SlurmctldPidFile={folder / 'slurmctld.pid'}",
        f"SlurmdPidFile={folder / 'slurmd.pid'}",
        f"SlurmctldLogFile={folder / 'slurmctld.log'}",
        f"SlurmdLogFile={folder / 'slurmd.log'}",
        node,
        f"PartitionName=local Nodes={name} Default=YES MaxTime=INFINITE State=UP",
        "",
    ])


def start(folder: Path, timeout_s: float = 60.0) -> dict[str, str]:
    """Start munged, slurmctld and slurmd with their files in ``folder``; return the
    environment variables that point SLURM's commands at the cluster (``SLURM_CONF``).

    Raises
    ------
    RuntimeError
        When a program is missing, this is not root, or the node is not idle within
        ``timeout_s`` seconds (the daemons' log files are named).
    """
    if not available():
        raise RuntimeError("a local SLURM cluster needs root and the programs "
                           f"{', '.join(PROGRAMS)} (Debian: apt-get install slurmctld slurmd "
                           "slurm-client munge)")
    folder = Path(folder).resolve()
    for sub in ("state", "spool"):
        (folder / sub).mkdir(parents=True, exist_ok=True)
    conf = folder / "slurm.conf"
    conf.write_text(slurm_conf(folder, node_line()))
    env = {**os.environ, "SLURM_CONF": str(conf)}
    # munge at its default socket (/run/munge), where a configless slurmd looks before it
    # has a configuration; --force lets root run it; one already running is used
    if not Path(MUNGE_SOCKET).exists():
        Path(MUNGE_SOCKET).parent.mkdir(parents=True, exist_ok=True)
        subprocess.run([_which("munged"), "--force",
                        f"--pid-file={folder / 'munged.pid'}",
                        f"--log-file={folder / 'munged.log'}",
                        f"--seed-file={folder / 'munged.seed'}"], check=True)
    subprocess.run([_which("slurmctld"), "-f", str(conf)], env=env, check=True)
    # configless slurmd (Slurm >= 20.02): it fetches slurm.conf from slurmctld and keeps it
    # in /run/slurm/conf, where the job's nested srun finds it (the Snakemake job step
    # removes SLURM_CONF from its environment)
    subprocess.run([_which("slurmd"), "--conf-server", "127.0.0.1:6817"], env=env, check=True)
    scontrol = _which("scontrol")
    end = time.monotonic() + timeout_s
    state = ""
    while time.monotonic() < end:
        out = subprocess.run([scontrol, "show", "nodes", "--oneliner"], env=env,
                             capture_output=True, text=True)
        match = re.search(r"State=(\S+)", out.stdout)
        state = match.group(1) if match else out.stderr.strip()
        if state.startswith("IDLE"):
            return {"SLURM_CONF": str(conf)}
        time.sleep(1.0)
    stop(folder)
    raise RuntimeError(f"the local SLURM node is not idle after {timeout_s:.0f} s (state "
                       f"{state!r}); see {folder / 'slurmctld.log'} and {folder / 'slurmd.log'}")


def _kill(pid_file: Path, timeout_s: float = 20.0) -> None:
    try:
        pid = int(pid_file.read_text().split()[0])
    except (OSError, ValueError, IndexError):
        return
    try:
        os.kill(pid, signal.SIGTERM)
    except ProcessLookupError:
        return
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return
        time.sleep(0.2)
    os.kill(pid, signal.SIGKILL)


def stop(folder: Path) -> None:
    """Stop the daemons that :func:`start` started in ``folder`` (slurmd, slurmctld, munged)."""
    folder = Path(folder).resolve()
    for pid_file in ("slurmd.pid", "slurmctld.pid", "munged.pid"):
        _kill(folder / pid_file)


def main(argv: list[str] | None = None) -> int:
    """``up FOLDER`` / ``down FOLDER``; ``up`` prints the ``export SLURM_CONF=…`` line."""
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 2 or argv[0] not in ("up", "down"):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    if argv[0] == "down":
        stop(Path(argv[1]))
        return 0
    try:
        env = start(Path(argv[1]))
    except (RuntimeError, subprocess.CalledProcessError) as err:
        print(f"local_slurm: {err}", file=sys.stderr)
        return 1
    print(f"export SLURM_CONF={env['SLURM_CONF']}   # one-node cluster on {socket.gethostname()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
