"""A new user's first real campaign, through the ``leopod`` console command only (issue 23).

``leopod init`` for GRACE-A 2007-03-21 writes a campaign whose inputs are download families of
the catalogue; a local HTTP mirror on 127.0.0.1 (Python's http.server in a thread) serves a
temporary folder laid out as the catalogue's archives expect it (``shared``: the day's
folder of onboard RINEX, CODE orbits and clocks; ``igs_station``: ``pcv_archive/`` with the
IGS05 ANTEX), filled with copies of ../shared/data/grace-a_2007-080 made here; every other
archive points at a closed port, so nothing leaves the machine. The user adds one overlay file
(the mirror's URLs, and the kinematic orbit as an independent check), then ``leopod check``,
``leopod run --progress on`` to the float and kinematic orbits, and ``leopod compare``.

Why the kinematic orbit: it is a geometric solution, epoch by epoch from the same phases, with
no force model, pulses or empirical accelerations; the float orbit is reduced-dynamic. A frame,
time-tag, antenna or product mismatch in the chain separates them by metres, while the two
agree to a few centimetres when the chain is right: GRACE kinematic positions are good to a few
centimetres per axis (Jäggi et al. 2007), the float orbit of this day to about 1 cm (sub-arc
overlap 1.3 cm, README). Authority for the files: ../shared/data/MANIFEST.md.
"""

from __future__ import annotations

import functools
import gzip
import re
import shutil
import socket
import subprocess
import sys
import threading
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import numpy as np
import pytest
import yaml

REPO = Path(__file__).resolve().parents[2]
LEOPOD = str(Path(sys.executable).with_name("leopod"))
DAY_FILES = ("graa0800.07o.gz", "cod14193.sp3.gz", "cod14193.clk.gz")
FLOAT = "results/grace-a-2007/float_pod/grace-a/2007-080.sp3"
KINEMATIC = "results/grace-a-2007/kinematic_pod/grace-a/2007-080.sp3"


class _Mirror(SimpleHTTPRequestHandler):
    """Serves the mirror folder and records the paths asked for."""

    def log_message(self, format, *args):
        self.server.requested.append(self.path)


def _mirror(root: Path, shared_data: Path) -> None:
    day = root / "shared" / "grace-a_2007-080"
    day.mkdir(parents=True)
    for name in DAY_FILES:
        shutil.copy(shared_data / "grace-a_2007-080" / name, day / name)
    antex = root / "station" / "pcv_archive" / "igs05_1402.atx"   # the IGS layout, unpacked
    antex.parent.mkdir(parents=True)
    with gzip.open(shared_data / "grace-a_2007-080" / "igs05_1402.atx.gz") as src:
        antex.write_bytes(src.read())


def _closed_port_url() -> str:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return f"http://127.0.0.1:{sock.getsockname()[1]}"


def _leopod(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([LEOPOD, *args], capture_output=True, text=True, cwd=cwd,
                          timeout=1200)


@pytest.mark.shared
def test_a_new_user_runs_grace_a_from_an_archive_mirror(shared_data, tmp_path):
    _mirror(tmp_path / "mirror", shared_data)
    server = ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(
        _Mirror, directory=str(tmp_path / "mirror")))
    server.requested = []
    threading.Thread(target=server.serve_forever, daemon=True).start()
    work = tmp_path / "work"
    work.mkdir()
    try:
        proc = _leopod("init", "grace-a-2007", "--satellite", "GRACE-A", "--start",
                       "2007-03-21", "--end", "2007-03-21", cwd=work)
        assert proc.returncode == 0, proc.stderr
        campaign = work / "grace-a-2007.yaml"
        assert "download:grace_a_obs" in campaign.read_text()

        url = f"http://127.0.0.1:{server.server_address[1]}"
        archives = yaml.safe_load((REPO / "config" / "catalogue.yaml").read_text())["archives"]
        urls = dict.fromkeys(archives, _closed_port_url())
        urls.update(shared=f"{url}/shared", igs_station=f"{url}/station")
        overlay = work / "mirror.yaml"
        overlay.write_text(yaml.safe_dump({
            "download": {"archive_urls": urls, "retries": 0, "timeout_s": 10.0},
            "kinematic": {"enabled": True}}))

        proc = _leopod("check", campaign.name, overlay.name, cwd=work)
        assert proc.returncode == 0, proc.stdout + proc.stderr
        assert "satellites.grace-a.observations: downloaded by the workflow" in proc.stdout

        proc = _leopod("run", campaign.name, overlay.name, "--cores", "2", "--progress", "on",
                       "--", FLOAT, KINEMATIC, cwd=work)
        assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    finally:
        server.shutdown()
        server.server_close()
    # the four inputs came from the mirror, in the archives' layouts
    assert {"/shared/grace-a_2007-080/" + n for n in DAY_FILES} | {
        "/station/pcv_archive/igs05_1402.atx"} <= set(server.requested)
    # progress: one line per job started and finished, up to all of them
    done = re.findall(r"^\[\s*(\d+)/(\d+)\s+\d+%\] done  (\S+)", proc.stdout, flags=re.M)
    assert done and done[-1][0] == done[-1][1]
    assert {"download_cod_orbit", "ingest", "float_pod", "kinematic_pod"} <= {
        rule for _, _, rule in done}

    # the daily SP3 covers its day: 00:00:00 to the last epoch before 24:00 at the output
    # step, although the GRACE-A data of 2007-080 start at 00:00:30 and end at 23:59:30 (the
    # SP3-d convention of a daily product; georinex, an independent reader, reads it)
    gr = pytest.importorskip("georinex")
    step = float(yaml.safe_load(campaign.read_text()).get("pod", {}).get("output_step_s", 30.0))
    sp3 = gr.load(work / FLOAT)
    t = sp3.time.values
    assert t[0] == np.datetime64("2007-03-21T00:00:00", "ns")
    assert t[-1] == np.datetime64("2007-03-22T00:00:00", "ns") - np.timedelta64(int(step), "s")
    assert np.all(np.diff(t) == np.timedelta64(int(step), "s"))
    assert np.isfinite(sp3.position.values).all()

    proc = _leopod("compare", KINEMATIC, FLOAT, cwd=work)
    assert proc.returncode == 0, proc.stderr
    total = next(line.split() for line in proc.stdout.splitlines()
                 if line.startswith("total"))
    epochs = int(total[1])
    mean_rtn = [float(x) for x in total[2:5]]
    rms_rtn, rms_3d = [float(x) for x in total[10:13]], float(total[13])
    assert epochs > 0.9 * 2880                   # the day's 30-s epochs, nearly all solved
    assert all(abs(m) < 2.0 for m in mean_rtn)   # [cm]: no offset between the solutions
    assert all(r < 5.0 for r in rms_rtn) and rms_3d < 8.0
