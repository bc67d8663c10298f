"""Can a tuner game the shaped reward? CMA-ES maximises it, then its best designs are audited.

    python benchmarks/shaping_adversary.py [CONFIG] [--trials 300] [--top 0] [--shaping 0.5]
                                          [--fidelity mbd] [--seed 0] [--survey 150] [--rule env|before] [--json]

1. survey: ``--survey`` random designs (uniform in the action box, seeded) scored by the env with
   ``env.reward_shaping = --shaping``: per outcome, how many runs earned partial credit and the
   largest credit, under the env's reward and, for comparison, under the rule before it paid only flights
   (any failed transfer with a ``miss_distance`` earned it, hooks that never let go included).
2. adversary: CMA-ES (Optuna's ``CmaEsSampler`` from ``agents.study_storage.make_sampler``, trials scored by
   ``agents.tune_workers.objective_for``, as ``aero-env tune`` scores them) maximises the shaped reward for
   ``--trials`` trials on the scene (default configs/paper.yaml, the prototype's).
3. audit: the ``--top`` best distinct trials (0, the default: every trial, best first) are
   simulated again with their traces, and each reward is checked by :func:`audit`, which shares no
   code with :mod:`aero_env.reward`:

   * traversals counted from the swings' catch records: frames 1, 2, ... in order, each caught
     after the previous swing's detach with the hook seated (``catch_seat_mm <= sim.catch_seat``) and,
     in the trace, turned through 90 deg (the robot at its lowest) while touching the hook: a catch that
     held; the reward's whole part is that count (the whole row for ``completed``);
   * partial credit (the rest) only where the trace shows a flight after the last catch (the hook
     touching no handrail for ``sim.contact_hold``), then equal to
     ``w · max(0, 1 - miss_distance / pitch)``, and below 1;
   * energy that never rose: in the trace and in the run's energy record, mechanical energy never
     more than ``sim.energy_tolerance`` x ((m2 + m3)·g·(La + Lb) + the spring's energy fully bent,
     recomputed here from ``design.spring_k`` and the law) above its running minimum;
   * health within the config's limits (joint drift, limit overshoot, penetration).

``--rule before`` runs the adversary against the old rule instead (the audit then shows what a
gamed reward looks like). Prints tables (``--json``: JSON); exits 1 when an audited design fails a check.
"""

from __future__ import annotations

import argparse
import collections
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:  # run as a script from anywhere: agents is a top-level package of the repository
    sys.path.insert(0, str(ROOT))

from aero_env.config import Config, ConfigError, load_config  # noqa: E402
from aero_env.design_space import DesignSpace  # noqa: E402
from aero_env.envs import AerialAcrobatEnv  # noqa: E402
from aero_env.physics import simulate  # noqa: E402

G = 9.81  # m/s^2; the audit's tolerance is a scale, and this rounding of g moves it by < 0.01 %


# ---- the audit: independent of aero_env.reward ----

def seated_catches(result, cfg: Config) -> int:
    """Consecutive traversals counted from the swings' catch records: swing j is on frame j, caught
    after swing j-1 let go of frame j-1, with the hook's centre within ``sim.catch_seat`` of the seat, and
    the catch held: the trace shows frame j, touching the hook, turned through 90 deg (the robot at its
    lowest point)."""
    seat_mm = cfg.sim.catch_seat * 1e3 * (1 + 1e-9)
    tr = result.trace
    if tr is None:
        raise ConfigError("seated_catches: the run has no trace; simulate(cfg, trace=True)")
    count = 0
    for prev, sw in zip(result.swings, result.swings[1:]):
        if sw.frame != prev.frame + 1 or prev.t_detach is None or not sw.t_catch > prev.t_detach:
            break
        if sw.catch_seat_mm is None or sw.catch_seat_mm > seat_mm:
            break
        held = (np.asarray(tr["frame"]) == sw.frame) & (np.asarray(tr["contact"]) == sw.frame)
        if not np.any(np.asarray(tr["theta1"])[held] >= math.radians(90.0)):
            break
        count += 1
    return count


def flight_seen(result, cfg: Config) -> bool:
    """The trace shows the hook off every handrail for ``sim.contact_hold`` (less one trace interval)
    after the last catch: it let go of that frame and flew."""
    tr = result.trace
    if tr is None:
        raise ConfigError("flight_seen: the run has no trace; simulate(cfg, trace=True)")
    t, contact = np.asarray(tr["t"]), np.asarray(tr["contact"])
    after = t > result.swings[-1].t_catch
    t, free = t[after], contact[after] < 0
    if len(t) < 2:
        return False
    interval = float(np.median(np.diff(t)))
    start = None
    for ti, f in zip(t, free):
        if f and start is None:
            start = ti
        elif not f:
            start = None
        if start is not None and ti - start >= cfg.sim.contact_hold - interval:
            return True
    return False


def energy_scale(cfg: Config) -> float:
    """(m2 + m3)·g·(La + Lb) + the leaf spring's energy fully bent (alpha_max - alpha_min), J."""
    d = cfg.design
    bend = math.radians(d.alpha_max_deg - d.alpha_min_deg)
    law = cfg.scene.effects.spring_law
    spring = {"linear": 0.5 * d.spring_k * bend ** 2, "stiffening": d.spring_k * bend ** 3 / 6}.get(law)
    if spring is None:
        raise ConfigError(f"energy_scale: scene.effects.spring_law = {law!r}: the audit knows linear and stiffening")
    return (d.m2 + d.m3) * G * (d.La + d.Lb) + spring


def energy_rise(result) -> float:
    """J: the largest rise of mechanical energy above its running minimum in the trace (or, with none, the record)."""
    if result.trace is None:
        return float(result.energy["max_rise"])
    e = np.asarray(result.trace["energy"])
    return float(np.max(e - np.minimum.accumulate(e)))


def audit(reward: float, result, cfg: Config) -> list[str]:
    """What does not back ``reward`` in ``result`` (a run of ``cfg`` with its trace): [] if everything does."""
    problems = []
    w, pitch = cfg.env.reward_shaping, cfg.scene.pitch
    if result.outcome == "unstable":
        return [] if reward == 0.0 else [f"unstable run paid {reward}"]
    seated = seated_catches(result, cfg)
    if result.outcome == "completed" and seated != cfg.scene.frames - 1:
        problems.append(f"completed with {seated} seated catches of {cfg.scene.frames - 1}")
    credit = reward - seated
    if not 0.0 <= credit < 1.0:
        problems.append(f"reward {reward} is not {seated} seated catches plus a credit below 1")
    elif flight_seen(result, cfg):
        expected = w * max(0.0, 1.0 - result.miss_distance / pitch) if result.miss_distance is not None else 0.0
        if not math.isclose(credit, expected, rel_tol=1e-9, abs_tol=1e-12):
            problems.append(f"credit {credit:.6g} for a flight that missed by {result.miss_distance} m "
                            f"(w·(1 - miss/pitch) = {expected:.6g})")
    elif credit != 0.0:
        problems.append(f"credit {credit:.6g} with no flight after the last catch ({result.outcome}: {result.reason})")
    tol = cfg.sim.energy_tolerance * energy_scale(cfg)
    rise = energy_rise(result)
    if rise > tol:
        problems.append(f"energy rose {rise:.3g} J in the trace (tolerance {tol:.3g} J)")
    if result.energy["max_rise"] > tol or result.energy["final"] > result.energy["initial"] + tol:
        problems.append(f"energy record {result.energy} rose more than {tol:.3g} J")
    d, s, h = cfg.design, cfg.sim, result.health
    limits = dict(joint_drift=s.max_joint_drift, limit_overshoot_deg=s.max_limit_overshoot_deg,
                  penetration=s.max_penetration * (d.hook_radius + 0.5 * d.handrail_thickness))
    for key, lim in limits.items():
        if not h.get(key, math.inf) <= lim:
            problems.append(f"health {key} = {h.get(key)} above its limit {lim:.3g}")
    return problems


# ---- the rule before it paid only flights, for comparison ----

def reward_before(result, cfg: Config) -> float:
    """The env's reward before it paid only flights: any failed transfer with a miss_distance earned partial credit."""
    if result.outcome == "unstable":
        return 0.0
    r = float(result.traversals)
    w = cfg.env.reward_shaping
    if w > 0 and result.outcome != "completed" and result.miss_distance is not None:
        r += w * max(0.0, 1.0 - result.miss_distance / cfg.scene.pitch)
    return r


def use_rule(rule: str) -> None:
    """Score the env with ``rule``: ``env`` (aero_env.reward, as shipped) or ``before``."""
    import aero_env.reward as module

    if rule == "before":
        module.reward = reward_before  # AerialAcrobatEnv._reward looks it up at each step


# ---- the three parts ----

def survey(cfg: Config, designs: int, seed: int) -> dict:
    env = AerialAcrobatEnv(cfg)
    space = env.space
    draw = space.draw_for_seed(0)
    actions = np.random.default_rng(seed).uniform(-1.0, 1.0, (designs, space.dim))
    rows = collections.defaultdict(lambda: dict(runs=0, credited=0, max_credit=0.0, credited_before=0,
                                                max_credit_before=0.0))
    for a in actions:
        env.reset(seed=0)
        _, r, _, _, info = env.step(a)
        ecfg = space.episode_config(space.values(a), draw)[0]
        before = reward_before(simulate(ecfg), ecfg) - info["traversals"]
        credit = r - info["traversals"]
        row = rows[info["outcome"]]
        row["runs"] += 1
        row["credited"] += int(credit > 0)
        row["max_credit"] = round(max(row["max_credit"], credit), 4)
        row["credited_before"] += int(before > 0)
        row["max_credit_before"] = round(max(row["max_credit_before"], before), 4)
    return dict(sorted(rows.items()))


def adversary(cfg: Config, trials: int, seed: int) -> list:
    """CMA-ES on the env's reward, as aero-env tune runs it (one episode seed: the scene draws nothing
    or every trial sees seed 0's draw); the study's trials."""
    from agents.design_eval import DesignEvaluator
    from agents.study_storage import import_optuna, make_sampler
    from agents.tune_workers import objective_for

    optuna = import_optuna()
    evaluator = DesignEvaluator(cfg, (0,))
    study = optuna.create_study(direction="maximize", sampler=make_sampler("cmaes", seed))
    study.optimize(objective_for(evaluator, "adversary"), n_trials=trials)
    evaluator.close()
    return [t for t in study.trials if t.state.name == "COMPLETE"]


def audit_top(cfg: Config, trials: list, top: int) -> list[dict]:
    """Re-run the ``top`` best distinct trials (0: all; seed 0's draw) with their traces; audit each."""
    space = DesignSpace(cfg)
    draw = space.draw_for_seed(0)
    names = [t.name for t in cfg.tunable]
    seen, out = set(), []
    for tr in sorted(trials, key=lambda t: (-t.value, t.number)):
        action = np.array([tr.params[n] for n in names])
        key = tuple(np.round(action, 12))
        if key in seen:
            continue
        seen.add(key)
        ecfg, _ = space.episode_config(space.values(action), draw)
        result = simulate(ecfg, trace=True)
        reward = float(tr.user_attrs["rewards"][0])
        problems = audit(reward, result, ecfg)
        if result.traversals != tr.user_attrs["traversals"][0] or result.outcome != tr.user_attrs["outcomes"][0]:
            problems.append(f"the re-run differs from the trial: {result.outcome} {result.traversals} vs "
                            f"{tr.user_attrs['outcomes'][0]} {tr.user_attrs['traversals'][0]}")
        out.append(dict(trial=tr.number, reward=round(reward, 6), outcome=result.outcome,
                        seated_catches=seated_catches(result, ecfg), flight=flight_seen(result, ecfg),
                        miss_distance_mm=None if result.miss_distance is None else round(result.miss_distance * 1e3, 2),
                        max_energy_rise_J=float(f"{max(energy_rise(result), result.energy['max_rise']):.3g}"),
                        energy_tolerance_J=float(f"{ecfg.sim.energy_tolerance * energy_scale(ecfg):.3g}"),
                        problems=problems))
        if len(out) == top:
            break
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config", nargs="?", default=str(ROOT / "configs" / "paper.yaml"))
    ap.add_argument("--trials", type=int, default=300)
    ap.add_argument("--top", type=int, default=0, help="audit the best N distinct trials (0: every trial)")
    ap.add_argument("--shaping", type=float, default=0.5)
    ap.add_argument("--fidelity", default=None, help="sim.fidelity (default: the config's)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--survey", type=int, default=150, help="random designs in the survey (0: none)")
    ap.add_argument("--rule", choices=("env", "before"), default="env")
    ap.add_argument("--json", action="store_true", help="the whole report as JSON (default: tables)")
    args = ap.parse_args(argv)
    if args.trials < 1:
        ap.error(f"--trials {args.trials}: must be at least 1")
    for name in ("top", "survey"):
        if getattr(args, name) < 0:
            ap.error(f"--{name} {getattr(args, name)}: must be at least 0")
    over = {"env.reward_shaping": args.shaping}
    if args.fidelity:
        over["sim.fidelity"] = args.fidelity
    try:
        cfg = load_config(args.config, over)
    except ConfigError as exc:
        ap.error(str(exc))
    use_rule(args.rule)
    shown = Path(args.config).resolve()
    report = dict(config=str(shown.relative_to(ROOT) if shown.is_relative_to(ROOT) else shown),
                  fidelity=cfg.sim.fidelity, shaping=args.shaping, rule=args.rule)
    t0 = time.perf_counter()
    if args.survey:
        report["survey"] = dict(designs=args.survey, by_outcome=survey(cfg, args.survey, args.seed))
    trials = adversary(cfg, args.trials, args.seed)
    values = np.array([t.value for t in trials])
    report["adversary"] = dict(sampler="cmaes", trials=len(trials), seed=args.seed, best=float(values.max()),
                               whole_row_trials=int((values >= cfg.scene.frames - 1).sum()),
                               credited_trials=int((values % 1 > 0).sum()))
    audited = audit_top(cfg, trials, args.top)
    report["audit"] = dict(designs=len(audited), failed=sum(bool(a["problems"]) for a in audited), top=audited)
    report["wall_time_s"] = round(time.perf_counter() - t0, 1)
    print(json.dumps(report, indent=1) if args.json else "\n".join(table(report)))
    return 1 if report["audit"]["failed"] else 0


def table(report: dict) -> list[str]:
    lines = [f"{report['config']} at {report['fidelity']}, env.reward_shaping {report['shaping']}, "
             f"reward rule: {report['rule']}"]
    if "survey" in report:
        lines += [f"survey: {report['survey']['designs']} random designs, partial credit by outcome "
                  f"(now | before it paid only flights)",
                  "| outcome | runs | credited now | max credit now | credited before | max credit before |",
                  "|---|---|---|---|---|---|"]
        for outcome, r in report["survey"]["by_outcome"].items():
            lines.append(f"| {outcome} | {r['runs']} | {r['credited']} | {r['max_credit']:.3f} | "
                         f"{r['credited_before']} | {r['max_credit_before']:.3f} |")
    a = report["adversary"]
    lines.append(f"adversary: CMA-ES, {a['trials']} trials (seed {a['seed']}): best reward {a['best']:.4g}; "
                 f"{a['whole_row_trials']} trials traversed the whole row, {a['credited_trials']} earned "
                 f"partial credit")
    au = report["audit"]
    lines += [f"audit of {au['designs']} designs (the best first): {au['failed']} failed",
              "| outcome | designs | failed | flight seen | seated catches | reward |", "|---|---|---|---|---|---|"]
    by = collections.defaultdict(list)
    for d in au["top"]:
        by[d["outcome"]].append(d)
    for outcome, ds in sorted(by.items()):
        seated, rewards = [d["seated_catches"] for d in ds], [d["reward"] for d in ds]
        lines.append(f"| {outcome} | {len(ds)} | {sum(bool(d['problems']) for d in ds)} | "
                     f"{sum(d['flight'] for d in ds)} | {min(seated)}-{max(seated)} | "
                     f"{min(rewards):.4f}-{max(rewards):.4f} |")
    credited = [d for d in au["top"] if d["reward"] % 1 > 0]
    shown = au["top"][:5] + [d for d in credited[:5] if d not in au["top"][:5]]
    shown += [d for d in au["top"] if d["problems"] and d not in shown]
    lines += ["the 5 best, the 5 best with partial credit, and every design that failed:",
              "| trial | reward | outcome | seated catches | flight | miss (mm) | energy rise / tolerance (J) "
              "| problems |",
              "|---|---|---|---|---|---|---|---|"]
    for d in shown:
        miss = "-" if d["miss_distance_mm"] is None else f"{d['miss_distance_mm']:.1f}"
        lines.append(f"| {d['trial']} | {d['reward']:.4f} | {d['outcome']} | {d['seated_catches']} | "
                     f"{'yes' if d['flight'] else 'no'} | {miss} | {d['max_energy_rise_J']:.2g} / "
                     f"{d['energy_tolerance_J']:.2g} | {'; '.join(d['problems']) or 'none'} |")
    lines.append(f"wall time {report['wall_time_s']} s")
    return lines


if __name__ == "__main__":
    sys.exit(main())
