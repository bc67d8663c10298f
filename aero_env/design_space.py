"""The design problem a config poses: actions to designs, the drawn context, tolerances.

A config's ``tunable`` list is the action space: action ``a`` in [-1, 1] maps onto
``[low, high]`` (for a tunable with ``relative_to``, those multiplied by that field's value in
the config: :meth:`Config.tunable_range`) linearly (``low + (a + 1)/2·(high - low)``) or geometrically
(``low·(high/low)^((a + 1)/2)``). A tunable's ``linked`` fields follow it by the same
factor relative to the config's values (so mu_k keeps its ratio to mu_s). A tunable with a
``step`` snaps to its nearest multiple inside the range (m3 to the 0.1 g a kitchen scale reads);
one with ``choices`` cuts the action's [-1, 1] into equal bins, one per choice, and sets the
field and its linked keys to that choice's values (a measured card pair). Either way a design
the action names is one a maker can build.

At each reset the ``context`` (what the designer knows of the scene: observed) and the
``tolerance`` draws (manufacturing error the designer does not know: not observed) come from
the caller's RNG. :meth:`DesignSpace.episode_config` then builds the config that is simulated:

    config values -> context draws -> tunable values (+ links) -> tolerances -> validated Config

The corners of that space are validated when the space is built (all of them up to
``EXHAUSTIVE_CORNERS`` varied dimensions, a fixed sample of 4096 beyond), so a bad ``tunable``
range fails at once, naming the corner and the field, instead of in the middle of training.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Mapping

import numpy as np

from .config import Config, ConfigError, check_value, real_field

EXHAUSTIVE_CORNERS = 12  # up to 2**12 corners are all checked; beyond, a fixed sample of 4096


@dataclass(frozen=True)
class Draw:
    """One reset's draws: context values (SI) and tolerance factors u in [-1, 1]."""

    context: dict
    tolerance_u: tuple


def in_action_dtype(a: np.ndarray) -> np.ndarray:
    """An action as the action space holds it (float32), returned as float64 for the mapping.

    A tuner proposes float64 points and a policy float32 ones; read through the space's dtype, both name the
    design the env's ``Box(..., float32)`` holds, so a stored design and the same action from a policy are one
    design. Without it a 5e-9 difference flipped 8 of 200 hold-out outcomes of a stored design (issue 35)."""
    return np.asarray(a, dtype=np.float64).astype(np.float32).astype(np.float64)


def _multiple(n: float, step: float) -> float:
    """``n·step`` as the maker writes it: 72 steps of 0.1 g is 0.0072 kg, not 72·1e-4 = 0.007200000000000001 (the
    step's own rounding error, carried into a stored design and onto the sheet). Twelve significant digits keep
    every multiple apart and drop that error."""
    return float(f"{n * step:.12g}")


def _on_grid(n: float, step: float, low: float, high: float) -> float:
    """The ``n``-th multiple of ``step``, kept inside [low, high] (the nearest multiple there)."""
    v = _multiple(n, step)
    if v < low:
        v = max(_multiple(math.ceil(low / step - 1e-9), step), low)  # a bound on the grid stays the bound, to the bit
    if v > high:
        v = min(_multiple(math.floor(high / step + 1e-9), step), high)
    return v


def _snap(v: float, step: float, low: float, high: float) -> float:
    """``v`` to the nearest multiple of ``step``, kept inside [low, high] (the nearest multiple there)."""
    return _on_grid(round(v / step), step, low, high)


def _snap_columns(v: np.ndarray, step: float, low: float, high: float) -> np.ndarray:
    """:func:`_snap` of every entry: the same rounding (numpy rounds half to even, as round does), and each multiple
    written once for the few that a batch reaches (a range of 0.1 g steps holds about a hundred)."""
    n, where = np.unique(np.round(v / step), return_inverse=True)
    return np.array([_on_grid(k, step, low, high) for k in n.tolist()], dtype=np.float64)[where.reshape(v.shape)]


class DesignSpace:
    def __init__(self, cfg: Config):
        self.cfg = cfg
        self.tunables = cfg.tunable
        self.context = cfg.context
        self.tolerances = tuple(t for t in cfg.tolerance if t.relative > 0 or t.absolute > 0)
        self.varied_context = tuple(c for c in self.context if c.low is not None and c.high > c.low)
        self.dim = len(self.tunables)
        if self.dim == 0:
            raise ConfigError("tunable: empty; the action space needs at least one tunable field")
        self.obs_dim = len(self.context)
        if self.obs_dim == 0:
            raise ConfigError("context: empty; the observation needs at least one field (e.g. scene.rise)")
        for section, entries in (("tunable", self.tunables), ("context", self.context)):
            for i, t in enumerate(entries):
                # checked here, not at load: simulate ignores these lists (a choice sets its linked keys, no scale)
                if t.linked and not getattr(t, "choices", ()) and cfg.value(t.name) <= 0:
                    raise ConfigError(f"{section}[{i}].linked: the links scale by {t.name} / its config value, which "
                                      f"is {cfg.value(t.name)!r}; allowed only when that value is > 0")
        # each tunable's (low, high) in its field's unit, a relative range resolved on this config's values
        self.ranges = tuple(cfg.tunable_range(t) for t in self.tunables)
        self._check_corners()

    # ---- actions <-> designs ----
    def values(self, action: np.ndarray) -> dict[str, float]:
        """Tunable (and linked) field values, SI, for an in-box action, read as the action space holds it
        (:func:`in_action_dtype`: float32)."""
        out: dict[str, float] = {}
        for t, (low, high), a in zip(self.tunables, self.ranges, in_action_dtype(np.asarray(action, np.float64))):
            x = (float(a) + 1.0) / 2.0
            if t.choices:  # one of a maker's choices, a bin of the box each: the field and its linked keys
                row = t.choices[min(max(math.floor(x * len(t.choices)), 0), len(t.choices) - 1)]
                out.update(zip((t.name, *t.linked), row))
                continue
            # low·(1-x) + high·x gives low and high exactly at the box's edges
            v = low * (high / low) ** x if t.scale == "log" else low * (1.0 - x) + high * x
            v = min(max(v, low), high)  # rounding must never step outside the declared range
            if t.step is not None:
                v = _snap(v, t.step, low, high)
            out[t.name] = v
            out.update(self._follow(t, v))
        return out

    def values_columns(self, actions: np.ndarray) -> dict[str, np.ndarray]:
        """:meth:`values` of every row of in-box ``actions`` (n, d) at once, one float64 array per field: the same
        double operations element by element, so each entry is the float :meth:`values` gives for its row (a
        geometric range takes Python's ``**`` per entry, as numpy's power need not round as Python's does)."""
        out: dict[str, np.ndarray] = {}
        for j, (t, (low, high)) in enumerate(zip(self.tunables, self.ranges)):
            x = (in_action_dtype(actions[:, j]) + 1.0) / 2.0
            if t.choices:
                n = len(t.choices)
                pick = np.clip(np.floor(x * n), 0, n - 1).astype(np.intp)
                for k, key in enumerate((t.name, *t.linked)):
                    out[key] = np.array([row[k] for row in t.choices], dtype=np.float64)[pick]
                continue
            if t.scale == "log":
                ratio = high / low
                v = np.array([low * ratio ** xj for xj in x.tolist()], dtype=np.float64)
            else:
                v = low * (1.0 - x) + high * x
            # min(max(v, low), high) as Python takes it: the first argument unless the other is strictly beyond it
            # (np.maximum(0.0, -0.0) gives -0.0 where max gives 0.0, and the model tells the two apart)
            v = np.where(low > v, low, v)
            v = np.where(high < v, high, v)
            if t.step is not None:
                v = _snap_columns(v, t.step, low, high)
            out[t.name] = v
            out.update(self._follow(t, v))
        return out

    def _follow(self, leader, value):
        """The values of ``leader``'s linked fields when it takes ``value`` (a float, or an array of them): each
        scaled by the same factor."""
        factor = value / self.cfg.value(leader.name) if leader.linked else 1.0
        return {key: self.cfg.value(key) * factor for key in leader.linked}

    def action_for(self, values: Mapping[str, float] | None = None, dtype=np.float32) -> np.ndarray:
        """The action (float32, the env's box; or ``dtype``) whose design is ``values`` (by dotted key; missing
        keys: the config's value)."""
        values = dict(values or {})
        tuned = {t.name for t in self.tunables}
        for key in values:
            if key not in tuned:
                linked = [t.name for t in self.tunables if key in t.linked]
                why = f"it follows {linked[0]} (linked)" if linked else "it is not tunable"
                raise ConfigError(f"action_for: {key!r} cannot be chosen, {why}; tunable fields: {sorted(tuned)}")
        a = np.empty(self.dim, dtype=dtype)
        for i, (t, (low, high)) in enumerate(zip(self.tunables, self.ranges)):
            # a value given here is read as the config reads one (a unit allowed: "7.2 g"), so NaN, None or a list
            # is refused in one line naming the field, before any arithmetic
            v = (check_value(t.name, real_field(t.name, "action_for"), values[t.name]) if t.name in values
                 else float(self.cfg.value(t.name)))
            if t.choices:  # the middle of the choice's bin
                leaders = [row[0] for row in t.choices]
                if v not in leaders:
                    raise ConfigError(f"{t.name} = {v!r}: not one of tunable[{i}]'s choices {leaders} (a maker's "
                                      f"measured values)")
                row = t.choices[leaders.index(v)]
                # a choice named by its first value is the whole pair; the config's own design must be one as listed
                for key, want in zip(t.linked if t.name not in values else (), row[1:]):
                    have = float(self.cfg.value(key))
                    if have != want:  # the config's other value of the pair is not the choice's
                        raise ConfigError(f"{key} = {have!r}: tunable[{i}]'s choice with {t.name} = {v!r} sets it to "
                                          f"{want!r}; give the pair as listed")
                a[i] = -1.0 + (2 * leaders.index(v) + 1) / len(leaders)
                continue
            if t.step is not None and abs(v / t.step - round(v / t.step)) > 1e-6:
                raise ConfigError(f"{t.name} = {v!r}: not a multiple of tunable[{i}].step = {t.step!r} (what a maker "
                                  f"can set); the nearest is {round(v / t.step) * t.step:.6g}")
            if not low <= v <= high:
                raise ConfigError(f"{t.name} = {v!r}: outside tunable[{i}]'s range [{low:.6g}, {high:.6g}]")
            x = math.log(v / low) / math.log(high / low) if t.scale == "log" else (v - low) / (high - low)
            a[i] = 2.0 * x - 1.0
        return a

    def check_action(self, action, clip: bool) -> np.ndarray:
        """``action`` as a float64 vector in the box, or a ConfigError naming the bad dimension."""
        try:
            raw = np.asarray(action)
        except (TypeError, ValueError):
            raw = np.asarray(None, dtype=object)
        if raw.dtype.kind not in "iuf":  # booleans, strings, None and objects are not positions in the box
            raise ConfigError(f"action = {action!r}: must be {self.dim} numbers in [-1, 1] (an integer or float "
                              f"array), got {'dtype ' + str(raw.dtype) if raw.dtype != object else 'non-numbers'}")
        a = raw.astype(np.float64)
        if a.shape != (self.dim,):
            raise ConfigError(f"action has shape {a.shape}: expected ({self.dim},), one value per tunable "
                              f"({', '.join(t.name for t in self.tunables)})")
        for i, (v, t) in enumerate(zip(a, self.tunables)):
            v = float(v)
            if not math.isfinite(v):
                raise ConfigError(f"action[{i}] ({t.name}) = {v!r}: must be a finite number in [-1, 1]")
            if not clip and abs(v) > 1.0:
                raise ConfigError(f"action[{i}] ({t.name}) = {v!r}: out of the action box, allowed [-1, 1] "
                                  f"(or set env.action_out_of_box: clip)")
        return np.clip(a, -1.0, 1.0)

    def rows_in_box(self, actions, clip: bool) -> np.ndarray | None:
        """:meth:`check_action` of every row of ``actions`` (n, d) at once, as one float64 array, where every row
        passes; None where one does not (:meth:`check_action` of that row then says why, in its words)."""
        a = np.asarray(actions)
        if a.dtype.kind not in "iuf":
            return None
        a = a.astype(np.float64)
        if not np.isfinite(a).all() or (not clip and (np.abs(a) > 1.0).any()):
            return None
        return np.clip(a, -1.0, 1.0)

    # ---- context and tolerances ----
    @property
    def draws_anything(self) -> bool:
        """Whether a reset draws anything (a varied context or a tolerance): if not, every seed is alike."""
        return bool(self.tolerances or self.varied_context)

    def draw(self, rng: np.random.Generator) -> Draw:
        u = rng.random(len(self.context) + len(self.tolerances))
        ctx = {}
        for c, ui in zip(self.context, u):
            ctx[c.name] = self.cfg.value(c.name) if c.low is None else c.low + float(ui) * (c.high - c.low)
        tol = tuple(2.0 * float(x) - 1.0 for x in u[len(self.context):])
        return Draw(ctx, tol)

    def fixed_draw(self) -> Draw:
        """What :meth:`draw` gives with any RNG in a space that draws nothing (no varied context, no tolerance),
        computed as :meth:`draw` computes it: a fixed range's ``low + u·0`` is ``low + 0.0``, which turns a -0.0
        into 0.0 (``nominal_draw``'s centre would keep it)."""
        if self.draws_anything:
            raise ValueError("fixed_draw: this space draws a context or a tolerance; use draw(rng)")
        ctx = {c.name: self.cfg.value(c.name) if c.low is None else c.low + 0.0 * (c.high - c.low)
               for c in self.context}
        return Draw(ctx, ())

    def draw_for_seed(self, seed: int) -> Draw:
        """What ``env.reset(seed=seed)`` draws (Gymnasium seeds the env's generator this way), for scoring an
        episode without the env."""
        from gymnasium.utils import seeding

        return self.draw(seeding.np_random(seed)[0])

    def nominal_draw(self) -> Draw:
        """The draw with every context at its config value (or range centre) and no tolerance error."""
        ctx = {c.name: self.cfg.value(c.name) if c.low is None else 0.5 * (c.low + c.high) for c in self.context}
        return Draw(ctx, (0.0,) * len(self.tolerances))

    def observation(self, draw: Draw) -> np.ndarray:
        """The context normalised to [-1, 1] over its range (0 where it is fixed), float32."""
        return self.observations([draw])[0]

    def episode_values(self, design: Mapping[str, float], draw: Draw) -> tuple[dict, dict]:
        """Every field the episode sets (dotted keys, SI: the drawn context and the fields linked to it, the
        design, the tolerances as built), and the fields the tolerances changed. The reduced model runs these without a Config
        (:func:`aero_env.models.reduced.simulate_designs`); :meth:`episode_config` builds one from them."""
        links = {}
        for c in self.context:
            links.update(self._follow(c, draw.context[c.name]))
        values = {**draw.context, **links, **design}
        built = {}
        for t, u in zip(self.tolerances, draw.tolerance_u):
            v = values.get(t.name, self.cfg.value(t.name))
            built[t.name] = v * (1.0 + t.relative * u) + t.absolute * u
        return {**values, **built}, built

    def episode_columns(self, design: Mapping[str, np.ndarray], draws) -> tuple[dict, dict]:
        """:meth:`episode_values` of many episodes at once, as one float64 array per field: ``design`` from
        :meth:`values_columns`, ``draws`` one :class:`Draw` per episode; each entry is the float
        :meth:`episode_values` gives for its episode."""
        n = len(draws)
        context = {c.name: np.array([d.context[c.name] for d in draws], dtype=np.float64) for c in self.context}
        links = {}
        for c in self.context:
            links.update(self._follow(c, context[c.name]))
        values = {**context, **links, **design}
        built = {}
        if self.tolerances:
            u = np.array([d.tolerance_u for d in draws], dtype=np.float64).reshape(n, len(self.tolerances))
            for j, t in enumerate(self.tolerances):
                v = values[t.name] if t.name in values else np.full(n, self.cfg.value(t.name), dtype=np.float64)
                built[t.name] = v * (1.0 + t.relative * u[:, j]) + t.absolute * u[:, j]
        return {**values, **built}, built

    def observations(self, draws) -> np.ndarray:
        """:meth:`observation` of each draw, stacked (n, k) float32."""
        obs = np.zeros((len(draws), self.obs_dim), dtype=np.float32)
        for i, c in enumerate(self.context):
            if c.low is not None and c.high > c.low:
                ctx = np.array([d.context[c.name] for d in draws], dtype=np.float64)
                obs[:, i] = 2.0 * (ctx - c.low) / (c.high - c.low) - 1.0
        return obs

    def episode_config(self, design: Mapping[str, float], draw: Draw) -> tuple[Config, dict]:
        """The config to simulate, and the fields the tolerances changed (as built, SI)."""
        values, built = self.episode_values(design, draw)
        return self.cfg.with_values(values), built

    # ---- validation ----
    def _check_corners(self) -> None:
        """Every corner of actions x context x tolerances must be a valid design, and every listed choice (the
        corners reach only a list's first and last)."""
        base = self.action_for(dtype=np.float64) if self.dim else np.zeros(0)
        for j, t in enumerate(self.tunables):
            for k in range(len(t.choices)):
                a = base.copy()
                a[j] = -1.0 + (2 * k + 1) / len(t.choices)
                try:
                    self.episode_config(self.values(a), self.nominal_draw())
                except ConfigError as exc:
                    raise ConfigError(f"tunable[{j}].choices[{k}] = {list(t.choices[k])}: not a valid design with the "
                                      f"config's other values: {exc}") from None
        varied_ctx = self.varied_context
        n = self.dim + len(varied_ctx) + len(self.tolerances)
        signs = [(-1.0, 1.0)] * n
        if n <= EXHAUSTIVE_CORNERS:
            corners = itertools.product(*signs)
        else:
            rng = np.random.default_rng(0)
            corners = (tuple(rng.choice((-1.0, 1.0), size=n)) for _ in range(2 ** EXHAUSTIVE_CORNERS))
        for corner in corners:
            a = np.array(corner[:self.dim])
            ctx = {c.name: self.cfg.value(c.name) for c in self.context}
            for c, s in zip(varied_ctx, corner[self.dim:]):
                ctx[c.name] = c.low if s < 0 else c.high
            draw = Draw(ctx, tuple(corner[self.dim + len(varied_ctx):]))
            try:
                self.episode_config(self.values(a), draw)
            except ConfigError as exc:
                where = ", ".join(f"{k}={v:.6g}" for k, v in {**self.values(a), **ctx}.items())
                raise ConfigError(f"the design space reaches an invalid design at the corner ({where}"
                                  f"{', tolerances ' + str(draw.tolerance_u) if draw.tolerance_u else ''}): "
                                  f"{exc}") from None


def _flat(d: dict, prefix: str = "") -> dict:
    out = {}
    for k, v in d.items():
        out.update(_flat(v, f"{prefix}{k}.") if isinstance(v, dict) else {f"{prefix}{k}": v})
    return out


CHECKS_ONLY = "scene.effects.clearance"  # a scene key that checks a design and changes no physics


def changes_outside_tunables(cfg: Config, other: Config) -> list[str]:
    """The design and scene keys in which ``other`` differs from ``cfg`` outside ``cfg``'s tunables (and the
    keys linked to them): empty when ``other`` is only another design for ``cfg``'s scene and robot. A scene's
    stored solution must be (``aero-env scenes``), and so must a design a sheet compares with.
    ``scene.effects.clearance`` is no change: a check, not physics (a solution found with it on runs, where its
    kit clears, as it would with it off)."""
    free = {t.name for t in cfg.tunable} | {k for t in cfg.tunable for k in t.linked} | {CHECKS_ONLY}
    a = _flat({k: cfg.to_dict()[k] for k in ("design", "scene")})
    b = _flat({k: other.to_dict()[k] for k in ("design", "scene")})
    return sorted(k for k in a.keys() | b.keys() if k not in free and a.get(k) != b.get(k))
