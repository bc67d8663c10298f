"""A throwaway PostgreSQL server on loopback, for the shared-study tests.

The server is Debian's (``apt-get install postgresql``, which ``.ci/run`` does): a temporary
cluster made by ``initdb`` with trust authentication, listening on 127.0.0.1 on a free port,
its socket in the cluster's own directory, stopped and deleted afterwards. PostgreSQL refuses
to run as root, so under root the cluster belongs to the ``postgres`` user and its commands run
through ``runuser``.
"""

from __future__ import annotations

import glob
import os
import shutil
import socket
import subprocess
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path

INSTALL = "sudo apt-get install -y postgresql   (Debian/Ubuntu; .ci/run does this)"


class PostgresMissing(RuntimeError):
    pass


def find_bin(name: str) -> str:
    """A PostgreSQL server program: on PATH, or in Debian's versioned directory."""
    found = shutil.which(name) or next(iter(sorted(glob.glob(f"/usr/lib/postgresql/*/bin/{name}"), reverse=True)),
                                       None)
    if not found:
        raise PostgresMissing(f"PostgreSQL's {name} was not found on PATH or in /usr/lib/postgresql/*/bin; "
                              f"install the server: {INSTALL}")
    return found


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextmanager
def postgres_server():
    """Yields the URL of a fresh, empty database; stops the server and removes its files after."""
    initdb, pg_ctl = find_bin("initdb"), find_bin("pg_ctl")
    as_root = os.geteuid() == 0
    if as_root and shutil.which("runuser") is None:
        raise PostgresMissing("running as root, and runuser (util-linux) is missing to start PostgreSQL as "
                              "the postgres user")
    prefix: list[str] = []
    base = Path(tempfile.mkdtemp(prefix="aero-pg-"))  # in /tmp, which the postgres user can reach
    if as_root:
        import pwd

        try:
            pw = pwd.getpwnam("postgres")
        except KeyError:
            raise PostgresMissing(f"running as root and there is no postgres user to own the cluster; {INSTALL}")
        os.chown(base, pw.pw_uid, pw.pw_gid)
        prefix = ["runuser", "-u", "postgres", "--"]
    data, port = base / "data", _free_port()
    log = base / "server.log"

    def run(*cmd: str) -> None:
        done = subprocess.run([*prefix, *cmd], capture_output=True, text=True, timeout=120)
        if done.returncode != 0:
            extra = log.read_text()[-2000:] if log.exists() else ""
            raise RuntimeError(f"{' '.join(cmd)} failed ({done.returncode}): {done.stderr[-2000:]}{extra}")

    try:
        run(initdb, "-D", str(data), "-A", "trust", "-U", "postgres", "--no-sync", "-E", "UTF8")
        options = f"-c listen_addresses=127.0.0.1 -c port={port} -c unix_socket_directories={base} -c fsync=off"
        run(pg_ctl, "-D", str(data), "-l", str(log), "-o", options, "-w", "-t", "60", "start")
        try:
            yield f"postgresql://postgres@127.0.0.1:{port}/postgres"
        finally:
            run(pg_ctl, "-D", str(data), "-m", "fast", "-w", "stop")
    finally:
        for _ in range(20):  # the server's last files can lag its exit by a moment
            shutil.rmtree(base, ignore_errors=True)
            if not base.exists():
                break
            time.sleep(0.1)
