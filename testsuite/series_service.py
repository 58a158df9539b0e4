"""The map-series service (tools/actinia/service.sh) started for a test (issues 30 and 49).

:func:`started` starts Redis and actinia on 127.0.0.1 on free ports in a
folder of the test and stops them again whatever happens (also when the
start fails half-way); :func:`missing` names what is not installed.
"""

import contextlib
import json
import os
import shutil
import socket
import subprocess
from dataclasses import dataclass

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DIST = os.environ.get("HISTO_DIST", os.path.join(ROOT, "dist"))
ACTINIA_VENV = os.environ.get("ACTINIA_VENV", os.path.expanduser(
    "~/.local/share/histo/actinia-venv"))
SERVICE = os.path.join(ROOT, "tools", "actinia", "service.sh")


@dataclass(frozen=True)
class Service:
    """A started service: its URL, folder, Redis port and work folder."""
    url: str
    folder: str
    redis_port: int
    work: str

    @property
    def credentials(self):
        """The file of the histo user's credentials (service.sh writes it)."""
        return os.path.join(self.folder, "credentials")

    def user_password(self):
        with open(self.credentials) as f:
            doc = json.load(f)
        return doc["user"], doc["password"]


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def missing():
    """What the service needs and is not installed (texts; empty: nothing)."""
    return [what for what, ok in (
        ("actinia-core (make actinia)", os.path.exists(os.path.join(ACTINIA_VENV, "bin",
                                                                    "gunicorn"))),
        ("redis-server (Debian redis-server)", shutil.which("redis-server")),
        ("the staged suite (make build)", os.path.exists(os.path.join(DIST, "scripts",
                                                                      "v.histo.lod2"))),
        ("GRASS", shutil.which("grass"))) if not ok]


@contextlib.contextmanager
def started(folder):
    """The service started in ``folder`` (stopped on leaving, whatever happens)."""
    port, redis_port = free_port(), free_port()
    env = dict(os.environ, DIST=DIST, ACTINIA_VENV=ACTINIA_VENV)
    try:
        subprocess.run(["bash", SERVICE, "start", folder, str(port), str(redis_port)],
                       check=True, env=env, capture_output=True, text=True, timeout=180)
        yield Service("http://127.0.0.1:{}".format(port), folder, redis_port,
                      os.path.join(folder, "work"))
    finally:
        subprocess.run(["bash", SERVICE, "stop", folder], env=env, capture_output=True)
