"""Reinforcement learning of designs with stable-baselines3 (PPO or SAC, on torch's CPU build).

The environment is a contextual bandit: one step per episode, the observation is the drawn
scene (context), the action is the design. On a scene whose context is drawn at every reset
(``aero_env/AerialAcrobatVaried-v0``, or any config with ``context`` ranges) the policy learns
a map from context to design, which one black-box design cannot be.

A training run writes to its directory ``DIR``:

| file              | what                                                                 |
|-------------------|----------------------------------------------------------------------|
| ``model.zip``     | the trained policy (``PPO.load`` / ``SAC.load``)                     |
| ``config.yaml``   | the scene it was trained on, complete (``load_config`` reads it)     |
| ``run.json``      | algorithm, hyper-parameters, seed, timesteps, time, config sha256    |
| ``evaluations.npz`` | the periodic evaluations (SB3's ``EvalCallback``)                  |
| ``monitor.csv``   | every training episode's reward (SB3's ``Monitor``)                  |
| ``learning_curve.png`` | training reward (rolling mean) and the periodic evaluations     |

``evaluate(DIR)`` runs the deterministic policy on fresh episode seeds and reports the mean and
spread of its reward. Hyper-parameters are the documented defaults below, overridden by name;
each override is checked against :data:`HP_SPECS` (its type and range) before anything is built.

``DIR`` must be new or empty (``overwrite=True`` first removes a previous run's files, so that
two runs never share one learning curve). A run stopped by Ctrl-C or SIGTERM keeps what it learnt: the
policy so far in ``model.zip`` (and SAC's replay buffer), ``run.json`` marked ``interrupted``
with ``timesteps_done``; ``resume=True`` (``aero-env train ... --resume``) continues it up to
``timesteps`` with the same settings, appending to its monitor files (one more per vector env,
``r1-0.monitor.csv``, ...) and its evaluations. A resumed run is not bit-identical to one that
was never stopped (the environments restart their episodes and PPO its rollout).

A file of the run that does not read back (cut, empty, edited: :func:`read_run_json`, :func:`read_run_config`,
:func:`load_policy`) stops ``evaluate`` and a resume with one line naming it and what to do; a refused resume
leaves ``DIR`` as it found it.
"""

from __future__ import annotations

import contextlib
import copy
import dataclasses
import hashlib
import json
import math
import os
import shlex
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from types import SimpleNamespace
from typing import Any, Mapping

import numpy as np

from aero_env.config import Config, ConfigError, MissingExtra, did_you_mean, from_dict, load_config, shown
from aero_env.files import write_atomically
from aero_env.scene_args import MAX_SEED, check_output_dir

from .interrupts import SigintOnce, children_ignore_sigint
from .options import ALGOS, check_choice, check_ints

# Every step is a whole episode, so there is nothing to discount or bootstrap: gamma is moot and
# small rollouts/batches suit the few thousand (slow) episodes a design study can afford. PPO's
# first designs spread with std e^-1 = 0.37 about the box's centre, as CMA-ES's first population
# does (a third of the box); SB3's default std of 1 would throw a third of them onto the box's faces.
ALGO_DEFAULTS: dict[str, dict[str, Any]] = {
    "ppo": dict(learning_rate=3e-4, n_steps=64, batch_size=64, n_epochs=10, gamma=0.0, gae_lambda=1.0,
                ent_coef=0.0, clip_range=0.2, policy_kwargs=dict(net_arch=[64, 64], log_std_init=-1.0)),
    "sac": dict(learning_rate=3e-4, buffer_size=100_000, learning_starts=100, batch_size=64, gamma=0.0,
                train_freq=1, gradient_steps=1, policy_kwargs=dict(net_arch=[64, 64])),
}
# What ``--hp`` may set, per algorithm: (type, low, high, low excluded). Ranges are SB3's own
# constraints (PPO's batch_size > 1, rates and discounts in [0, 1]) or, for counts, bounds past which
# the value is surely a slip. ``policy_kwargs`` is a mapping (net_arch: a list of layer widths).
_COMMON_HP = dict(learning_rate=(float, 0.0, 1.0, True), gamma=(float, 0.0, 1.0, False),
                  policy_kwargs=(dict, None, None, False))
HP_SPECS: dict[str, dict[str, tuple]] = {
    "ppo": dict(_COMMON_HP, n_steps=(int, 1, 10**7, False), batch_size=(int, 2, 10**7, False),
                n_epochs=(int, 1, 10**4, False), gae_lambda=(float, 0.0, 1.0, False),
                ent_coef=(float, 0.0, 1.0, False), clip_range=(float, 0.0, 1.0, True)),
    "sac": dict(_COMMON_HP, buffer_size=(int, 1, 10**8, False), learning_starts=(int, 0, 10**9, False),
                batch_size=(int, 1, 10**7, False), train_freq=(int, 1, 10**6, False),
                gradient_steps=(int, 1, 10**4, False)),
}
RUN_FILES = ("model.zip", "config.yaml", "run.json", "evaluations.npz", "learning_curve.png", "replay_buffer.pkl")
RUN_CORE = ("run.json", "model.zip", "config.yaml")  # what makes a folder a run: resumed, started from, loaded
EVAL_EPISODES = 10         # episodes per periodic evaluation
EVAL_SEED_OFFSET = 10_000  # evaluation seeds start here, away from the training envs' seeds


@dataclass(frozen=True)
class TrainSettings:
    algo: str = "ppo"
    timesteps: int = 2000
    n_envs: int = 1
    seed: int = 0
    eval_every: int = 500          # timesteps between periodic evaluations (0: none)
    vector: bool = False           # step the n_envs designs in one call of the native vector env
    hyperparameters: Mapping[str, Any] | None = None
    progress: bool = True

    def check(self) -> "TrainSettings":
        check_choice("algo", self.algo, ALGOS)
        check_ints(self, (("timesteps", 1, 10**9), ("n_envs", 1, 256), ("eval_every", 0, 10**9),
                          ("seed", 0, MAX_SEED)))
        hp = {}
        for name, value in (self.hyperparameters or {}).items():
            if name not in ALGO_DEFAULTS[self.algo]:
                hint = did_you_mean(name, ALGO_DEFAULTS[self.algo]).lstrip(";")
                raise ConfigError(f"--hp {name}: not a {self.algo} hyper-parameter here;{hint or ''} allowed: "
                                  f"{', '.join(ALGO_DEFAULTS[self.algo])}")
            hp[name] = check_hyperparameter(self.algo, name, value)
        if self.algo == "ppo":
            n_steps = hp.get("n_steps", ALGO_DEFAULTS["ppo"]["n_steps"])
            if n_steps * self.n_envs < 2:
                raise ConfigError(f"--hp n_steps={n_steps} with --n-envs {self.n_envs}: PPO needs a rollout of at "
                                  f"least 2 steps (n_steps x n_envs), allowed n_steps >= {math.ceil(2 / self.n_envs)}")
        return dataclasses.replace(self, hyperparameters=hp) if self.hyperparameters is not None else self

    def algo_kwargs(self) -> dict[str, Any]:
        # a copy all the way down: SAC adds use_sde to the policy_kwargs it is given, which made a second SAC run in
        # one process record other hyper-parameters, and its --resume refused
        return copy.deepcopy({**ALGO_DEFAULTS[self.algo], **(self.hyperparameters or {})})

    def steps_per_round(self) -> int:
        """Steps SB3 takes between two looks at the budget: PPO a whole rollout (n_steps x n_envs), SAC one step
        of every env; ``learn`` stops at the first whole round at or past the budget."""
        return self.algo_kwargs()["n_steps"] * self.n_envs if self.algo == "ppo" else self.n_envs


def progress_plan(settings: TrainSettings, todo: int) -> tuple[int, str, str | None]:
    """What the progress bar counts for ``todo`` more steps: the steps ``learn`` will take (``todo`` rounded up
    to whole rounds, :meth:`TrainSettings.steps_per_round`), the bar's description, and the line said before it
    when the rounding adds steps (None otherwise)."""
    unit = settings.steps_per_round()
    total = math.ceil(todo / unit) * unit
    if settings.algo == "ppo":
        n_steps = settings.algo_kwargs()["n_steps"]
        what = f"whole rollouts of n_steps x n_envs = {n_steps} x {settings.n_envs} = {unit} steps"
    else:
        what = f"a step of each of the {unit} envs at a time"
    line = None if total == todo else (f"aero-env train: {settings.algo.upper()} trains in {what}: {todo} steps "
                                       f"to go become {total}")
    return total, f"steps ({unit} a round)", line


def check_hyperparameter(algo: str, name: str, value: Any) -> Any:
    """``value`` of ``--hp name=value`` as its type, or a ConfigError naming it, the value and the range."""
    typ, lo, hi, lo_open = HP_SPECS[algo][name]
    where = f"--hp {name}={value!r}"
    if typ is dict:
        if not isinstance(value, Mapping):
            raise ConfigError(f"{where}: must be a mapping, e.g. policy_kwargs={{net_arch: [64, 64]}}")
        arch = value.get("net_arch")
        if arch is not None and not (isinstance(arch, list) and arch and all(
                isinstance(w, int) and not isinstance(w, bool) and 1 <= w <= 4096 for w in arch)):
            raise ConfigError(f"{where}: net_arch must be a list of layer widths, whole numbers in [1, 4096]")
        log_std = value.get("log_std_init")
        if log_std is not None and (isinstance(log_std, bool) or not isinstance(log_std, (int, float))
                                    or not -20.0 <= log_std <= 2.0):
            raise ConfigError(f"{where}: log_std_init must be a number in [-20, 2]")
        return dict(value)
    number = value
    if isinstance(value, str):
        try:
            number = float(value)  # YAML 1.1 reads 3e-4 (no dot) as a string
        except ValueError:
            pass
    kind = "a whole number" if typ is int else "a number"
    span = f"{'(' if lo_open else '['}{lo}, {hi}]"
    if isinstance(number, bool) or not isinstance(number, (int, float)) or not math.isfinite(number):
        raise ConfigError(f"{where}: must be {kind} in {span} (a {algo} hyper-parameter)")
    if typ is int:
        if not float(number).is_integer():
            raise ConfigError(f"{where}: must be {kind} in {span} (a {algo} hyper-parameter)")
        number = int(number)
    else:
        number = float(number)
    if number < lo or (lo_open and number == lo) or number > hi:
        raise ConfigError(f"{where}: out of range, allowed {span} (a {algo} hyper-parameter)")
    return number


class TrainInterrupted(Exception):
    """Ctrl-C or SIGTERM during training: the run so far was saved; ``run`` is what run.json now holds, ``by`` the
    KeyboardInterrupt that stopped it (:class:`~aero_env.signals.Terminated` for SIGTERM)."""

    def __init__(self, run: dict, out: Path, by: KeyboardInterrupt):
        super().__init__(f"interrupted at {run['timesteps_done']} of {run['timesteps']} timesteps")
        self.run, self.out, self.by = run, out, by


def check_run_dir(out: str | Path, overwrite: bool = False, resume: bool = False) -> None:
    """The run's folder before any work: new or empty, or ``overwrite``; with ``resume``, a run to go on with."""
    out = Path(out)
    if overwrite and resume:
        raise ConfigError("--overwrite with --resume: choose one (start the run again, or go on with it)")
    if not resume:
        check_output_dir(out, "--out", overwrite, "--overwrite to start the run in it again, or --resume to go on "
                                                  "with it")
        return
    missing = missing_run_files(out)
    if missing:
        raise ConfigError(f"--resume: {str(out)!r} holds no run to go on with (no {', '.join(missing)})")


def missing_run_files(folder: Path) -> list[str]:
    """The files of :data:`RUN_CORE` that ``folder`` lacks (none: it holds a run ``aero-env train`` wrote)."""
    return [name for name in RUN_CORE if not (folder / name).is_file()]


def policy_sha256(folder: str | Path) -> str:
    """The sha256 of a run's ``model.zip``: a finish records its start's, so a start trained again shows."""
    return file_sha256(Path(folder) / "model.zip")


def file_sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def clear_run(out: Path) -> None:
    """Remove a previous run's files from ``out`` (``--overwrite``); other files stay."""
    for name in RUN_FILES:
        (out / name).unlink(missing_ok=True)
    for f in out.glob("*.monitor.csv"):
        f.unlink()


def _resume_state(cfg: Config, settings: "TrainSettings", out: Path, init_from: str | Path | None = None) -> dict:
    """The stopped run in ``out``, checked against this call: same scene and settings (``init_from`` too: absent,
    or the run's own start, so that the command that started the run resumes it), more timesteps."""
    before = read_run_json(out)
    started = (before.get("init_from") or {}).get("dir")
    if init_from is not None and (started is None or Path(started).resolve() != Path(init_from).resolve()):
        raise ConfigError(f"--init-from {str(init_from)!r} with --resume: the run in {str(out)!r} started from "
                          f"{'a new policy' if started is None else repr(started)}; resume it with that, or without "
                          f"--init-from")
    if read_run_config(out) != cfg:
        raise ConfigError(f"--resume: the run in {str(out)!r} was trained on another scene (its config.yaml); "
                          f"give the same CONFIG and --set, or a new --out")
    for key in ("algo", "n_envs", "seed", "eval_every", "vector"):
        if before.get(key, False if key == "vector" else None) != getattr(settings, key):  # runs before --vector
            raise ConfigError(f"--{key.replace('_', '-')} {getattr(settings, key)!r}: the run in {str(out)!r} was "
                              f"trained with {before.get(key)!r}; resume it with the same value")
    if before.get("hyperparameters") != _jsonable(settings.algo_kwargs()):
        raise ConfigError(f"--hp: the run in {str(out)!r} was trained with {before.get('hyperparameters')}; resume "
                          f"it with the same --hp")
    done = int(before.get("timesteps_done", before.get("timesteps", 0)))
    if settings.timesteps <= done:
        raise ConfigError(f"--timesteps {settings.timesteps}: the run in {str(out)!r} already has {done}; give more "
                          f"to go on with it, allowed [{done + 1}, 1000000000]")
    return dict(before, timesteps_done=done)


def check_init_from(init_from: str | Path, cfg: Config, settings: "TrainSettings") -> dict:
    """The run ``init_from`` holds, checked as a start for a new PPO run on ``cfg`` with ``settings`` (before any
    work): a PPO run with the same network, trained on the same scene but for ``sim.fidelity`` (an action then names
    the same design, and the context reads the same). Its fidelity may differ: that is what it is for (pretrain at
    ``reduced``, finish at ``mbd``). Returns what the new run records of it, the start's own start nested (a chain
    of stages is counted whole) and its policy file's sha256 (a benchmark can tell a start replaced since)."""
    where = f"--init-from {str(init_from)!r}"
    if settings.algo != "ppo":
        # SAC keeps state outside its state dicts (the entropy coefficient, the replay buffer) and plays random
        # designs for its first learning_starts steps: a weights-only start would not be the pretrained policy
        raise ConfigError(f"{where} with --algo {settings.algo}: allowed with --algo ppo only (SAC's entropy "
                          f"coefficient and replay buffer would not carry over)")
    folder = Path(init_from)
    missing = missing_run_files(folder)
    if missing:
        raise ConfigError(f"{where}: no {', '.join(missing)} there; give a folder aero-env train wrote")
    try:
        before, trained_on = read_run_json(folder), read_run_config(folder)
    except ConfigError as e:
        raise ConfigError(f"{where}: {e}") from None
    if before.get("algo") != "ppo":
        raise ConfigError(f"{where}: a {before.get('algo')!r} run; allowed: a ppo run")
    theirs = (before.get("hyperparameters") or {}).get("policy_kwargs")
    ours = _jsonable(settings.algo_kwargs()).get("policy_kwargs")
    if theirs != ours:
        raise ConfigError(f"{where}: its network is policy_kwargs={theirs}, this run's {ours}; give the same "
                          f"--hp policy_kwargs")
    key = _first_difference(trained_on.replace({"sim.fidelity": cfg.sim.fidelity}).to_dict(), cfg.to_dict())
    if key is not None:
        raise ConfigError(f"{where}: trained on another scene ({key} differs; only sim.fidelity may); give the "
                          f"CONFIG and --set it was trained with")
    policy = folder / "model.zip"
    _sb3()  # the rl extra, or its one-line MissingExtra
    from stable_baselines3.common.save_util import load_from_zip_file

    try:
        load_from_zip_file(policy, load_data=False, device="cpu")
    except Exception as e:  # a cut or foreign file: refused here, before this run writes anything
        raise ConfigError(f"{where}: its model.zip does not load ({type(e).__name__}); train it again") from None
    record = dict(dir=str(folder), fidelity=trained_on.sim.fidelity,
                  timesteps_done=int(before.get("timesteps_done", before.get("timesteps", 0))),
                  wall_time=before.get("wall_time"), seed=before.get("seed"),
                  sha256=policy_sha256(folder))
    if before.get("init_from"):
        record["init_from"] = before["init_from"]
    return record


def _first_difference(a: Any, b: Any, prefix: str = "") -> str | None:
    """The first dotted key at which two config trees differ (None: they are the same)."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(a.keys() | b.keys()):
            found = _first_difference(a.get(k), b.get(k), f"{prefix}{k}.")
            if found:
                return found
        return None
    return None if a == b else prefix.rstrip(".")


def _sb3():
    try:
        import stable_baselines3
        import torch
    except ImportError:
        raise MissingExtra("aero-env train", "stable-baselines3 and torch", "rl") from None
    torch.set_num_threads(1)  # the networks are tiny: one thread is fastest and keeps runs bit-identical
    one_numba_thread()
    return stable_baselines3


def one_numba_thread() -> None:
    """The reduced model's batches on one thread while a policy trains or plays, unless ``NUMBA_NUM_THREADS`` is set.

    Training alternates a batch of ``n_envs`` designs with torch's update. On an idle 2-core machine a second
    numba thread saves about 0.3 ms of a 16-design batch; on a busy one, numba's OpenMP workers spin on the
    cores between batches and the docs' vector run at ``reduced`` took 48.5 s instead of 5.9 s (issue 36). The
    results are the same bits on any number of threads (tests/test_reduced_kernel.py)."""
    if "NUMBA_NUM_THREADS" not in os.environ:
        import numba

        numba.set_num_threads(1)


def make_env(cfg_dict: dict, monitor_file: str | None = None):
    """One environment of the scene (module-level, so that worker processes can build it)."""
    from stable_baselines3.common.monitor import Monitor

    from aero_env.envs import AerialAcrobatEnv

    return Monitor(AerialAcrobatEnv(from_dict(cfg_dict)), monitor_file)


def _vec_env(cfg: Config, n_envs: int, seed: int, monitor_dir: Path | None, prefix: str = "", vector: bool = False):
    from functools import partial

    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv, VecMonitor

    if vector:  # one call steps every design (at reduced: one kernel call; at a pymunk fidelity: a process pool)
        from aero_env.envs import AerialAcrobatVectorEnv

        from .vec_env import GymnasiumVecEnv

        monitor = str(monitor_dir / f"{prefix}vector") if monitor_dir else None
        # the pool asked for (aero-env's main is guarded): at a pymunk fidelity one process per core, as before
        venv = VecMonitor(GymnasiumVecEnv(AerialAcrobatVectorEnv(n_envs, cfg, workers=os.cpu_count() or 1)), monitor)
        venv.seed(seed)
        return venv
    fns = [partial(make_env, cfg.to_dict(), str(monitor_dir / f"{prefix}{i}") if monitor_dir else None)
           for i in range(n_envs)]
    venv = _worker_processes(SubprocVecEnv, fns) if n_envs > 1 else DummyVecEnv(fns)
    venv.seed(seed)
    return venv


def _worker_processes(cls, fns):
    """SB3's ``SubprocVecEnv`` (``cls``) of ``fns``, one spawned process each. Stopped while its workers start (a
    Ctrl-C or SIGTERM while they import), it kills the ones it launched: they ignore both signals
    (:func:`~agents.interrupts.children_ignore_sigint`), hold nothing yet, and SB3's ``terminate()`` at exit, a
    SIGTERM, would not end them (one lived on to print a BrokenPipeError traceback)."""
    venv = cls.__new__(cls)
    try:
        venv.__init__(fns, start_method="spawn")
    except BaseException:
        _kill_workers(venv)
        raise
    return venv


def _kill_workers(workers) -> None:
    for process in getattr(workers, "processes", ()):
        if process.is_alive():
            process.kill()
            process.join()


def _close(venv) -> None:
    """Close a vector env (None: not made yet) whose workers may already be gone, or stopped mid-step."""
    if venv is None:
        return
    workers = getattr(venv, "unwrapped", venv)  # a VecMonitor's innermost vector env
    if getattr(workers, "waiting", False):
        # Ctrl-C between a step's send and its last reply: SubprocVecEnv.close would wait again for every reply,
        # those already read too, forever (seen: a run hung at its save). A worker still stepping replies, then
        # reads the close that follows, so nothing needs waiting for: read what has come, then close.
        for remote in workers.remotes:
            with contextlib.suppress(EOFError, OSError):
                if remote.poll(0):
                    remote.recv()
        workers.waiting = False
    try:
        venv.close()
    except (EOFError, OSError, BrokenPipeError):
        _kill_workers(workers)  # a close cut short leaves workers that ignore SIGTERM waiting for a command


def train(cfg: Config, settings: TrainSettings, out: str | Path, overwrite: bool = False,
          resume: bool = False, callbacks: list | None = None, init_from: str | Path | None = None) -> dict:
    """Train a policy on ``cfg``'s scene and write the run's directory; returns run.json's content.

    ``callbacks``: more SB3 callbacks to run beside the periodic evaluation (a benchmark's hold-out curve);
    they only watch, so the policy learnt is the same with or without them.

    ``out`` must be new or empty unless ``overwrite`` (a previous run's files are removed first) or
    ``resume`` (go on with the run stopped there). Ctrl-C or SIGTERM saves the run so far and raises
    :class:`TrainInterrupted`; before the first training step, it removes what this call wrote (a resumed run
    is left as it was) and raises KeyboardInterrupt (Terminated for SIGTERM), as any other failure before that
    step does with its own exception. Either way ``out`` holds a whole run or none: every file is written
    atomically, and a save runs to its end through a second signal (:mod:`agents.interrupts`).

    ``init_from``: a run folder whose policy (weights and optimiser state) this run starts from instead of a new
    one (:func:`check_init_from`; PPO only): a policy pretrained at ``reduced`` finished at ``mbd``. ``run.json``
    records it under ``init_from``; ``timesteps`` and ``wall_time`` count this run's own. Resuming such a run
    takes the same ``init_from`` or none."""
    settings = settings.check()
    out = Path(out)
    if init_from is not None and Path(init_from).resolve() == out.resolve():
        raise ConfigError(f"--init-from {str(init_from)!r}: the run's own --out; copy the pretrained run elsewhere, "
                          f"or give a new --out")
    check_run_dir(out, overwrite, resume)
    before = _resume_state(cfg, settings, out, init_from) if resume else None
    start = check_init_from(init_from, cfg, settings) if init_from is not None and not resume else None
    sb3 = _sb3()
    if overwrite and out.is_dir():
        clear_run(out)
    kept = _Kept.of(out)
    segment = before.get("segments", 1) if before else 0  # monitor files of resumed segments: r1-0, r2-0, ...
    run = dict(algo=settings.algo, timesteps=settings.timesteps, n_envs=settings.n_envs, seed=settings.seed,
               eval_every=settings.eval_every, vector=settings.vector,
               hyperparameters=_jsonable(settings.algo_kwargs()))
    if start or (before and "init_from" in before):
        run["init_from"] = start or before["init_from"]
    todo, wall_before = settings.timesteps, 0.0
    if before:
        todo, wall_before = settings.timesteps - before["timesteps_done"], float(before.get("wall_time", 0.0))
    model = venv = evaluation = None
    t0 = time.perf_counter()
    with SigintOnce(f"aero-env train: stopping; it ends once {out} holds a whole run or nothing new") as sigint:
        try:
            with children_ignore_sigint():  # the workers leave Ctrl-C to this process, which closes them
                out.mkdir(parents=True, exist_ok=True)
                if not before:  # a resumed run's config.yaml is this scene already (_resume_state)
                    write_atomically(out / "config.yaml", lambda f: f.write(cfg.to_yaml().encode()))
                # a config.yaml cut between its sections still loads, as another scene: the sha256 tells it
                run["config_sha256"] = file_sha256(out / "config.yaml")
                venv = _vec_env(cfg, settings.n_envs, settings.seed + (1000 * segment), out,
                                f"r{segment}-" if segment else "", settings.vector)
                model, evaluation, extra = _model(sb3, cfg, settings, out, venv, before, segment, start)
                callbacks = [*(callbacks or []), *extra]
                if settings.progress:
                    callbacks.append(_progress_bar(settings, todo))
                t0 = time.perf_counter()
                with warnings.catch_warnings():  # the evaluations run one env in-process, whatever --n-envs says
                    warnings.filterwarnings("ignore", message="Training and eval env are not of the same type")
                    model.learn(todo, callback=callbacks, reset_num_timesteps=before is None)
                with sigint.saving():  # a Ctrl-C now waits for the finished run's files
                    wall = wall_before + time.perf_counter() - t0
                    _close(venv)
                    run.update(timesteps_done=int(model.num_timesteps), wall_time=wall,
                               episodes_per_second=model.num_timesteps / wall)
                    if before:
                        run["segments"] = segment + 1
                    _save_run(model, out, run, evaluation, keep_replay=False)
                return run
        except KeyboardInterrupt as stop:  # Ctrl-C, or SIGTERM (Terminated)
            with sigint.saving():
                _close(venv)
                if not _trained(model, before):  # stopped before the first step: the folder as this call found it
                    kept.restore()
                    raise
                wall = wall_before + time.perf_counter() - t0
                run.update(timesteps_done=int(model.num_timesteps), interrupted=True, segments=segment + 1,
                           wall_time=wall, episodes_per_second=model.num_timesteps / wall if wall > 0 else None)
                _save_run(model, out, run, evaluation, keep_replay=settings.algo == "sac")
            raise TrainInterrupted(run, out, stop) from None
        except Exception:
            with sigint.saving():
                _close(venv)  # its workers ignore SIGTERM (children_ignore_sigint): nothing else would end them
                if not _trained(model, before):  # a failed start (a damaged file of the run resumed, say) leaves
                    kept.restore()               # the folder as this call found it: no stray monitor file
            raise


def _trained(model, before: dict | None) -> bool:
    """Whether ``model`` took a training step in this call (``before``: the run it resumed)."""
    return model is not None and model.num_timesteps > (before["timesteps_done"] if before else 0)


def _model(sb3, cfg: Config, settings: TrainSettings, out: Path, venv, before: dict | None, segment: int,
           start: dict | None = None):
    """The model to train (new, new from ``start``'s policy, or the stopped run's), its periodic evaluation (None
    without) and the callbacks that run it."""
    from stable_baselines3.common.callbacks import EvalCallback

    cls = {"ppo": sb3.PPO, "sac": sb3.SAC}[settings.algo]
    evaluation, callbacks = None, []
    if settings.eval_every:
        eval_env = _vec_env(cfg, 1, settings.seed + EVAL_SEED_OFFSET, None)
        evaluation = EvalCallback(eval_env, n_eval_episodes=EVAL_EPISODES, log_path=str(out), verbose=0,
                                  eval_freq=max(1, settings.eval_every // settings.n_envs), warn=False)
        if before and (out / "evaluations.npz").is_file():
            (evaluation.evaluations_timesteps, evaluation.evaluations_results,
             evaluation.evaluations_length) = _read_evaluations(out / "evaluations.npz")
        callbacks.append(evaluation)
    if not before:
        model = cls("MlpPolicy", venv, seed=settings.seed, device="cpu", verbose=0, **settings.algo_kwargs())
        if start:  # this run's settings, seed and env; the pretrained run's weights and optimiser state
            model.set_parameters(str(Path(start["dir"]) / "model.zip"), exact_match=True, device="cpu")
        return model, evaluation, callbacks
    model = load_policy(cls, out / "model.zip", env=venv)
    model.set_random_seed(settings.seed + 1000 * segment)  # a resumed segment is seeded too
    replay = out / "replay_buffer.pkl"
    if settings.algo == "sac" and replay.is_file():
        try:
            model.load_replay_buffer(replay)
        except Exception as e:  # cut, or not a pickled replay buffer
            raise _unreadable(replay, f"not a replay buffer that loads ({_why(e)})",
                              f"remove it to resume with an empty buffer, or {_retrain(out)}") from None
    return model, evaluation, callbacks


def _read_evaluations(path: Path) -> tuple[list, list, list]:
    """A stopped run's periodic evaluations (its evaluations.npz) as EvalCallback keeps them, or a one-line error."""
    try:
        with np.load(path) as old:
            return ([int(t) for t in old["timesteps"]], [list(r) for r in old["results"]],
                    [list(r) for r in old["ep_lengths"]])
    except Exception as e:  # cut, not an .npz, an array missing or of another shape
        raise _unreadable(path, f"not the run's evaluations ({_why(e)})",
                          f"remove it to resume without the evaluations so far, or {_retrain(path.parent)}") from None


def _save_run(model, out: Path, run: dict, evaluation, keep_replay: bool) -> None:
    """Write the run's files, each atomically, the policy before the run.json that describes it: a run stopped
    anywhere in here keeps the previous save's pair, or this one's."""
    write_atomically(out / "model.zip", model.save)
    if keep_replay:  # SAC's replay buffer, for --resume
        write_atomically(out / "replay_buffer.pkl", model.save_replay_buffer)
    else:
        (out / "replay_buffer.pkl").unlink(missing_ok=True)
    if evaluation is not None and evaluation.evaluations_timesteps:
        # EvalCallback writes evaluations.npz in place, where a Ctrl-C can cut it: rewritten whole from memory
        write_atomically(out / "evaluations.npz", lambda f: np.savez(
            f, timesteps=evaluation.evaluations_timesteps, results=evaluation.evaluations_results,
            ep_lengths=evaluation.evaluations_length))
    write_atomically(out / "run.json", lambda f: f.write(json.dumps(run, indent=2).encode()))
    write_atomically(out / "learning_curve.png", lambda f: plot_learning_curve(out, f))


@dataclass
class _Kept:
    """What a run's folder held before this call wrote to it, so that a call stopped before it trained can
    leave the folder as it found it: the files it held (none, for a new folder) and the folders made for it."""

    out: Path
    names: frozenset
    made: tuple  # folders that did not exist, outermost first

    @classmethod
    def of(cls, out: Path) -> "_Kept":
        missing = [p for p in (out, *out.parents) if not p.exists()]
        names = frozenset(p.name for p in out.iterdir()) if out.is_dir() else frozenset()
        return cls(out, names, tuple(reversed(missing)))

    def restore(self) -> None:
        if self.out.is_dir():
            for p in self.out.iterdir():
                if p.name not in self.names and p.is_file():
                    p.unlink()
        for folder in reversed(self.made):
            with contextlib.suppress(OSError):  # not empty: something else was put there meanwhile
                folder.rmdir()


def _progress_bar(settings: TrainSettings, todo: int):
    """SB3's progress bar counting the steps ``learn`` will take (its own counts up to ``todo`` and runs past it, to
    the end of the last rollout: "256/200"); a line on stderr first says why the count exceeds ``--timesteps``."""
    import sys

    from stable_baselines3.common import callbacks as sb3_callbacks

    total, description, line = progress_plan(settings, todo)

    class WholeRounds(sb3_callbacks.ProgressBarCallback):
        def _on_training_start(self) -> None:
            if line:
                print(line, file=sys.stderr)
            self.pbar = sb3_callbacks.tqdm(total=total, desc=description)

    return WholeRounds()


def _jsonable(x):
    return json.loads(json.dumps(x, default=str))


# run.json's fields that a resume, a start from the run (--init-from) and evaluate read back: each one's type, and
# whether every run has it (the others came later, or only with a resume or --init-from)
RUN_FIELDS: dict[str, tuple[type, bool]] = {
    "algo": (str, True), "timesteps": (int, True), "n_envs": (int, True), "seed": (int, True),
    "eval_every": (int, True), "hyperparameters": (dict, True), "timesteps_done": (int, False),
    "wall_time": (float, False), "segments": (int, False), "vector": (bool, False), "init_from": (dict, False),
    "config_sha256": (str, False)}
_KINDS = {str: "a string", int: "a whole number >= 0", float: "a number", bool: "true or false",
          dict: "a JSON object"}


def _why(exc: BaseException) -> str:
    """An exception as a clause of a one-line message: its type and the start of its first line."""
    text = (str(exc).strip().splitlines() or [""])[0]
    text = text if len(text) <= 100 else text[:97] + "..."
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def _retrain(folder: Path) -> str:
    return f"train the run again (aero-env train ... --out {shlex.quote(str(folder))} --overwrite)"


def _unreadable(path: Path, what: str, fix: str | None = None) -> ConfigError:
    """A run's file that cannot be read back: one line naming it, what is wrong and what to do (default: train
    the run again)."""
    return ConfigError(f"run file {str(path)!r}: {what}; {fix or _retrain(path.parent)}")


def read_run_json(folder: str | Path) -> dict:
    """A run's run.json, its fields checked (:data:`RUN_FIELDS`), or a one-line error naming the file."""
    path = Path(folder) / "run.json"
    try:
        run = json.loads(path.read_bytes())
    except (OSError, ValueError) as e:  # ValueError: not UTF-8, or not JSON
        raise _unreadable(path, f"not the run's JSON record ({_why(e)})") from None
    if not isinstance(run, dict):
        raise _unreadable(path, f"a JSON {type(run).__name__}, not the run's record (an object)")
    for key, (kind, always) in RUN_FIELDS.items():
        if key not in run:
            if always:
                raise _unreadable(path, f"no {key!r} field")
            continue
        value = run[key]
        fits = isinstance(value, (int, float) if kind is float else kind)
        if not fits or (kind is not bool and isinstance(value, bool)) or (kind is int and value < 0):
            raise _unreadable(path, f"{key} = {shown(value)}: must be {_KINDS[kind]}")
    if run["algo"] not in ALGOS:
        raise _unreadable(path, f"algo = {shown(run['algo'])}: must be one of {', '.join(ALGOS)}")
    if "init_from" in run and not isinstance(run["init_from"].get("dir"), str):
        raise _unreadable(path, "init_from has no 'dir' (the folder the run started from)")
    return run


def read_run_config(folder: str | Path, overrides: Mapping[str, Any] | None = None) -> Config:
    """The scene a run was trained on (its config.yaml, the file run.json's ``config_sha256`` names, where it has
    one), or a one-line error naming the file and what to do; ``overrides`` (evaluate's ``--set``) apply once the
    file has read whole, so that their own errors stay theirs."""
    path = Path(folder) / "config.yaml"
    recorded = read_run_json(folder).get("config_sha256")
    if recorded is not None and file_sha256(path) != recorded:
        raise _unreadable(path, "cut or changed since the run was trained (not the sha256 its run.json records)")
    try:
        cfg = load_config(path)
    except ConfigError as e:
        said = str(e) if str(e).startswith("config file ") else f"run file {str(path)!r}: {e}"
        raise ConfigError(f"{said}; {_retrain(Path(folder))}") from None
    return load_config(path, overrides) if overrides else cfg


def load_policy(cls, path: Path, **kwargs):
    """``cls.load(path)`` (PPO or SAC) on the CPU, or a one-line error naming the file: cut, empty, not a zip, or a
    zip whose policy.pth or data is damaged."""
    try:
        return cls.load(path, device="cpu", **kwargs)
    except Exception as e:  # SB3 and torch raise a dozen kinds here, each with a traceback of 20-30 lines
        raise _unreadable(path, f"not a policy that loads ({_why(e)})") from None


def check_run_files(run_dir: str | Path) -> Path:
    """``run_dir`` as a Path, or a one-line error if it is not a folder ``aero-env train`` wrote."""
    run_dir = Path(run_dir)
    missing = missing_run_files(run_dir)
    if missing:
        raise ConfigError(f"{run_dir}: no {missing[0]}; expected the directory `aero-env train --out DIR` wrote")
    return run_dir


def load_run(run_dir: str | Path):
    """The trained model and its scene from a training directory."""
    sb3 = _sb3()
    run_dir = check_run_files(run_dir)
    run = read_run_json(run_dir)
    cls = {"ppo": sb3.PPO, "sac": sb3.SAC}[run["algo"]]
    return load_policy(cls, run_dir / "model.zip"), read_run_config(run_dir), run


def policy_actions(model, obs: np.ndarray) -> np.ndarray:
    """The deterministic policy's action for each row of ``obs`` (contexts x observation), asked one row at a time:
    the one inference path of ``aero-env evaluate`` and the benchmarks. A batch gives other float32 round-off
    than one row (torch's kernels sum in another order: 3e-7 apart), and that flips about 1 % of outcomes near a
    knife-edge; asked row by row, a context's design does not depend on which other contexts were asked with it."""
    obs = np.asarray(obs)
    return np.array([model.predict(row, deterministic=True)[0] for row in obs]).reshape(len(obs), -1)


def evaluate(run_dir: str | Path, episodes: int = 20, seed: int = 0, config: Config | None = None,
             against: Config | None = None) -> dict:
    """The deterministic policy's reward on ``episodes`` episode seeds ``seed, seed+1, ...``, and the design it
    chose for each episode's context (``per_episode``).

    ``against``: a config holding one fixed design for the scene (e.g. the best single design a robust tune
    wrote): its tunable fields are played on the same seeds, and ``against`` in the result reports its reward
    and whole-row share beside the policy's. Its robot (``design``) may differ from the scene's only in the
    tunable fields and the fields the scene draws; its ``scene`` section is not read.

    ``config``: another scene to evaluate on (default: the one it was trained on). It must pose the same
    design problem (:func:`_check_same_problem`): the same context, ranges included (the observation), and
    the same tunable fields (the action), in order. The tunables' ranges may differ; the action then maps
    onto the new scene's ranges (relative ranges follow it)."""
    check_ints(SimpleNamespace(episodes=episodes, seed=seed), (("episodes", 1, 10**6), ("seed", 0, MAX_SEED)))
    from aero_env.envs import AerialAcrobatEnv

    model, trained_on, run = load_run(run_dir)
    if config is not None:
        _check_same_problem(trained_on, config)
    env = AerialAcrobatEnv(config or trained_on)
    if env.observation_space != model.observation_space or env.action_space != model.action_space:
        raise ConfigError(f"the scene's spaces ({env.observation_space}, {env.action_space}) are not the policy's "
                          f"({model.observation_space}, {model.action_space})")
    fixed = None if against is None else fixed_design_action(env, against)
    per_episode, fixed_rows = [], []
    for s in range(seed, seed + episodes):
        obs, _ = env.reset(seed=s)
        action = policy_actions(model, obs[None])[0]
        _, r, _, _, info = env.step(np.clip(action, -1.0, 1.0))
        per_episode.append(dict(seed=s, context=info["context"], design=info["design"], reward=float(r),
                                traversals=int(info["traversals"]), outcome=info["outcome"]))
        if fixed is not None:
            env.reset(seed=s)  # the same context and build for the fixed design
            _, r, _, _, info = env.step(fixed)
            fixed_rows.append((float(r), int(info["traversals"])))
    rewards = [e["reward"] for e in per_episode]
    traversals = [e["traversals"] for e in per_episode]
    outcomes = [e["outcome"] for e in per_episode]
    rw = np.array(rewards)
    full_row = env.config.scene.frames - 1
    rep = dict(algo=run["algo"], fidelity=env.config.sim.fidelity, trained_at=trained_on.sim.fidelity,
               episodes=episodes, seeds=[seed, seed + episodes - 1], mean_reward=float(rw.mean()),
               std_reward=float(rw.std()), min_reward=float(rw.min()), max_reward=float(rw.max()),
               full_row=full_row, full_row_fraction=float(np.mean(np.array(traversals) >= full_row)),
               outcomes={o: outcomes.count(o) for o in sorted(set(outcomes))}, rewards=rewards,
               varied_context=[c.name for c in env.space.varied_context], per_episode=per_episode)
    if fixed is not None:
        fr = np.array([r for r, _ in fixed_rows])
        rep["against"] = dict(design=env.space.values(fixed), mean_reward=float(fr.mean()),
                              std_reward=float(fr.std()),
                              full_row_fraction=float(np.mean([t >= full_row for _, t in fixed_rows])),
                              rewards=fr.tolist())
    return rep


def fixed_design_action(env, design: Config) -> np.ndarray:
    """The action that plays ``design``'s tunable values in ``env``'s scene, or a ConfigError where ``design``
    is not one design for that scene (it changes another field, or a value lies outside its tunable range)."""
    from aero_env.design_space import changes_outside_tunables

    # only its design is played, on the scene evaluated: its scene section (frames, pitch, ...) is not read,
    # and the fields the scene draws at every reset are drawn for it too
    drawn = {c.name for c in env.config.context} | {k for c in env.config.context for k in c.linked}
    other = [k for k in changes_outside_tunables(env.config, design) if k.startswith("design.") and k not in drawn]
    if other:
        raise ConfigError(f"--against: the design differs from the scene's robot outside its tunables "
                          f"({', '.join(other[:4])}{', ...' if len(other) > 4 else ''}); give a design for this "
                          f"scene, e.g. the --out of aero-env tune on it")
    return env.space.action_for({t.name: design.value(t.name) for t in env.space.tunables}, dtype=np.float64)


def _check_same_problem(trained_on: Config, scene: Config) -> None:
    """A policy reads the context it was trained with (the fields, and their ranges, over which each observation
    is normalised) and writes the tunable fields it was trained with, in that order; their ranges may differ."""
    for section in ("context", "tunable"):
        theirs = [x.name for x in getattr(trained_on, section)]
        ours = [x.name for x in getattr(scene, section)]
        if theirs != ours:
            raise ConfigError(f"the scene evaluated on: its {section} is {ours}, the policy's is {theirs}; a policy "
                              f"{'observes' if section == 'context' else 'chooses'} the fields it was trained on, in "
                              f"that order")
    for ours, theirs in zip(scene.context, trained_on.context):
        if (ours.low, ours.high) != (theirs.low, theirs.high):
            raise ConfigError(f"the scene evaluated on: context {ours.name} ranges over [{ours.low}, {ours.high}], the "
                              f"policy's over [{theirs.low}, {theirs.high}]; an observation is the value's place in the "
                              f"range it was trained on, so the ranges must be the same")


def plot_learning_curve(run_dir: str | Path, path: str | Path) -> None:
    """Training episodes' reward (rolling mean over 50) and the periodic evaluations (mean ± std)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    run_dir = Path(run_dir)
    fig, ax = plt.subplots(figsize=(7, 4))
    ep = _monitor_rewards(run_dir)
    if len(ep):
        k = min(50, len(ep))
        roll = np.convolve(ep, np.ones(k) / k, mode="valid")
        ax.plot(np.arange(k, len(ep) + 1), roll, color="C0", label=f"training episodes (mean of {k})")
    ev = run_dir / "evaluations.npz"
    if ev.is_file():
        data = np.load(ev)
        m, s = data["results"].mean(axis=1), data["results"].std(axis=1)
        ax.errorbar(data["timesteps"], m, yerr=s, fmt="o-", color="C3", capsize=3,
                    label=f"evaluation ({data['results'].shape[1]} episodes, deterministic)")
    ax.set(xlabel="timesteps (= episodes = designs tried)", ylabel="reward (traversals)", title=run_dir.name)
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=110, format="png")  # path may be a file (write_atomically's)
    plt.close(fig)


def _monitor_rewards(run_dir: Path) -> np.ndarray:
    """Every training episode's reward, ordered by its end time across the vector's envs (and across the
    segments of a resumed run: each file's times count from its own start, which its first line gives)."""
    rows = []
    for f in sorted(run_dir.glob("*.monitor.csv")):
        head, _, rest = f.read_text(errors="replace").partition("\n")  # a damaged one: its lines that parse
        try:
            t_start = float(json.loads(head.lstrip("#")).get("t_start", 0.0))
        except (ValueError, AttributeError):
            t_start = 0.0
        for line in rest.splitlines()[1:]:  # the header r,l,t
            try:
                r, _, t = line.split(",")[:3]
                rows.append((t_start + float(t), float(r)))
            except ValueError:  # an empty line, or the last one cut by Ctrl-C while it was written
                continue
    return np.array([r for _, r in sorted(rows)])
