"""The baselines of a context -> design map (agents/context_maps.py) and the episode runner they play on."""

from __future__ import annotations

import json

import numpy as np
import pytest

from aero_env.config import load_config
from aero_env.envs import AerialAcrobatEnv
from agents.context_maps import ContextSearch, NearestNeighbour, ParamMap, fit_map, search_contexts
from agents.episode_runner import EpisodeRunner, draws_for_seeds, fresh_builds

from .conftest import PAPER

CONTEXTS = PAPER.parent / "contexts.yaml"
SINGLE = PAPER.parent / "contexts_single.yaml"


def _single_action(space) -> np.ndarray:
    single = load_config(SINGLE)
    return space.action_for({t.name: single.value(t.name) for t in space.tunables}, dtype=np.float64)


@pytest.mark.parametrize("fidelity", ["reduced", "mbd"])
def test_the_runner_plays_an_episode_as_env_step_does(fidelity):
    cfg = load_config(CONTEXTS, {"sim.fidelity": fidelity, "scene.frames": 3})
    runner = EpisodeRunner(cfg, workers=1)
    seeds = [11, 12, 13, 14]
    actions = np.random.default_rng(0).uniform(-1, 1, (len(seeds), runner.space.dim))
    got = runner.traversals(draws_for_seeds(runner.space, seeds), actions)
    env = AerialAcrobatEnv(cfg)
    want = []
    for s, a in zip(seeds, actions):
        env.reset(seed=s)
        want.append(env.step(a)[4]["traversals"])
    assert got.tolist() == want and runner.episodes == len(seeds)


def test_a_fresh_build_keeps_the_contexts_and_draws_the_cutting_error_again():
    runner = EpisodeRunner(load_config(CONTEXTS, {"sim.fidelity": "reduced"}))
    draws = draws_for_seeds(runner.space, range(20))
    again = fresh_builds(runner.space, draws, seed=3)
    assert [d.context for d in again] == [d.context for d in draws]
    assert np.array_equal(runner.observations(again), runner.observations(draws))
    u_old, u_new = np.array([d.tolerance_u for d in draws]), np.array([d.tolerance_u for d in again])
    assert u_new.shape == u_old.shape and (u_new != u_old).all() and np.abs(u_new).max() <= 1.0
    assert [d.tolerance_u for d in fresh_builds(runner.space, draws, seed=3)] == [d.tolerance_u for d in again]


def test_a_linear_map_is_w_obs_plus_b_clipped_and_survives_json():
    m = ParamMap("linear", 4, 5, params=np.arange(25, dtype=float) / 50.0 - 0.2)
    obs = np.random.default_rng(1).uniform(-1, 1, (6, 4))
    want = [[min(1.0, max(-1.0, sum(m.params[i * 4 + j] * o[j] for j in range(4)) + m.params[20 + i]))
             for i in range(5)] for o in obs]
    assert np.allclose(m.act(obs), want, rtol=0, atol=1e-12)
    back = ParamMap.from_json_dict(json.loads(json.dumps(m.to_json_dict())))
    assert np.array_equal(back.act(obs), m.act(obs))
    p = np.random.default_rng(3).normal(0, 0.5, 8 * 5 + 5 * 9)
    mlp = ParamMap("mlp", 4, 5, hidden=8, params=p)
    assert mlp.size == 85
    for o, got in zip(obs, mlp.act(obs)):  # hidden unit k: tanh(sum_j W1[k, j] o_j + b1[k]); W1 row-major first
        hidden = [np.tanh(sum(p[k * 4 + j] * o[j] for j in range(4)) + p[32 + k]) for k in range(8)]
        out = [min(1.0, max(-1.0, sum(p[40 + i * 8 + k] * hidden[k] for k in range(8)) + p[80 + i])) for i in range(5)]
        assert np.allclose(got, out, rtol=0, atol=1e-12)


def test_nearest_neighbour_answers_with_the_design_of_the_closest_context():
    rng = np.random.default_rng(2)
    table = NearestNeighbour(rng.uniform(-1, 1, (30, 4)), rng.uniform(-1, 1, (30, 5)))
    queries = rng.uniform(-1, 1, (10, 4))
    for q, a in zip(queries, table.act(queries)):
        dists = [float(np.sum((q - o) ** 2)) for o in table.obs]
        assert np.array_equal(a, table.actions[dists.index(min(dists))])


def test_nearest_neighbour_keeps_only_the_contexts_whose_row_was_made():
    obs, actions = np.eye(4)[:3], np.arange(15, dtype=float).reshape(3, 5) / 20
    found = ContextSearch(actions, np.array([True, False, True]), np.array([4, 3, 4]), np.ones(3, int), obs)
    table = NearestNeighbour.from_search(found)
    assert np.array_equal(table.obs, obs[[0, 2]]) and np.array_equal(table.act(obs[[1]]), actions[[0]])
    none = ContextSearch(actions, np.zeros(3, bool), np.array([1, 3, 2]), np.ones(3, int), obs)
    assert np.array_equal(NearestNeighbour.from_search(none).act(obs[[1]]), actions[[1]])  # none made: all kept


def test_a_map_tuned_at_reduced_beats_the_single_design_it_started_from():
    """CMA-ES on 25 numbers, 8k episodes: the map completes the row on more fresh contexts than the design it
    started from (both scored at reduced, on contexts the tune never saw)."""
    runner = EpisodeRunner(load_config(CONTEXTS, {"sim.fidelity": "reduced"}))
    start = _single_action(runner.space)
    m, history = fit_map(runner, "linear", 0, 8192, start=start)
    assert history[-1]["episodes"] <= 8192 and len(history) >= 5
    fresh = draws_for_seeds(runner.space, range(700_000, 700_200))
    mapped = runner.whole_rows(fresh, m.act(runner.observations(fresh))).mean()
    single = runner.whole_rows(fresh, np.tile(start, (len(fresh), 1))).mean()
    assert mapped >= single + 0.15, (mapped, single)


def test_a_per_context_search_keeps_a_design_that_really_makes_the_row():
    """Each design the search calls a whole row is one, replayed through the env itself; a context the start
    design already solves costs one episode; no context spends more than its budget."""
    cfg = load_config(CONTEXTS, {"sim.fidelity": "reduced"})
    runner = EpisodeRunner(cfg)
    draws = draws_for_seeds(runner.space, range(300, 316))
    start = _single_action(runner.space)
    first = runner.whole_rows(draws, np.tile(start, (len(draws), 1)))
    found = search_contexts(runner, draws, start, seed=0, max_evals=41, popsize=8)
    assert found.solved.sum() > first.sum() and (found.evaluations <= 41).all()
    assert (found.evaluations[first] == 1).all() and (found.evaluations[~first] > 1).all()
    env = AerialAcrobatEnv(cfg)
    for s, a, ok in zip(range(300, 316), found.actions, found.solved):
        env.reset(seed=s)
        assert (env.step(a)[4]["traversals"] >= cfg.scene.frames - 1) == ok


class _Peak:
    """A stand-in runner: a context is a target design; an action makes 4 traversals within 0.1 of it (sup norm),
    3 within 0.2, 2 within 0.3, ... so the search meets near misses on its way."""

    full_row = 4

    def __init__(self):
        self.episodes = 0

    def traversals(self, draws, actions):
        self.episodes += len(draws)
        d = np.abs(np.asarray(actions) - np.asarray(draws)).max(axis=1)
        return np.clip(4 - np.floor(d / 0.1), 0, 4).astype(np.int64)

    def observations(self, draws):
        return np.asarray(draws)


def test_a_search_calls_a_context_solved_only_for_a_whole_row_and_keeps_its_best():
    runner = _Peak()
    rng = np.random.default_rng(5)
    start = np.zeros(3)
    targets = [start + 0.15, start + 0.05, *rng.uniform(-0.6, 0.6, (10, 3))]  # a near miss (3), a hit (4), others
    found = search_contexts(runner, targets, start, seed=1, max_evals=81, popsize=8)
    replay = runner.traversals(targets, found.actions)
    assert found.traversals.tolist() == replay.tolist()
    assert found.solved.tolist() == (replay >= 4).tolist() and found.solved[1] and found.evaluations[1] == 1
    assert found.evaluations[0] > 1  # three traversals is not the row: the search went on
    assert (found.evaluations <= 81).all() and runner.episodes - len(targets) == found.evaluations.sum()


def test_each_of_ten_map_seeds_has_its_own_block_of_training_contexts():
    """Seeds 0-4 keep the blocks their shipped maps were fitted on, 10,000·(seed+1) onward; seeds 5-9 take the
    upper halves, 5,000 later. At the shipped budget no two seeds' training contexts meet, and all lie below nearest
    neighbour's contexts (60,000 onward); a seed past 9 has no block."""
    from agents.context_maps import map_block_start, map_seed_span

    assert [map_block_start(k) for k in range(10)] == [10_000, 20_000, 30_000, 40_000, 50_000,
                                                        15_000, 25_000, 35_000, 45_000, 55_000]
    from aero_env.design_space import DesignSpace

    space = DesignSpace(load_config(PAPER.parent / "contexts.yaml"))
    for kind in ("linear", "mlp"):
        spans = sorted(map_seed_span(kind, space.dim, space.obs_dim, k, 40_960) for k in range(10))
        for (_, last), (nxt, _) in zip(spans, spans[1:]):
            assert last < nxt, kind
        assert spans[-1][1] < 60_000 and spans[0][0] == 10_000
    with pytest.raises(ValueError, match="seed = 10: a map's training seeds are 0-9"):
        map_block_start(10)


def test_a_search_can_start_each_context_from_its_own_design():
    """``start`` with one row per context: a context whose own start makes the row costs one episode and keeps that
    start; one row repeated for every context is the one-design search, episode for episode."""
    rng = np.random.default_rng(6)
    targets = [*rng.uniform(-0.6, 0.6, (6, 3))]
    starts = np.array(targets)
    starts[3:] = 0.0  # the last three start from the centre, away from their targets
    runner = _Peak()
    found = search_contexts(runner, targets, starts, seed=2, max_evals=81, popsize=8)
    assert found.solved[:3].all() and (found.evaluations[:3] == 1).all()
    assert np.array_equal(found.actions[:3], starts[:3])
    one, rows = _Peak(), _Peak()
    a = search_contexts(one, targets, np.zeros(3), seed=2, max_evals=81, popsize=8)
    b = search_contexts(rows, targets, np.zeros((6, 3)), seed=2, max_evals=81, popsize=8)
    for name in ("actions", "solved", "traversals", "evaluations"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert one.episodes == rows.episodes
