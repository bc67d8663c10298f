"""A study's storage (issue 50 §4-6, §9): a SQLite URL that names no file, a damaged or foreign study file, tunes
started together on a new file, and a study resumed with settings that would change what it means."""

from __future__ import annotations

import sqlite3
import subprocess
import sys
import textwrap
from contextlib import closing

import pytest
from sqlalchemy.engine import make_url

from aero_env.config import ConfigError, load_config
from agents.study_storage import open_storage
from agents.tune import TuneSettings, tune

from .conftest import COARSE, PAPER, ROOT

FAST = {"scene.frames": 3, **COARSE}


@pytest.fixture(scope="module")
def cfg():
    return load_config(PAPER, FAST)


# ---- sqlite:/// with no file ----

@pytest.mark.parametrize("url", ["sqlite:///", "sqlite://", "sqlite:///:memory:", "sqlite+pysqlite:///",
                                 "sqlite:///study.db", "sqlite:////tmp/study.db", "sqlite:///study.db?timeout=5",
                                 "postgresql://u@h/db"])
def test_a_sqlite_url_that_names_no_file_is_refused(url):
    # SQLAlchemy's own reading of the URL says which keep the study in memory: no file, or SQLite's ":memory:"
    parsed = make_url(url)
    in_memory = parsed.get_backend_name() == "sqlite" and parsed.database in (None, "", ":memory:")
    if not in_memory:
        TuneSettings(storage=url).check()
        return
    with pytest.raises(ConfigError) as refused:
        TuneSettings(storage=url, workers=2).check()
    line = str(refused.value)
    assert line.startswith(f"--storage {url!r}:") and "sqlite:///study.db" in line and "\n" not in line


# ---- a damaged study file ----

def study_file(tmp_path, cfg) -> str:
    """A study of 3 trials in a SQLite file, as a tune leaves it (its WAL folded back into the file)."""
    url = f"sqlite:///{tmp_path / 's.db'}"
    tune(cfg, TuneSettings(sampler="random", trials=3, storage=url, study="s", progress=False))
    with closing(sqlite3.connect(tmp_path / "s.db")) as conn:
        conn.execute("PRAGMA wal_checkpoint(TRUNCATE)")
    return url


def overwrite_page(path, table: str) -> int:
    """Overwrite the page holding ``table``'s rows past its header bytes, as a failing disk might; the page number."""
    with closing(sqlite3.connect(path)) as conn:
        page = conn.execute("SELECT rootpage FROM sqlite_master WHERE name = ?", (table,)).fetchone()[0]
        size = conn.execute("PRAGMA page_size").fetchone()[0]
    with open(path, "r+b") as f:
        f.seek((page - 1) * size + 8)
        f.write(bytes((7 * i + 3) % 256 for i in range(size - 8)))
    return page


# trials: the 108-line traceback; study_directions: the study read as one with no objective, whose every trial then
# failed, forever
@pytest.mark.parametrize("table", ["trials", "trial_params", "study_directions"])
def test_a_damaged_study_file_is_refused_in_one_line_naming_it_and_the_page(cfg, tmp_path, table):
    url = study_file(tmp_path, cfg)
    path = tmp_path / "s.db"
    page = overwrite_page(path, table)
    before = path.read_bytes()
    with pytest.raises(ConfigError) as refused:
        open_storage(url)
    line = str(refused.value)
    assert line.startswith(f"study file {str(path)!r} (--storage {url}): damaged (On tree page {page} ")
    assert "move it aside" in line and "\n" not in line
    assert path.read_bytes() == before  # refused before anything was written to it


@pytest.mark.parametrize("content", [b"not a database\n", bytes(range(256)) * 64], ids=["text", "binary"])
def test_a_file_that_is_not_a_database_is_refused_in_one_line(tmp_path, content):
    path = tmp_path / "notes.db"
    path.write_bytes(content)
    with pytest.raises(ConfigError) as refused:
        open_storage(f"sqlite:///{path}")
    assert str(refused.value).startswith(f"study file {str(path)!r} (--storage sqlite:///{path}): not a SQLite "
                                         f"database")
    assert path.read_bytes() == content


def test_the_command_refuses_a_damaged_study_in_one_line(cfg, tmp_path):
    url = study_file(tmp_path, cfg)
    overwrite_page(tmp_path / "s.db", "trials")
    done = subprocess.run([sys.executable, "-m", "aero_env.cli", "tune", str(PAPER), "--set", "scene.frames=3",
                           "--trials", "5", "--storage", url, "--study", "s", "--no-progress"],
                          capture_output=True, text=True, cwd=tmp_path, timeout=120)
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr[-3000:]
    assert done.stderr.startswith("aero-env: file error: study file ") and "damaged" in done.stderr


# ---- a study resumed with other settings ----

@pytest.mark.parametrize("option, field, stored, given", [
    ("--seed", "seed", 0, 1), ("--sampler", "sampler", "random", "tpe"),
    ("--seeds-per-design", "seeds_per_design", 1, 2), ("--robust", "robust", 0, 1)])
def test_a_study_resumed_with_a_setting_that_changes_it_is_refused(cfg, tmp_path, option, field, stored, given):
    url = f"sqlite:///{tmp_path / 's.db'}"
    made = dict(sampler="random", trials=2, seed=0, seeds_per_design=1, robust=0, storage=url, study="s",
                progress=False)
    assert made[field] == stored
    tune(cfg, TuneSettings(**made))
    with pytest.raises(ConfigError) as refused:
        tune(cfg, TuneSettings(**{**made, "trials": 3, field: given}))
    assert str(refused.value) == (f"{option} {given}: study 's' was run with {option} {stored}; resume it with "
                                  f"{option} {stored}, or give a new --study name")
    assert tune(cfg, TuneSettings(**{**made, "trials": 3})).trials_run == 1  # the same settings resume it


# ---- tunes started together on a new file ----

RACER = textwrap.dedent("""
    import os, sys, time
    from aero_env.config import load_config
    from agents.tune import TuneSettings, tune
    from agents.study_storage import import_optuna
    import_optuna()
    cfg = load_config(sys.argv[1], {"scene.frames": 3, "sim.fidelity": "mbd", "sim.dt": 0.001})
    settings = TuneSettings(sampler="random", trials=1, storage=sys.argv[2], study=sys.argv[3], progress=False)
    print("ready", flush=True)
    while not os.path.exists(sys.argv[4]):  # all released at once
        time.sleep(0.0005)
    tune(cfg, settings)
    print("done", flush=True)
""")


@pytest.mark.slow
def test_tunes_started_together_on_a_new_sqlite_file_all_run(tmp_path):
    """Four processes, each with a study of its own, released at the same instant onto a new file: each made
    Optuna's tables as it went, and one or more failed "table studies already exists" in 7 of 8 such rounds."""
    for round_ in range(4):
        folder = tmp_path / str(round_)
        folder.mkdir()
        url, go = f"sqlite:///{folder / 'new.db'}", folder / "go"
        racers = [subprocess.Popen([sys.executable, "-c", RACER, str(PAPER), url, f"p{i}", str(go)], cwd=ROOT,
                                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for i in range(4)]
        for racer in racers:
            assert racer.stdout.readline() == "ready\n", racer.communicate()[1][-3000:]
        go.touch()
        for racer in racers:
            out, err = racer.communicate(timeout=300)
            assert racer.returncode == 0 and out == "done\n", err[-3000:]
        with closing(sqlite3.connect(folder / "new.db")) as conn:  # read by SQLite itself, not through Optuna
            rows = conn.execute("SELECT study_name, count(*) FROM trials JOIN studies USING (study_id) "
                                "WHERE state = 'COMPLETE' GROUP BY study_name").fetchall()
            assert sorted(rows) == [(f"p{i}", 1) for i in range(4)], round_
            assert conn.execute("SELECT count(*) FROM version_info").fetchone()[0] == 1


WRITER = textwrap.dedent("""
    import sqlite3, sys, time
    held = sqlite3.connect(sys.argv[1], isolation_level=None)
    held.execute("BEGIN IMMEDIATE")  # the write lock a tune holds while it makes its study or commits a trial
    held.execute("CREATE TABLE held (x)")
    print("held", flush=True)
    time.sleep(float(sys.argv[2]))
    held.execute("ROLLBACK")
""")


def test_a_study_opened_while_another_tune_writes_to_it_waits_for_the_write(tmp_path):
    """The switch to WAL needs the file to itself, and SQLite refuses it at once ("database is locked", its busy
    timeout not asked) while another process holds the write lock: one of four tunes started together on a new
    file failed so in CI. Here a file still in SQLite's default journal is opened while another process holds the
    write lock for 1 s: the open waits for it and leaves the file in WAL."""
    path = tmp_path / "s.db"
    open_storage(f"sqlite:///{path}").engine.dispose()  # Optuna's tables made; then back to the default journal
    with closing(sqlite3.connect(path)) as conn:
        assert conn.execute("PRAGMA journal_mode=DELETE").fetchone()[0] == "delete"
    writer = subprocess.Popen([sys.executable, "-c", WRITER, str(path), "1.0"], stdout=subprocess.PIPE, text=True)
    try:
        assert writer.stdout.readline() == "held\n"
        open_storage(f"sqlite:///{path}").engine.dispose()
    finally:
        writer.wait(timeout=60)
    with closing(sqlite3.connect(path)) as conn:
        assert conn.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
