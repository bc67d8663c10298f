"""Context -> design maps found without gradients: the baselines a contextual bandit calls for.

The design environment is a contextual bandit: one step, the observation is the context, the action the
design. Before a policy network earns its training, it has to beat the simple maps a practitioner would try
first (issue 35). This module builds them, each on the episodes of an :class:`EpisodeRunner`:

* :class:`ParamMap` ``linear``: ``design = clip(W·obs + b)``, ``d·(k+1)`` numbers (25 for the maker's
  contexts); ``mlp``: one tanh hidden layer of ``hidden`` units. :func:`fit_map` tunes the numbers with
  CMA-ES: every candidate of a generation plays the same fresh training contexts (common random numbers),
  and the generation's mean map is the result. It starts from the best single design for every context
  (only the output bias set): a practitioner's map starts from the design already tuned.
* :func:`search_contexts`: a search per context, on that episode itself (its context and its build): the
  start design first, then CMA-ES about it until a design completes the whole row or the budget is spent.
  On hold-out contexts it is the **oracle**: what a budgeted search on the episode itself reaches, the
  ceiling a benchmark can measure (not a bound: a map may make a row the search's budget missed). On
  training contexts it fills the table of :class:`NearestNeighbour`, which answers a context with the design
  found for the nearest training context.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .episode_runner import EpisodeRunner, draws_for_seeds

SEARCH_STEP = 0.3  # a per-context search's first step, in action units (a third of the box's half-width)
MAP_STEP = 0.1  # a map's first step: picked among 0.3, 0.1 (linear) and 0.1, 0.05 (mlp) on the watch contexts


@dataclass
class ParamMap:
    """``obs (n, k) -> actions (n, d)``: ``linear`` (W, b) or ``mlp`` (tanh hidden layer), from a flat vector."""

    kind: str
    obs_dim: int
    act_dim: int
    hidden: int = 8
    params: np.ndarray | None = None

    @property
    def size(self) -> int:
        k, d, h = self.obs_dim, self.act_dim, self.hidden
        return d * (k + 1) if self.kind == "linear" else h * (k + 1) + d * (h + 1)

    def act(self, obs: np.ndarray, params: np.ndarray | None = None) -> np.ndarray:
        p = np.asarray(self.params if params is None else params, dtype=np.float64)
        obs = np.asarray(obs, dtype=np.float64)
        k, d, h = self.obs_dim, self.act_dim, self.hidden
        if self.kind == "linear":
            w, b = p[:d * k].reshape(d, k), p[d * k:]
            return np.clip(obs @ w.T + b, -1.0, 1.0)
        w1, b1 = p[:h * k].reshape(h, k), p[h * k:h * (k + 1)]
        rest = p[h * (k + 1):]
        w2, b2 = rest[:d * h].reshape(d, h), rest[d * h:]
        return np.clip(np.tanh(obs @ w1.T + b1) @ w2.T + b2, -1.0, 1.0)

    def to_json_dict(self) -> dict:
        return dict(kind=self.kind, obs_dim=self.obs_dim, act_dim=self.act_dim, hidden=self.hidden,
                    params=[float(x) for x in self.params])

    @classmethod
    def from_json_dict(cls, d: dict) -> "ParamMap":
        return cls(d["kind"], d["obs_dim"], d["act_dim"], d.get("hidden", 8), np.asarray(d["params"], float))


def fit_map(runner: EpisodeRunner, kind: str, seed: int, episodes: int, start: np.ndarray | None = None,
            contexts: int = 64, seed_base: int = 10_000, hidden: int = 8, sigma: float = MAP_STEP,
            first_context: int | None = None, on_generation=None) -> tuple[ParamMap, list[dict]]:
    """Tune a map on ``runner``'s scene by CMA-ES within ``episodes`` episodes; returns it and its history
    (per generation: episodes so far, the population's mean and best reward). ``start``: the design the search
    starts from, for every context (a tuned single design); default the box's centre.

    Generation g plays the training contexts of episode seeds ``map_block_start(seed) + g·contexts`` onward (or
    ``first_context + g·contexts``), the same ones for every candidate (:func:`map_seed_span` gives the whole range).
    A budget too small for one generation is refused. ``on_generation(episodes, params)``, if given, sees the map
    after each generation: after the last generation within a smaller budget it is the map a fit with that budget
    returns (same seed, same contexts), so one fit gives every budget's map."""
    from cmaes import CMA

    space = runner.space
    m = ParamMap(kind, space.obs_dim, space.dim, hidden)
    mean = np.zeros(m.size)
    if start is not None:  # the map that answers every context with ``start``: only the output bias set
        mean[-space.dim:] = start
    opt = CMA(mean=mean, sigma=sigma, seed=seed)
    lam = opt.population_size
    if episodes < lam * contexts:
        raise ValueError(f"episodes = {episodes}: a {kind} map needs at least one generation, {lam} designs x "
                         f"{contexts} contexts = {lam * contexts} episodes")
    history, used, g = [], 0, 0
    while used + lam * contexts <= episodes:
        first = (map_block_start(seed, seed_base) if first_context is None else first_context) + g * contexts
        draws = draws_for_seeds(space, range(first, first + contexts))
        obs = runner.observations(draws)
        cands = [opt.ask() for _ in range(lam)]
        actions = np.concatenate([m.act(obs, x) for x in cands])
        trav = runner.traversals(draws * lam, actions).reshape(lam, contexts)
        rewards = trav.mean(axis=1)
        opt.tell([(x, -float(r)) for x, r in zip(cands, rewards)])
        used += lam * contexts
        g += 1
        history.append(dict(episodes=used, mean_reward=float(rewards.mean()), best_reward=float(rewards.max())))
        if on_generation is not None:
            on_generation(used, np.asarray(opt.mean, dtype=np.float64))
    m.params = np.asarray(opt.mean, dtype=np.float64)
    return m, history


MAP_SEEDS = 10  # a map's training seeds 0-9 each have their own block of training contexts


def map_block_start(seed: int, seed_base: int = 10_000) -> int:
    """The first episode seed of training seed ``seed``'s block of contexts. Seeds 0-4 start at ``seed_base·(seed+1)``
    (their shipped maps were fitted there); seeds 5-9 take the upper half of those blocks, ``seed_base/2`` later:
    10 blocks of ``seed_base/2`` seeds, none shared (:func:`map_block_size`)."""
    if not 0 <= seed < MAP_SEEDS:
        raise ValueError(f"seed = {seed}: a map's training seeds are 0-{MAP_SEEDS - 1}")
    return seed_base * (seed % 5 + 1) + seed_base // 2 * (seed // 5)


def map_block_size(seed_base: int = 10_000) -> int:
    """Episode seeds in each training seed's block of contexts (a fit must end inside its block)."""
    return seed_base // 2


def map_seed_span(kind: str, dim: int, obs_dim: int, seed: int, episodes: int, contexts: int = 64,
                  seed_base: int = 10_000, hidden: int = 8) -> tuple[int, int]:
    """The episode seeds [first, last] that :func:`fit_map` draws its training contexts from."""
    from cmaes import CMA

    size = ParamMap(kind, obs_dim, dim, hidden).size
    lam = CMA(mean=np.zeros(size), sigma=MAP_STEP).population_size
    generations = episodes // (lam * contexts)
    first = map_block_start(seed, seed_base)
    return first, first + generations * contexts - 1


@dataclass
class ContextSearch:
    """What a per-context search found: per context, the design (action) and whether it made the whole row."""

    actions: np.ndarray
    solved: np.ndarray
    traversals: np.ndarray   # what the kept design did on its context
    evaluations: np.ndarray  # episodes spent on each context
    obs: np.ndarray


def search_contexts(runner: EpisodeRunner, draws: list, start: np.ndarray, seed: int, max_evals: int = 200,
                    popsize: int = 8, sigma: float = SEARCH_STEP) -> ContextSearch:
    """Search each episode (context + build) of ``draws`` for a design that completes the whole row: the start
    design first, then CMA-ES about it (first step ``sigma``, ``popsize`` designs a generation, every open
    context's generation in one batch), until a design makes the row or ``max_evals`` episodes are spent. A
    context keeps the first design that made the row, else the best seen (most traversals, first). ``start``: one
    design for every context, or one row per context. A context solved after ``evaluations`` episodes is solved by a
    search with any ``max_evals`` at least that, and by none with less (the budget only stops a search)."""
    from cmaes import CMA

    n = len(draws)
    start = np.asarray(start, dtype=np.float64)
    actions = start.copy() if start.ndim == 2 else np.tile(start, (n, 1))
    best = runner.traversals(draws, actions)
    solved = best >= runner.full_row
    evals = np.ones(n, dtype=np.int64)
    opts = {i: CMA(mean=actions[i].copy(), sigma=sigma, bounds=np.tile([-1.0, 1.0], (actions.shape[1], 1)),
                   seed=seed * 100_003 + i, population_size=popsize) for i in np.flatnonzero(~solved)}
    while opts:
        open_ = [i for i in opts if evals[i] + popsize <= max_evals]
        if not open_:
            break
        cands = {i: [opts[i].ask() for _ in range(popsize)] for i in open_}
        batch_draws = [draws[i] for i in open_ for _ in range(popsize)]
        batch = np.array([x for i in open_ for x in cands[i]])
        got = runner.traversals(batch_draws, batch).reshape(len(open_), popsize)
        for row, i in enumerate(open_):
            evals[i] += popsize
            opts[i].tell([(x, -float(t)) for x, t in zip(cands[i], got[row])])
            j = int(np.argmax(got[row]))
            if got[row, j] > best[i]:
                best[i], actions[i] = got[row, j], cands[i][j]
            if best[i] >= runner.full_row:
                solved[i] = True
                del opts[i]
        for i in [i for i in opts if evals[i] + popsize > max_evals]:
            del opts[i]
    return ContextSearch(actions, solved, best, evals, runner.observations(draws))


@dataclass
class NearestNeighbour:
    """A context's design: the one found for the nearest training context (Euclidean, normalised context)
    among those where the search made the whole row (among all of them, with their best designs, where it made
    none)."""

    obs: np.ndarray
    actions: np.ndarray

    @classmethod
    def from_search(cls, found: ContextSearch) -> "NearestNeighbour":
        keep = found.solved if found.solved.any() else np.ones(len(found.solved), bool)
        return cls(np.asarray(found.obs[keep], float), np.asarray(found.actions[keep], float))

    def act(self, obs: np.ndarray) -> np.ndarray:
        obs = np.asarray(obs, dtype=np.float64)
        d2 = ((obs[:, None, :] - self.obs[None, :, :]) ** 2).sum(axis=2)
        return self.actions[np.argmin(d2, axis=1)]

    def to_json_dict(self) -> dict:
        return dict(obs=self.obs.tolist(), actions=self.actions.tolist())

    @classmethod
    def from_json_dict(cls, d: dict) -> "NearestNeighbour":
        return cls(np.asarray(d["obs"], float), np.asarray(d["actions"], float))
