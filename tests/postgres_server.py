"""A throwaway PostgreSQL server on loopback, for the shared-study tests.

The server is Debian's (``apt-get install postgresql``, which ``.ci/run`` does): a temporary
cluster made by ``initdb`` with trust authentication, listening on 127.0.0.1 on a free port,
its socket in the cluster's own directory, stopped and deleted afterwards. PostgreSQL refuses
to run as root, so under root the cluster belongs to the ``postgres`` user and its commands run
through ``runuser``. :func:`postgres_cluster` also stops and starts the server in between, for the
tests of a study whose server restarts (tests/test_tune_faults.py).
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
    """PostgreSQL cannot serve the tests here: its programs are missing, or the server would not start. The message
    is one line (what is missing or which command failed, and its last words), for ``pytest.fail``."""


def _last_line(*texts: str) -> str:
    for text in texts:
        lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
        if lines:
            return lines[-1]
    return "no output"


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


class PostgresCluster:
    """A running throwaway server: ``url`` of its database; ``stop()`` and ``start()`` take it down and up
    again on the same port and data (``-m fast``: open connections are cut, as a crash or an
    administrator's restart would)."""

    def __init__(self, url: str, run, pg_ctl: str, data: Path, log: Path, options: str):
        self.url, self._run, self._pg_ctl, self._data, self._log, self._options = url, run, pg_ctl, data, log, options
        self.running = True

    def stop(self) -> None:
        self._run(self._pg_ctl, "-D", str(self._data), "-m", "fast", "-w", "stop")
        self.running = False

    def start(self) -> None:
        self._run(self._pg_ctl, "-D", str(self._data), "-l", str(self._log), "-o", self._options, "-w", "-t", "60",
                  "start")
        self.running = True


@contextmanager
def postgres_cluster():
    """Yields a :class:`PostgresCluster` with a fresh, empty database; stops the server and removes its files
    after."""
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
            server = log.read_text(errors="replace") if log.exists() else ""
            raise PostgresMissing(f"PostgreSQL would not start: {Path(cmd[0]).name} {cmd[-1]} exited "
                                  f"{done.returncode}: {_last_line(server, done.stderr, done.stdout)}")

    try:
        run(initdb, "-D", str(data), "-A", "trust", "-U", "postgres", "--no-sync", "-E", "UTF8")
        options = f"-c listen_addresses=127.0.0.1 -c port={port} -c unix_socket_directories={base} -c fsync=off"
        cluster = PostgresCluster(f"postgresql://postgres@127.0.0.1:{port}/postgres", run, pg_ctl, data, log, options)
        cluster.start()
        try:
            yield cluster
        finally:
            if cluster.running:
                cluster.stop()
    finally:
        for _ in range(20):  # the server's last files can lag its exit by a moment
            shutil.rmtree(base, ignore_errors=True)
            if not base.exists():
                break
            time.sleep(0.1)


@contextmanager
def postgres_server():
    """Yields the URL of a fresh, empty database; stops the server and removes its files after."""
    with postgres_cluster() as cluster:
        yield cluster.url
