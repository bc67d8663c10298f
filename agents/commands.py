"""The agents' ``aero-env`` subcommands: ``tune``, ``train`` and ``evaluate``.

They plug into ``aero-env`` through the ``aero_env.commands`` entry point (pyproject.toml), so
the physics package never imports the agents, and they read their scene and check their output
paths with :mod:`aero_env.scene_args`, not through the command line's module. Heavy imports
(Optuna, torch) happen only when a command runs. Every option is checked before the first trial
or training step; Ctrl-C ends with one line saying what was kept and how to go on (exit 130).
"""

from __future__ import annotations

import json
import shlex
import sys
from pathlib import Path

from aero_env.config import FIDELITY_PRESETS
from aero_env.scene_args import PLOT_SUFFIXES, YAML_SUFFIXES, add_seed, check_not_the_config, check_output, load_scene

from .options import ALGOS, SAMPLERS
from .study_faults import RECONNECT_S



def register(sub, scene_command) -> None:
    tp = scene_command(sub, "tune", "search the design space with Optuna (CMA-ES, TPE or random search)")
    tp.add_argument("--sampler", default="cmaes", choices=SAMPLERS, help="the search: random is the baseline")
    tp.add_argument("--trials", type=int, default=200,
                    help="the study's target number of finished trials (a resumed study runs the rest)")
    tp.add_argument("--seeds-per-design", type=int, default=1, metavar="K",
                    help="episode seeds each design is scored on (mean reward); >1 where the scene draws "
                         "context or tolerances, so that robust designs win")
    add_seed(tp, 0, "the sampler's seed")
    tp.add_argument("--storage", metavar="URL", help="memory, sqlite:///FILE.db or postgresql://USER@HOST/DB "
                    "(default: memory; sqlite:///aero-env-tune.db with --study or --workers > 1)")
    tp.add_argument("--study", metavar="NAME", help="study name; an existing study resumes "
                    "(default: CONFIG-SAMPLER-sSEED)")
    tp.add_argument("--workers", type=int, default=1, help="local processes sharing the study")
    tp.add_argument("--out", default="best.yaml", metavar="FILE.yaml",
                    help="write the best design as a complete config; its folder must exist")
    tp.add_argument("--plot", metavar="FILE.png", help="optimisation-history plot (default: next to --out, "
                    "NAME_history.png)")
    tp.add_argument("--no-progress", action="store_true", help="no progress bar")
    tp.add_argument("--screen", metavar="FIDELITY", choices=tuple(FIDELITY_PRESETS),
                    help="multi-fidelity: score --screen-designs random designs at this cheap fidelity first "
                         "(reduced: one vectorised batch), then confirm the best --trials of them at the config's own "
                         f"fidelity; one of {', '.join(FIDELITY_PRESETS)} (absent: no screen)")
    tp.add_argument("--screen-designs", type=int, default=20000, metavar="M", help="designs the screen scores")
    tp.add_argument("--robust", default="0", metavar="K",
                    help="score each design as its mean reward over K hand-made builds within the default tolerances "
                         "(aero_env/robustness/tolerances.py), the same K builds for every trial, drawn from --seed; "
                         "composes with --seeds-per-design (K builds of each seed's episode); --screen ranks designs "
                         "as drawn, without the builds, which only the confirmed trials are scored on "
                         "(default 0: the design as drawn)")
    tp.add_argument("--reconnect", type=float, default=RECONNECT_S, metavar="SECONDS",
                    help="how long each process retries a lost database (bounded backoff) before the run stops; "
                         "rerunning the same command then resumes the study")
    tp.set_defaults(func=cmd_tune)

    rp = scene_command(sub, "train", "train a policy that maps the scene's context to a design (stable-baselines3)")
    rp.add_argument("--algo", default="ppo", choices=ALGOS, help="the RL algorithm")
    rp.add_argument("--timesteps", type=int, default=2000,
                    help="environment steps = episodes = designs tried (with --resume: the run's total)")
    rp.add_argument("--n-envs", type=int, default=1, help="environments stepped together (>1: one process each, or one vector env with --vector)")
    rp.add_argument("--vector", action="store_true",
                    help="step the --n-envs designs in one call of the native vector env (at sim.fidelity reduced: one "
                         "call of the compiled model; at a pymunk fidelity: a pool of processes over the cores)")
    add_seed(rp, 0, "seed of the policy and of the training episodes")
    rp.add_argument("--eval-every", type=int, default=500, metavar="STEPS",
                    help="timesteps between periodic evaluations (0: none)")
    rp.add_argument("--hp", action="append", metavar="KEY=VALUE",
                    help="override a hyper-parameter of agents.rl.ALGO_DEFAULTS, checked against its type and range "
                         "(agents.rl.HP_SPECS; repeatable), e.g. --hp learning_rate=1e-3")
    rp.add_argument("--out", default="runs/policy", metavar="DIR",
                    help="the run's folder: new or empty (made with its parents)")
    rp.add_argument("--overwrite", action="store_true", help="replace the run already in --out (its files are removed)")
    rp.add_argument("--resume", action="store_true",
                    help="go on with the run in --out (stopped by Ctrl-C, or finished: up to --timesteps in all), with "
                         "the same CONFIG, --set, --algo, --n-envs, --vector, --seed, --eval-every and --hp")
    rp.add_argument("--init-from", metavar="DIR",
                    help="start from the policy of the PPO run in DIR (the same network and scene; its sim.fidelity "
                         "may differ): pretrain at sim.fidelity=reduced, finish here at mbd")
    rp.add_argument("--no-progress", action="store_true", help="no progress bar")
    rp.set_defaults(func=cmd_train)

    ep = sub.add_parser("evaluate", help="the trained policy's reward over episode seeds (mean and spread)")
    ep.add_argument("run_dir", metavar="DIR", help="a directory written by aero-env train")
    ep.add_argument("--episodes", type=int, default=20, help="episodes, one per seed")
    add_seed(ep, 0, "first episode seed")
    ep.add_argument("--config", metavar="FILE.yaml",
                    help="evaluate on this scene instead of the one it was trained on (the same context, ranges "
                         "included, and the same tunable fields, whose ranges may differ)")
    ep.add_argument("--set", action="append", metavar="KEY=VALUE",
                    help="override a value of the scene evaluated on (repeatable), e.g. --set scene.frames=4 (not a context "
                         "field the scene draws: that is drawn at every reset)")
    ep.add_argument("--against", metavar="FILE.yaml",
                    help="also play this config's design (e.g. the best single design of a robust tune) on the same "
                         "episodes, and report the policy against it")
    ep.add_argument("--json", action="store_true", help="print one JSON object instead of the summary")
    ep.set_defaults(func=cmd_evaluate)


def _same_command() -> str:
    """The command line this process runs, fit to paste: how a stopped study resumes."""
    import shlex

    return shlex.join(["aero-env", *sys.argv[1:]])


def _whole(text: str):
    """A whole number given on the command line as an int; anything else as given, for the settings' check to name."""
    try:
        return int(text, 10)
    except ValueError:
        return text


def cmd_tune(args) -> int:
    from aero_env.signals import exit_status, signal_name

    from .study_faults import StorageUnavailable, redact
    from .tune import TuneInterrupted, plot_history, summary_lines, tune, write_best_yaml
    from .tune_settings import TuneSettings
    from .tune_workers import WorkersFailed

    out = Path(args.out)
    plot = Path(args.plot) if args.plot else out.with_name(f"{out.stem}_history.png")
    check_output(out, "--out", YAML_SUFFIXES)
    check_not_the_config(out, "--out", args.config)
    check_output(plot, "--plot" if args.plot else "--plot (next to --out)", PLOT_SUFFIXES)
    settings = TuneSettings(sampler=args.sampler, trials=args.trials, seeds_per_design=args.seeds_per_design,
                            seed=args.seed, storage=args.storage, study=args.study, workers=args.workers,
                            progress=not args.no_progress, screen=args.screen,
                            screen_designs=args.screen_designs, reconnect_s=args.reconnect,
                            robust=_whole(args.robust)).check()
    cfg = load_scene(args)
    try:
        result = tune(cfg, settings, config_name=Path(args.config).stem)
    except TuneInterrupted as stop:
        kept = "no trial had finished, so no design was written"
        if stop.result is not None:
            write_best_yaml(cfg, stop.result, out)
            plot_history(stop.result, plot)
            kept = (f"the best so far (reward {stop.result.best_reward:.4g}, trial {stop.result.best_trial}) is in "
                    f"{out}")
        if stop.storage == "memory":
            how = ("the study was in memory and is gone: to tune with a study you can resume, give --storage "
                   "sqlite:///aero-env-tune.db (or --study NAME)")
        else:
            how = (f"its finished trials are kept in study {stop.study!r} ({redact(stop.storage)}): rerun the same "
                   f"command to resume: {_same_command()}")
        print(f"aero-env tune: {signal_name(stop.by)} after {stop.finished} of {stop.target} trials; {kept}; "
              f"{how}", file=sys.stderr)
        return exit_status(stop.by)
    except StorageUnavailable as lost:
        print(f"aero-env tune: stopped: {lost}; the study's finished trials are kept in study {lost.study!r}: once "
              f"the database is back, rerun the same command to resume: {_same_command()}", file=sys.stderr)
        return 1
    except WorkersFailed as failed:  # a worker's error (a study file damaged mid-run, say), or workers dying
        print(f"aero-env tune: stopped: {' '.join(str(failed).split())}; the study's finished trials are kept in "
              f"study {settings.study_name(Path(args.config).stem)!r} ({redact(settings.resolved_storage())})",
              file=sys.stderr)
        return 1
    write_best_yaml(cfg, result, out)
    plot_history(result, plot)
    if args.json:
        print(json.dumps({**result.to_json_dict(), "out": str(out), "plot": str(plot)}, indent=2))
    else:
        print("\n".join(summary_lines(result, cfg)))
        print(f"wrote best design: {out}\nwrote history plot: {plot}")
    return 0


# What training on the fast rung risks (issue 35 §3), measured in docs/agents.md: the reduced model parts from the
# world on some designs, and a policy trained on it can learn to choose exactly those
REDUCED_RISK = ("aero-env train: sim.fidelity = reduced trains on the fast model, which parts from the world on some "
                "designs, and a policy can learn to pick them; score it where it will be used: aero-env evaluate "
                "{out} --set sim.fidelity=mbd; finish it there: this command at sim.fidelity=mbd with --init-from "
                "{out}, a new --out and a few thousand --timesteps (docs/agents.md#the-fast-rung-and-a-policy)")


def cmd_train(args) -> int:
    from aero_env.config import parse_override
    from aero_env.signals import exit_status, signal_name

    from .rl import TrainInterrupted, TrainSettings, check_run_dir, train

    hp = dict(parse_override(t) for t in args.hp or [])
    settings = TrainSettings(algo=args.algo, timesteps=args.timesteps, n_envs=args.n_envs, seed=args.seed,
                             eval_every=args.eval_every, vector=args.vector, hyperparameters=hp, progress=not args.no_progress).check()
    check_run_dir(args.out, args.overwrite, args.resume)
    cfg = load_scene(args)
    if cfg.sim.model == "reduced":
        print(REDUCED_RISK.format(out=shlex.quote(str(args.out))), file=sys.stderr)
    try:
        run = train(cfg, settings, args.out, overwrite=args.overwrite, resume=args.resume, init_from=args.init_from)
    except KeyboardInterrupt as stop:  # Ctrl-C or SIGTERM before the first step: train left the folder as it found it
        print(f"aero-env train: {signal_name(stop)} before the first training step; {args.out} is as it was before",
              file=sys.stderr)
        return exit_status(stop)
    except TrainInterrupted as stop:
        r = stop.run
        print(f"aero-env train: {signal_name(stop.by)} at {r['timesteps_done']} of {r['timesteps']} timesteps; kept "
              f"the policy so far and its curves in {args.out} (aero-env evaluate {args.out} scores it); resume: rerun "
              f"the same command with --resume", file=sys.stderr)
        return exit_status(stop.by)
    if args.json:
        print(json.dumps({**run, "out": args.out}, indent=2))
    else:
        done = run["timesteps_done"]
        rounded = "" if done == run["timesteps"] else f" (--timesteps {run['timesteps']}, rounded up to whole rounds)"
        start = run.get("init_from")
        since = "" if not start else (f", from the policy in {start['dir']} ({start['timesteps_done']} steps at "
                                      f"{start['fidelity']})")
        print(f"trained {run['algo']} for {done} steps{rounded} on {run['n_envs']} env(s) in {run['wall_time']:.1f} s "
              f"({run['episodes_per_second']:.1f} episodes/s){since}")
        print(f"wrote {args.out}/model.zip, config.yaml, run.json, learning_curve.png; "
              f"next: aero-env evaluate {args.out}")
    return 0


def cmd_evaluate(args) -> int:
    from aero_env.config import ConfigError

    from .rl import check_run_files, evaluate, read_run_config

    run_dir = check_run_files(args.run_dir)
    scene = None
    if args.config or args.set:
        from aero_env.config import load_config, parse_override

        overrides = dict(parse_override(s) for s in args.set or [])
        # without --config, --set changes the scene the policy was trained on (its config.yaml in DIR)
        scene = load_config(args.config, overrides) if args.config else read_run_config(run_dir, overrides)
        drawn = {c.name for c in scene.context if c.low is not None}
        for key in overrides:
            if key in drawn:
                raise ConfigError(f"--set {key}: the scene draws {key} at every reset (its context range), so a value "
                                  f"set here is never used; change the range with --set 'context=[...]' or a --config")
    against = None
    if args.against:
        from aero_env.config import load_config

        against = load_config(args.against)
    rep = evaluate(args.run_dir, episodes=args.episodes, seed=args.seed, config=scene, against=against)
    if args.json:
        print(json.dumps(rep, indent=2))
        return 0
    print(f"{rep['algo']} policy over {rep['episodes']} episodes (seeds {rep['seeds'][0]}..{rep['seeds'][1]}): "
          f"reward {rep['mean_reward']:.3f} ± {rep['std_reward']:.3f} (min {rep['min_reward']:g}, max "
          f"{rep['max_reward']:g}); whole row ({rep['full_row']}) in {100 * rep['full_row_fraction']:.0f} %")
    if against is not None:
        a = rep["against"]
        gain = 100 * (rep["full_row_fraction"] - a["full_row_fraction"])
        print(f"against {args.against} (one design for every episode): reward {a['mean_reward']:.3f} ± "
              f"{a['std_reward']:.3f}; whole row in {100 * a['full_row_fraction']:.0f} %; the policy "
              f"{gain:+.0f} points")
    print("outcomes: " + ", ".join(f"{k} {v}" for k, v in rep["outcomes"].items()))
    print("\n".join(design_table(rep)))
    return 0


def design_table(rep: dict) -> list[str]:
    """The design the policy chose for each episode's context: the varied context fields, then the design."""
    from aero_env.config import real_field
    from aero_env.quantities import in_maker_units

    rows = rep["per_episode"]
    context = rep["varied_context"]
    keys = context + list(rows[0]["design"])
    units = {key: real_field(key, key).metadata["unit"] for key in keys}  # SI, as the values are

    def heading(key: str) -> str:
        unit = in_maker_units(1.0, units[key])[1]
        return key.split(".")[-1] + (f" [{unit}]" if unit else "")

    def cell(key: str, value: float) -> str:
        return f"{in_maker_units(value, units[key])[0]:.4g}"

    def cells(row: dict) -> list[str]:
        values = {**row["context"], **row["design"]}
        return [*(cell(k, values[k]) for k in keys), f"{row['reward']:g}", row["outcome"]]

    if context:
        lines = ["designs chosen per context:",
                 "  ".join(f"{h:>12}" for h in ["seed", *map(heading, keys), "reward", "outcome"])]
        lines += ["  ".join(f"{v:>12}" for v in [str(row["seed"]), *cells(row)]) for row in rows]
        return lines
    # nothing observed: every episode gets the same design; one row per distinct result, with its episode count
    counts: dict[tuple, int] = {}
    for row in rows:
        counts[tuple(cells(row))] = counts.get(tuple(cells(row)), 0) + 1
    lines = [f"the design chosen (the scene draws no context: one design for all {len(rows)} episodes):",
             "  ".join(f"{h:>12}" for h in ["episodes", *map(heading, keys), "reward", "outcome"])]
    lines += ["  ".join(f"{v:>12}" for v in [str(n), *row]) for row, n in counts.items()]
    return lines
