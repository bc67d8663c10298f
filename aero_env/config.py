"""Scene configuration: schema, defaults, loading, overrides and validation.

A config has three sections, all in SI units with the paper's symbols:

* ``design``: what a designer of the toy changes (lengths, masses, spring, friction pair,
  hook geometry, angle limits).
* ``scene``: the row of swing frames, the start state, and the ``effects`` the scene
  switches on (each effect is a part the physics builder adds only when named).
* ``sim``: the fidelity (a named preset of model, time step, solver iterations and substeps),
  tolerances and time limits.

Four more sections describe the design problem that the Gymnasium environment poses
(the physics never reads them):

* ``tunable``: the action space, a list of ``{name, low, high, scale, linked}``; one action
  dimension per entry, mapped onto [low, high] (linear or log).
* ``context``: the observation, a list of ``{name, low, high}``; what a designer knows of the
  scene. Drawn uniformly at each reset; without low/high it stays at the config's value.
* ``tolerance``: a list of ``{name, relative, absolute}``; manufacturing error the designer does
  not know, drawn at each reset and applied to the built machine.
* ``env``: episode options (out-of-box actions, reward shaping, rendering).

A number may carry its unit, in a file or in ``--set``: ``m2: 7.71 g``, ``La: "48.3 mm"``,
``spring_k: 0.877 N*mm/rad``, ``rest_angle_deg: 55 deg`` (:mod:`aero_env.quantities` lists the
spellings); a plain number is in the key's own unit. The allowed ranges are those of a card toy
(masses up to 100 g, a spring up to 100 N·mm/rad, friction torques up to 10 N·mm, a row rising
at most 10 cm a frame), so that a plain number written in the usual smaller unit
(``design.m2=7.7`` for 7.7 g) is out of range and the error asks "did you mean 7.7 g?".

Every field is declared once below with its default, unit, allowed range and meaning;
the schema table of docs/configuration.md is generated from the same declarations (``aero-env schema``).
``load_config(path, overrides={"design.m2": 0.008})`` returns a validated, immutable
:class:`Config`. Bad input raises :class:`ConfigError` naming the key, the value and
the allowed range.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, Mapping

import yaml

from . import quantities
from .units import GRAVITY


class ConfigError(ValueError):
    """A config value is missing, unknown, of the wrong type or out of range."""


def spec(default: Any, unit: str, doc: str, lo: float | None = None, hi: float | None = None,
         lo_open: bool = False, choices: tuple[str, ...] | None = None):
    """Declare one config field: default, unit, meaning and allowed range."""
    return field(default=default, metadata=dict(unit=unit, doc=doc, lo=lo, hi=hi,
                                                lo_open=lo_open, choices=choices))


@dataclass(frozen=True)
class Design:
    """What a designer changes. Table 1 and Table 3 (white/gray) of the article by default."""

    La: float = spec(0.0483, "m", "axis to counterbalance, along the frame", 0.0, 1.0, lo_open=True)
    Lb: float = spec(0.0517, "m", "axis to handrail (the hook's seat)", 0.0, 1.0, lo_open=True)
    Lc: float = spec(0.03, "m", "two-link model: joint (hook) to robot centre; sets I2 with Ld", 0.0, 0.3)
    Ld: float = spec(0.06, "m", "two-link model: joint (hook) to bottom of torso; sets I2 with Lc", 0.0, 0.5, lo_open=True)
    h: float = spec(0.005, "m", "counterbalance offset normal to the frame", -0.1, 0.1)
    m1: float = spec(0.004, "kg", "swing frame mass (I1 = 2*m1/3*(La^2+Lb^2-La*Lb))", 0.0, 0.1, lo_open=True)
    m2: float = spec(0.00771, "kg", "robot mass as Table 1 counts it: torso card + coins + arm + the handrail "
                     "(handrail_mass, which the world puts on the frame)", 0.0, 0.1, lo_open=True)
    m3: float = spec(0.0072, "kg", "counterbalance mass (point mass at (La, h))", 0.0, 0.1, lo_open=True)
    dT: float = spec(0.0, "N·m", "frame's own moment at theta1 = 0 without robot and counterbalance", -0.1, 0.1)
    spring_k: float = spec(8.77e-4, "N·m/rad", "leaf-spring stiffness (torque = k·(alpha - alpha_min))", 0.0, 0.1, lo_open=True)
    mu_s: float = spec(0.542, "-", "static friction, arm tip on handrail", 0.0, 10.0)
    mu_k: float = spec(0.409, "-", "kinetic friction, arm tip on handrail (<= mu_s)", 0.0, 10.0)
    arm_length: float = spec(0.03, "m", "arm: torso axle to hook tip", 0.0, 0.3, lo_open=True)
    arm_mass: float = spec(0.0015, "kg", "arm mass (part of m2), a uniform rod", 0.0, 0.1, lo_open=True)
    torso_length: float = spec(0.0874, "m", "torso card strip, from the axle down (fitted: docs/physics.md)", 0.0, 0.5, lo_open=True)
    coin_mass: float = spec(0.004, "kg", "coins on the torso (part of m2; four 1-yen coins of 1 g)", 0.0, 0.1)
    coin_radius: float = spec(0.01, "m", "coin radius (a 1-yen coin is 20 mm across)", 0.0, 0.1)
    coin_offset: float = spec(0.0869, "m", "axle to the coins' centre, along the torso (fitted: docs/physics.md)", 0.0, 0.5)
    handrail_mass: float = spec(0.00021, "kg", "the handrail's card, counted in m2 by Table 1 and carried by the "
                                "frame at the seat (docs/physics.md: 0.21 g, not the 2.1 g the text prints)",
                                0.0, 0.01)
    pivot_friction: float = spec(1.0e-4, "N·m", "Coulomb friction torque of each frame's bamboo skewer in its card "
                                 "shaft hole (0: no part built)", 0.0, 0.01)
    axle_friction: float = spec(8.0e-6, "N·m", "Coulomb friction torque at the arm's axle in the torso (0: no part "
                                "built)", 0.0, 0.01)
    alpha_min_deg: float = spec(60.0, "deg", "arm angle with the spring straight (arm snapped forward)", 0.0, 180.0)
    alpha_max_deg: float = spec(120.0, "deg", "arm angle with the spring fully bent", 0.0, 180.0)
    rest_angle_deg: float = spec(55.0, "deg", "frame angle theta1 at rest, counterbalance against the stopper", -90.0, 270.0)
    stop_angle_deg: float = spec(180.0, "deg", "frame angle theta1 at the end stop", -90.0, 270.0)
    notch_angle_deg: float = spec(65.72, "deg", "handrail notch bisector direction (world) at the rest angle", -180.0, 180.0)
    notch_opening_deg: float = spec(90.0, "deg", "angle between the handrail notch's two faces", 30.0, 150.0)
    notch_back_face: float = spec(0.00426, "m", "handrail notch face that rises toward the back (at rest)", 0.0, 0.1, lo_open=True)
    notch_front_face: float = spec(0.00584, "m", "handrail notch face that rises toward the front (at rest)", 0.0, 0.1, lo_open=True)
    handrail_thickness: float = spec(0.001, "m", "card thickness of the handrail faces", 0.0, 0.01, lo_open=True)
    hook_radius: float = spec(0.001, "m", "radius of the arm tip's contact edge", 0.0, 0.01, lo_open=True)
    Cd: float = spec(1.05, "-", "drag coefficient (drag effect)", 0.0, 10.0)
    rho: float = spec(1.29, "kg/m^3", "air density (drag effect)", 0.0, 100.0)
    frame_width: float = spec(0.01, "m", "projected width of a frame, per unit length (drag effect)", 0.0, 0.1)
    robot_width: float = spec(0.02, "m", "projected width of torso and arm (drag effect)", 0.0, 0.1)


@dataclass(frozen=True)
class Effects:
    """The effects a scene switches on; the builder adds only the parts named here."""

    drag: bool = spec(False, "-", "quadratic air drag on frames, torso and arm")
    friction: str = spec("static_kinetic", "-", "hook friction law: static_kinetic switches mu_s/mu_k by slip speed; "
                         "static or kinetic use one coefficient", choices=("static_kinetic", "static", "kinetic"))
    spring_law: str = spec("linear", "-", "leaf spring: linear k·da, or stiffening k/2·da^2",
                           choices=("linear", "stiffening"))
    live_frames: int = spec(1, "-", "frames ahead of the robot's frame that are simulated (others cost nothing)", 1, 100)
    hook: str = spec("contact", "-", "contact: the frictional hook on the notched handrail; pin: the two-link model "
                     "(hook pinned to frame 0, robot one rigid body with m2, Lc, I2; for checking the world)",
                     choices=("contact", "pin"))


@dataclass(frozen=True)
class Scene:
    """The row of frames and the start state."""

    frames: int = spec(8, "-", "swing frames in the row", 2, 1000)
    pitch: float = spec(0.082, "m", "horizontal distance between neighbouring frame axes", 0.0, 0.5, lo_open=True)
    rise: float = spec(0.002, "m", "height gained per frame (the incline of the row)", -0.1, 0.1)
    theta2_start_deg: float = spec(81.0, "deg", "robot line angle at the first catch (brief: 80-81)", 0.0, 180.0)
    floor_drop: float = spec(0.15, "m", "floor depth below the axis of the frame the robot left", 0.0, 2.0, lo_open=True)
    effects: Effects = field(default_factory=Effects, metadata=dict(unit="", doc="effects switched on", lo=None,
                                                                    hi=None, lo_open=False, choices=None))


# The fidelity ladder, cheapest to most accurate. A preset is data: it fills the sim fields it
# names, and a field the config names beside it wins (see ``from_dict``). ``model`` picks the
# engine: ``mbd`` is the pymunk world, ``reduced`` the two-link swing with ballistic flight and a
# geometric catch test (no pymunk; ``dt`` is then its integration step). ``reference`` is the step
# and iteration count past which refining (half the step, twice the iterations) keeps the traversal count of >= 99 %
# of random designs and moves the median first detach by <= one default step (measured: 99.0 %,
# 0.19 ms on 200 designs): docs/fidelity.md, "The ladder, measured", gives the study and the rungs.
FIDELITY_PRESETS: dict[str, dict[str, Any]] = {
    "reduced": dict(model="reduced", dt=0.004, iterations=1, substeps=1),
    "mbd-fast": dict(model="mbd", dt=0.001, iterations=30, substeps=1),
    "mbd": dict(model="mbd", dt=0.0005, iterations=30, substeps=1),
    "mbd-fine": dict(model="mbd", dt=0.00025, iterations=30, substeps=2),
    "reference": dict(model="mbd", dt=0.0000625, iterations=120, substeps=1),
}
DEFAULT_FIDELITY = "mbd"


@dataclass(frozen=True)
class Sim:
    """Fidelity, time stepping, solver and event thresholds."""

    fidelity: str = spec(DEFAULT_FIDELITY, "-", "named preset of model, dt, iterations and substeps "
                         "(cheapest first); a field set beside it wins over the preset",
                         choices=tuple(FIDELITY_PRESETS))
    model: str = spec("mbd", "-", "mbd: the pymunk world; reduced: two-link swing + ballistic flight + geometric "
                      "catch test, no pymunk (set by the fidelity preset)", choices=("mbd", "reduced"))
    dt: float = spec(0.0005, "s", "physics time step (reduced: its integration step); set by the fidelity preset",
                     0.0, 0.01, lo_open=True)
    iterations: int = spec(30, "-", "pymunk solver iterations per step; set by the fidelity preset", 1, 1000)
    substeps: int = spec(1, "-", "pymunk steps of dt per runner step: events, friction switching and checks run "
                         "once per runner step; set by the fidelity preset", 1, 100)
    collision_slop: float = spec(2e-5, "m", "allowed contact overlap (pymunk slop)", 0.0, 0.001)
    slip_speed: float = spec(0.001, "m/s", "tangential speed above which the hook slides (mu_k)", 0.0, 1.0, lo_open=True)
    contact_hold: float = spec(0.01, "s", "contact must be lost (or kept) this long for a detach (or catch)", 0.0, 1.0, lo_open=True)
    catch_seat: float = spec(0.003, "m", "a touch of the next handrail held for contact_hold is a catch only if the "
                             "hook's centre came this close to the seat (the notch's corner) meanwhile; a seated hook "
                             "sits there up to its penetration (< 1 mm); farther touches are grazes", 0.0, 0.1,
                             lo_open=True)
    flight_timeout: float = spec(0.5, "s", "longest flight between detach and catch", 0.0, 10.0, lo_open=True)
    swing_timeout: float = spec(3.0, "s", "longest swing on one frame before it counts as stalled", 0.0, 60.0, lo_open=True)
    rest_timeout: float = spec(1.0, "s", "a frame that has not left its rest angle this long after the catch never "
                               "will (the hanging robot's swing only loses energy, so its largest pull comes "
                               "first): stalled", 0.0, 60.0, lo_open=True)
    stop_hold: float = spec(0.3, "s", "time hooked at the end stop before the run is no_detach", 0.0, 10.0, lo_open=True)
    t_max: float = spec(60.0, "s", "hard limit on simulated time for a run", 0.0, 3600.0, lo_open=True)
    energy_tolerance: float = spec(0.005, "-", "largest rise of mechanical energy above its running minimum before "
                                   "'unstable', as a fraction of (m2 + m3)·g·(La + Lb) + the spring's energy "
                                   "fully bent", 0.0, 1.0, lo_open=True)
    check_interval: float = spec(0.005, "s", "check energy, health and finiteness this often (at least every runner "
                                 "step; and every step while the hook is being caught, where penetration peaks)",
                                 0.0, 1.0, lo_open=True)
    min_release_height: float = spec(0.01, "m", "a hook letting go lower than this above the next handrail has fallen short", 0.0, 1.0)
    max_speed: float = spec(20.0, "m/s", "any body faster than this is 'unstable'", 0.0, 1e4, lo_open=True)
    max_joint_drift: float = spec(1e-3, "m", "a frame skewer, the arm's axle or a pinned hook coming apart by more "
                                  "than this is 'unstable'", 0.0, 0.1, lo_open=True)
    max_limit_overshoot_deg: float = spec(5.0, "deg", "a frame or the arm turning past its stopper by more than "
                                          "this is 'unstable'", 0.0, 90.0, lo_open=True)
    max_penetration: float = spec(0.8, "-", "the hook sinking into a handrail card deeper than this fraction of "
                                  "hook_radius + half the card is 'unstable' (at 1 its centre reaches the card's "
                                  "middle and it tunnels through)", 0.0, 1.0, lo_open=True)
    trace_every: int = spec(2, "-", "record the trace every this many runner steps", 1, 100000)


@dataclass(frozen=True)
class EnvOptions:
    """How the design environment treats actions, rewards and rendering."""

    action_out_of_box: str = spec("error", "-", "an action outside [-1, 1]: error names the dimension; clip clips it "
                                  "(NaN is always an error)", choices=("error", "clip"))
    reward_shaping: float = spec(0.0, "-", "partial credit for a failed transfer that flew (the hook let go): "
                                 "reward = traversals + reward_shaping·max(0, 1 - miss_distance/pitch); a hook that "
                                 "never let go (stalled, no_detach) earns none; 0 = off", 0.0, 0.99)
    record_trace: bool = spec(False, "-", "keep each step's time series (angles, speeds, energy every sim.trace_every "
                              "steps) in env.unwrapped.last_run.trace; off: last_run holds the summary only")
    render_width: int = spec(720, "px", "width of rendered frames", 64, 4096)
    render_height: int = spec(300, "px", "height of rendered frames", 64, 4096)
    render_slowmo: float = spec(4.0, "-", "rendered animations play this many times slower than real time",
                                0.1, 100.0)


def _item(doc: str, unit: str = "-", default: Any = None):
    return field(default=default, metadata=dict(unit=unit, doc=doc, lo=None, hi=None, lo_open=False, choices=None))


@dataclass(frozen=True)
class Tunable:
    """One action dimension: a design or scene number and the range the action maps onto."""

    name: str = _item("dotted key of a real-valued design or scene field, e.g. design.m3")
    low: float = _item("value at action -1 (with relative_to: a multiple of that field's value)", "field's")
    high: float = _item("value at action +1, above low (with relative_to: a multiple)", "field's")
    scale: str = _item("linear, or log (geometric; low > 0)", default="linear")
    linked: tuple = _item("keys scaled by the same factor as this one, keeping their ratio to it "
                          "(design.mu_k with design.mu_s keeps the friction pair's ratio)", default=())
    relative_to: str | None = _item("a dotted key: low and high are then multiples of that field's value in the "
                                    "config, so the range follows the scene (absent: low and high are in the "
                                    "field's own unit)", default=None)


@dataclass(frozen=True)
class ContextRange:
    """One observed scene number, drawn uniformly from [low, high] at reset (fixed when both are absent)."""

    name: str = _item("dotted key of a real-valued design or scene field, e.g. scene.rise")
    low: float | None = _item("lowest value drawn (absent: the config's value)", "field's")
    high: float | None = _item("highest value drawn (absent: the config's value)", "field's")


@dataclass(frozen=True)
class Tolerance:
    """Manufacturing error on one number: value·(1 + relative·u) + absolute·u, u ~ U(-1, 1) at reset."""

    name: str = _item("dotted key of a real-valued design or scene field, e.g. design.m3")
    relative: float = _item("± fraction of the value, in [0, 0.5]", default=0.0)
    absolute: float = _item("± in the field's unit, >= 0", "field's", default=0.0)


# The default design problem: the frame's counterbalance (m3, h, La), the leaf spring, and the
# card pair of the hook (mu_s, with mu_k kept at the pair's ratio). The robot's mass, the
# row's rise and pitch are what the designer is given. The ranges follow the scene: the
# counterbalance's mass scales with the robot it balances, its place with the frame's arm La,
# and the spring with its own value, so a smaller toy (``--set design.La=0.029``) is searched
# around its own size. On the prototype they span 3.9-12.3 g, -9.7-19.3 mm, 36-65 mm and
# 0.19-3.9 N·mm/rad, and the prototype lies inside every range. The card pair's friction is a
# property of the card, not of the toy's size, so its range is absolute.
DEFAULT_TUNABLES = (
    Tunable("design.m3", 0.5, 1.6, relative_to="design.m2"),
    Tunable("design.h", -0.2, 0.4, relative_to="design.La"),
    Tunable("design.La", 0.75, 1.35, relative_to="design.La"),
    Tunable("design.spring_k", 0.22, 4.5, "log", relative_to="design.spring_k"),
    Tunable("design.mu_s", 0.2, 1.5, "log", linked=("design.mu_k",)),
)
DEFAULT_CONTEXT = (ContextRange("scene.rise"), ContextRange("scene.pitch"), ContextRange("design.m2"))


@dataclass(frozen=True)
class Config:
    design: Design = field(default_factory=Design)
    scene: Scene = field(default_factory=Scene)
    sim: Sim = field(default_factory=Sim)
    tunable: tuple[Tunable, ...] = DEFAULT_TUNABLES
    context: tuple[ContextRange, ...] = DEFAULT_CONTEXT
    tolerance: tuple[Tolerance, ...] = ()
    env: EnvOptions = field(default_factory=EnvOptions)

    def tunable_range(self, t: Tunable) -> tuple[float, float]:
        """``t``'s ``(low, high)`` in its field's unit: as written, or times ``t.relative_to``'s value here.

        A relative range is checked here, when the design problem is posed (the environment, a tuner),
        not when the config is read: ``aero-env simulate`` ignores the tunables, so a scene scaled past
        where its relative ranges fit the fields' ranges still simulates."""
        if t.relative_to is None:
            return t.low, t.high
        i = self.tunable.index(t)
        base = float(self.value(t.relative_to))
        if not base > 0:
            raise ConfigError(f"tunable[{i}].relative_to = {t.relative_to!r}: its value in this config is {base!r}; a "
                              f"range relative to it needs a value > 0 (or give {t.name}'s low and high in its unit)")
        low, high = t.low * base, t.high * base
        f = real_field(t.name, f"tunable[{i}].name")
        for key, v in (("low", low), ("high", high)):
            _check_value(f"tunable[{i}].{key} ({getattr(t, key):g} x {t.relative_to} = {v:.6g}, a value of {t.name})",
                         f, v)
        return low, high

    def to_dict(self) -> dict:
        """Plain dicts and lists (YAML-ready); ``from_dict(cfg.to_dict())`` gives ``cfg`` back.

        Sim fields equal to their fidelity preset's value are left out, so that the dict names the
        fidelity and only what departs from it: ``replace({"sim.fidelity": ...})`` on it moves the
        preset's fields with the fidelity."""
        out = _plain(dataclasses.asdict(self))
        preset = FIDELITY_PRESETS[self.sim.fidelity]
        for key, value in preset.items():
            if out["sim"][key] == value:
                del out["sim"][key]
        return out

    def to_yaml(self) -> str:
        """The whole config as YAML that :func:`load_config` reads back to an equal config."""
        return yaml.safe_dump(self.to_dict(), sort_keys=False)

    def value(self, key: str) -> Any:
        """A field by dotted key, e.g. ``cfg.value("design.m3")`` or ``cfg.value("scene.effects.drag")``."""
        node: Any = self
        for name in key.split("."):
            node = getattr(node, name)
        return node

    def with_values(self, values: Mapping[str, float]) -> "Config":
        """A new config with real-valued ``design.*``/``scene.*`` fields set, each checked against its
        range and the design's cross-checks (the fast path ``replace`` takes for numbers only)."""
        changes: dict[str, dict[str, float]] = {"design": {}, "scene": {}}
        for key, v in values.items():
            f = real_field(key, "key")
            sec, name = key.split(".", 1)
            changes[sec][name] = _check_value(key, f, v)
        cfg = dataclasses.replace(self, design=dataclasses.replace(self.design, **changes["design"]),
                                  scene=dataclasses.replace(self.scene, **changes["scene"]))
        _check_design(cfg.design)
        return cfg

    def replace(self, overrides: Mapping[str, Any]) -> "Config":
        """A new validated config with dotted-key overrides applied."""
        return from_dict(self.to_dict(), overrides)


SECTIONS = {"design": Design, "scene": Scene, "sim": Sim, "env": EnvOptions}
LIST_SECTIONS = {"tunable": Tunable, "context": ContextRange, "tolerance": Tolerance}


def _plain(x: Any) -> Any:
    if isinstance(x, Mapping):
        return {k: _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_plain(v) for v in x]
    return x


def _set_dotted(tree: dict, key: str, value: Any) -> None:
    if key in LIST_SECTIONS:  # a list section is replaced whole
        tree[key] = value
        return
    parts = key.split(".")
    if len(parts) < 2 or parts[0] not in SECTIONS:
        hint = did_you_mean(key, [r[0] for r in schema_rows() if "[]" not in r[0]] + list(LIST_SECTIONS))
        raise ConfigError(f"override key {key!r}: must start with one of {sorted(SECTIONS)} (e.g. design.m2), "
                          f"or be one of {sorted(LIST_SECTIONS)}{hint}")
    node = tree
    for p in parts[:-1]:
        child = node.setdefault(p, {})
        if not isinstance(child, dict):
            raise ConfigError(f"override key {key!r}: {p!r} is a value, not a section")
        node = child
    node[parts[-1]] = value


def _check_value(path: str, f: dataclasses.Field, value: Any) -> Any:
    meta = f.metadata
    typ = f.type if isinstance(f.type, type) else {"float": float, "int": int, "bool": bool, "str": str}.get(f.type)
    if typ is bool:
        if not isinstance(value, bool):
            raise ConfigError(f"{path} = {value!r}: must be true or false")
        return value
    if typ is str:
        if not isinstance(value, str) or (meta["choices"] and value not in meta["choices"]):
            raise ConfigError(f"{path} = {value!r}: must be one of {list(meta['choices'])}")
        return value
    raw = value
    value, plain = _with_unit(path, value, meta["unit"])
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        units = quantities.units_for(meta["unit"])
        with_units = f", optionally with a unit ({', '.join(units)})" if len(units) > 1 else ""
        raise ConfigError(f"{path} = {value!r}: must be a number ({typ.__name__}) in {_range_text(meta)}{with_units}")
    shown = repr(value) if plain else f"{raw!r} (= {value:.6g} {meta['unit']})"
    if typ is int:
        if isinstance(value, float) and not value.is_integer():
            raise ConfigError(f"{path} = {shown}: must be a whole number in {_range_text(meta)}")
        value = int(value)
    else:
        value = float(value)
    if plain:
        shown = repr(value)
    if not math.isfinite(value):
        raise ConfigError(f"{path} = {shown}: must be finite, in {_range_text(meta)}")
    if not _in_range(meta, value):
        hint = quantities.smaller_unit_hint(value, meta["unit"], lambda v: _in_range(meta, v)) if plain else ""
        raise ConfigError(f"{path} = {shown}: out of range, allowed {_range_text(meta)}{hint}")
    return value


def _in_range(meta: Mapping[str, Any], value: float) -> bool:
    lo, hi = meta["lo"], meta["hi"]
    if lo is not None and (value < lo or (meta["lo_open"] and value == lo)):
        return False
    return hi is None or value <= hi


def _with_unit(path: str, value: Any, unit: str) -> tuple[Any, bool]:
    """``value`` as a number in ``unit`` when it is a string that spells one (``"7.71 g"``, or ``"1e-9"``,
    which YAML 1.1 reads as a string), and whether it was a plain number (no unit named)."""
    if not isinstance(value, str):
        return value, True
    try:
        number = quantities.parse(value, unit)
    except quantities.UnitError as exc:
        raise ConfigError(f"{path} = {value!r}: {exc}") from None
    if number is None:
        return value, True
    try:
        float(value)
        return number, True
    except ValueError:
        return number, False


def _range_text(meta: Mapping[str, Any]) -> str:
    lo, hi, unit = meta["lo"], meta["hi"], meta["unit"]
    left = "(" if meta["lo_open"] else "["
    u = f" {unit}" if unit and unit != "-" else ""
    return f"{left}{lo}, {hi}]{u}"


def did_you_mean(name: Any, candidates, prefix: str = "") -> str:
    """"; did you mean PREFIXkey?" naming the candidate closest to ``name`` (difflib; case ignored), or ""."""
    by_lower: dict[str, str] = {}
    for c in candidates:
        by_lower.setdefault(str(c).lower(), str(c))
    text = str(name).lower()
    if text in by_lower:
        return f"; did you mean {prefix}{by_lower[text]}?"
    close = difflib.get_close_matches(text, list(by_lower), n=1, cutoff=0.6)
    return f"; did you mean {prefix}{by_lower[close[0]]}?" if close else ""


def _unknown_key(where: str, name: Any, known, prefix: str = "") -> ConfigError:
    """An unknown key: the closest known one, else the keys themselves when few, else where to find them."""
    known = sorted(map(str, known))
    hint = did_you_mean(name, known, prefix)
    if not hint:
        hint = (f"; allowed keys are {known}" if len(known) <= 8 else
                f"; none is close among its {len(known)} keys (aero-env schema lists them)")
    return ConfigError(f"{where}: unknown key{hint}")


def _build(cls, data: Any, path: str):
    if data is None:
        data = {}
    if not isinstance(data, Mapping):
        raise ConfigError(f"{path}: must be a mapping of keys to values, got {data!r}")
    known = {f.name: f for f in fields(cls)}
    unknown = sorted(map(str, set(data) - set(known)))
    if unknown:
        raise _unknown_key(f"{path}.{unknown[0]}", unknown[0], known, f"{path}.")
    kwargs = {}
    for name, f in known.items():
        if name not in data:
            continue
        sub = f.default_factory if f.default_factory is not dataclasses.MISSING else None
        if sub is not None and dataclasses.is_dataclass(sub):
            kwargs[name] = _build(sub, data[name], f"{path}.{name}")
        else:
            kwargs[name] = _check_value(f"{path}.{name}", f, data[name])
    return cls(**kwargs)


def _check_design(d: Design) -> None:
    if d.mu_k > d.mu_s:
        raise ConfigError(f"design.mu_k = {d.mu_k!r}: must not exceed design.mu_s = {d.mu_s!r} "
                          f"(kinetic friction is at most static), allowed [0, {d.mu_s}]")
    if not d.alpha_min_deg < d.alpha_max_deg:
        raise ConfigError(f"design.alpha_max_deg = {d.alpha_max_deg!r}: must exceed design.alpha_min_deg = "
                          f"{d.alpha_min_deg!r}, allowed ({d.alpha_min_deg}, 180]")
    if not 10.0 <= d.stop_angle_deg - d.rest_angle_deg <= 270.0:
        raise ConfigError(f"design.stop_angle_deg = {d.stop_angle_deg!r}: the frame must be able to turn from "
                          f"rest_angle_deg = {d.rest_angle_deg!r} by 10 to 270 deg, allowed "
                          f"[{d.rest_angle_deg + 10}, {d.rest_angle_deg + 270}]")
    x_max = max(d.La, d.Lb)
    if abs(d.dT) > d.m1 * GRAVITY * x_max:
        lim = d.m1 * GRAVITY * x_max
        raise ConfigError(f"design.dT = {d.dT!r}: the frame's own moment would put its centre of mass beyond its "
                          f"ends, allowed [{-lim:.3g}, {lim:.3g}] N·m (m1·g·max(La, Lb))")
    if d.coin_offset > d.torso_length:
        raise ConfigError(f"design.coin_offset = {d.coin_offset!r}: the coins sit on the torso card, allowed "
                          f"[0, {d.torso_length}] m (design.torso_length)")
    parts = d.arm_mass + d.coin_mass + d.handrail_mass
    if parts >= d.m2:
        hi = Design.__dataclass_fields__["m2"].metadata["hi"]
        raise ConfigError(f"design.m2 = {d.m2!r}: must exceed its listed parts arm_mass + coin_mass + handrail_mass "
                          f"= {parts:.6g} kg (the torso card is the rest), allowed ({parts:.6g}, {hi:g}] kg")


def from_dict(data: Mapping[str, Any] | None, overrides: Mapping[str, Any] | None = None) -> Config:
    """Validate a plain mapping (as read from YAML) plus dotted overrides into a Config."""
    tree = _deep_copy(data or {})
    if not isinstance(tree, dict):
        raise ConfigError(f"config: must be a mapping with sections {sorted(SECTIONS)}, got {data!r}")
    for key, value in (overrides or {}).items():
        _set_dotted(tree, key, value)
    _apply_fidelity(tree, overrides or {})
    unknown = sorted(map(str, set(tree) - set(SECTIONS) - set(LIST_SECTIONS)))
    if unknown:
        hint = did_you_mean(unknown[0], SECTIONS | LIST_SECTIONS)
        raise ConfigError(f"{unknown[0]}: unknown section{hint}; allowed sections are "
                          f"{sorted(SECTIONS | LIST_SECTIONS)}")
    sections = {name: _build(cls, tree.get(name), name) for name, cls in SECTIONS.items()}
    lists = {name: _build_list(name, tree[name]) for name in LIST_SECTIONS if name in tree}
    cfg = Config(**sections, **lists)
    _check_design(cfg.design)
    _check_sim(cfg.sim)
    _check_design_problem(cfg)
    return cfg


def _apply_fidelity(tree: dict, overrides: Mapping[str, Any]) -> None:
    """Fill the sim fields the fidelity preset names, unless the config names them itself.

    An override of ``sim.fidelity`` chooses that preset's numbers over the file's: the file's
    preset fields are dropped unless the same overrides set them too. So
    ``--set sim.fidelity=reference`` on a file that lists ``sim.dt`` runs at the reference step,
    and ``--set sim.fidelity=mbd-fast --set sim.dt=0.0008`` runs mbd-fast at 0.8 ms.
    """
    sim = tree.get("sim")
    if sim is None:
        sim = tree["sim"] = {}
    if not isinstance(sim, dict):
        return  # _build names the problem
    name = sim.get("fidelity", DEFAULT_FIDELITY)
    if not isinstance(name, str) or name not in FIDELITY_PRESETS:
        raise ConfigError(f"sim.fidelity = {name!r}: must be one of {list(FIDELITY_PRESETS)} (cheapest first)")
    preset = FIDELITY_PRESETS[name]
    if "sim.fidelity" in overrides:
        for key in preset:
            if f"sim.{key}" not in overrides:
                sim.pop(key, None)
    for key, value in preset.items():
        sim.setdefault(key, value)


def real_field(key: Any, where: str) -> dataclasses.Field:
    """The declaration of a real-valued ``design.*`` or ``scene.*`` field, or a ConfigError naming ``where``."""
    sec, _, name = str(key).partition(".")
    cls = {"design": Design, "scene": Scene}.get(sec)
    known = {f.name: f for f in fields(cls)} if cls else {}
    f = known.get(name)
    if f is None or f.type not in (float, "float"):
        choices = real_keys()
        hint = did_you_mean(key, choices) or f" (aero-env schema lists the {len(choices)} of them)"
        raise ConfigError(f"{where} = {key!r}: not a real-valued design or scene field{hint}")
    return f


def real_keys() -> list[str]:
    """Every real-valued ``design.*`` and ``scene.*`` key (what tunable, context and tolerance entries name)."""
    return [f"design.{f.name}" for f in fields(Design) if f.type in (float, "float")] + \
        [f"scene.{f.name}" for f in fields(Scene) if f.type in (float, "float")]


def _build_list(section: str, data: Any) -> tuple:
    """Validate one list section (tunable, context or tolerance) entry by entry."""
    cls = LIST_SECTIONS[section]
    if not isinstance(data, (list, tuple)):
        raise ConfigError(f"{section}: must be a list of mappings with keys {[f.name for f in fields(cls)]}, "
                          f"got {data!r}")
    items, seen = [], set()
    for i, entry in enumerate(data):
        where = f"{section}[{i}]"
        if not isinstance(entry, Mapping):
            raise ConfigError(f"{where}: must be a mapping with keys {[f.name for f in fields(cls)]}, got {entry!r}")
        allowed = {f.name for f in fields(cls)}
        extra = sorted(map(str, set(entry) - allowed))
        if extra:
            raise _unknown_key(f"{where}.{extra[0]}", extra[0], allowed)
        if "name" not in entry:
            raise ConfigError(f"{where}.name: missing; the dotted key of the field, e.g. design.m3")
        f = real_field(entry["name"], f"{where}.name")
        name = str(entry["name"])
        if name in seen:
            raise ConfigError(f"{where}.name = {name!r}: listed twice in {section}")
        seen.add(name)
        items.append(_ITEM_BUILDERS[section](entry, where, name, f))
    return tuple(items)


def _bound(entry: Mapping, key: str, where: str, name: str, f: dataclasses.Field) -> float:
    """``entry[key]`` checked against the range of the field it sets."""
    return _check_value(f"{where}.{key} (a value of {name})", f, entry[key])


def _tunable(entry, where, name, f) -> Tunable:
    for key in ("low", "high"):
        if key not in entry:
            raise ConfigError(f"{where}.{key}: missing; the value of {name} at action {'-1' if key == 'low' else '+1'}")
    relative_to = entry.get("relative_to")
    if relative_to is not None:
        real_field(relative_to, f"{where}.relative_to")
        low, high = (_factor(entry[key], f"{where}.{key}", relative_to) for key in ("low", "high"))
    else:
        low, high = _bound(entry, "low", where, name, f), _bound(entry, "high", where, name, f)
    if not low < high:
        if relative_to is not None:
            raise ConfigError(f"{where}.high = {high!r}: must exceed {where}.low = {low!r} (both multiples of "
                              f"{relative_to}'s value)")
        raise ConfigError(f"{where}.high = {high!r}: must exceed {where}.low = {low!r}, allowed ({low}, "
                          f"{f.metadata['hi']}]")
    scale = entry.get("scale", "linear")
    if scale not in ("linear", "log"):
        raise ConfigError(f"{where}.scale = {scale!r}: must be one of ['linear', 'log']")
    if scale == "log" and low <= 0:
        raise ConfigError(f"{where}.low = {low!r}: a log scale needs low > 0, allowed (0, {high})")
    linked = entry.get("linked", ()) or ()
    if isinstance(linked, str) or not isinstance(linked, (list, tuple)):
        raise ConfigError(f"{where}.linked = {linked!r}: must be a list of dotted keys, e.g. [design.mu_k]")
    for j, key in enumerate(linked):
        real_field(key, f"{where}.linked[{j}]")
        if key == name:
            raise ConfigError(f"{where}.linked[{j}] = {key!r}: a field cannot be linked to itself")
    return Tunable(name, low, high, scale, tuple(str(k) for k in linked),
                   None if relative_to is None else str(relative_to))


def _factor(value: Any, where: str, relative_to: str) -> float:
    """A bound of a relative range: a plain finite number, a multiple of ``relative_to``'s value."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ConfigError(f"{where} = {value!r}: with relative_to {relative_to}, low and high are plain numbers "
                          f"(multiples of {relative_to}'s value in the config, e.g. 0.75 and 1.35), not quantities")
    return float(value)


def _context(entry, where, name, f) -> ContextRange:
    has_low, has_high = entry.get("low") is not None, entry.get("high") is not None
    if has_low != has_high:
        raise ConfigError(f"{where}: give both low and high (drawn uniformly at reset), or neither (fixed)")
    if not has_low:
        return ContextRange(name)
    low, high = _bound(entry, "low", where, name, f), _bound(entry, "high", where, name, f)
    if low > high:
        raise ConfigError(f"{where}.high = {high!r}: must be at least {where}.low = {low!r}")
    return ContextRange(name, low, high)


def _tolerance(entry, where, name, f) -> Tolerance:
    out = {}
    unit = f.metadata["unit"]
    for key, hi, u in (("relative", 0.5, "-"), ("absolute", math.inf, unit)):
        v, _ = _with_unit(f"{where}.{key} (a tolerance of {name})", entry.get(key, 0.0), u)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not (0.0 <= v <= hi) or not math.isfinite(v):
            in_unit = f" {u}" if u != "-" else ""
            raise ConfigError(f"{where}.{key} = {v!r}: must be a finite number in [0, {hi}]{in_unit}")
        out[key] = float(v)
    return Tolerance(name, **out)


_ITEM_BUILDERS = {"tunable": _tunable, "context": _context, "tolerance": _tolerance}


def _check_design_problem(cfg: Config) -> None:
    """A field is either chosen (tunable) or given (context), and links only fields that are neither."""
    tuned = {t.name for t in cfg.tunable}
    for i, c in enumerate(cfg.context):
        if c.name in tuned:
            raise ConfigError(f"context[{i}].name = {c.name!r}: also tunable; the designer either chooses a value "
                              f"or is given it, not both")
    given = {c.name for c in cfg.context}
    leader: dict[str, str] = {}
    for i, t in enumerate(cfg.tunable):
        for key in t.linked:
            if key in tuned or key in given:
                raise ConfigError(f"tunable[{i}].linked: {key!r} is itself tunable or context; it cannot also follow "
                                  f"{t.name}")
            if key in leader:
                raise ConfigError(f"tunable[{i}].linked: {key!r} already follows {leader[key]}; a field can follow "
                                  f"one tunable only")
            leader[key] = t.name


def _check_sim(s: Sim) -> None:
    step = s.dt * s.substeps  # the pymunk runner samples contact once per runner step (reduced finds events exactly)
    if s.model == "mbd" and s.contact_hold < 5 * step:
        raise ConfigError(f"sim.contact_hold = {s.contact_hold!r}: must span at least 5 runner steps of sim.dt = "
                          f"{s.dt!r} x sim.substeps = {s.substeps} to tell a detach from a bounce, allowed "
                          f"[{5 * step:.3g}, 1.0] s")


def _deep_copy(x: Any) -> Any:
    if isinstance(x, Mapping):
        return {k: _deep_copy(v) for k, v in x.items()}
    return x


def read_yaml(path: str | Path, what: str) -> Any:
    """The YAML document in ``path`` (None for an empty file); a one-line ConfigError naming ``what`` (e.g.
    "config file") and the file when it is missing, a folder, unreadable or not YAML (with the line)."""
    p = Path(path)
    if p.is_dir():
        raise ConfigError(f"{what} {str(p)!r}: is a folder; give a YAML file (e.g. configs/paper.yaml)")
    if not p.is_file():
        raise ConfigError(f"{what} {str(p)!r}: not found")
    try:
        text = p.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise ConfigError(f"{what} {str(p)!r}: not a text file; expected YAML") from None
    except OSError as exc:
        raise ConfigError(f"{what} {str(p)!r}: cannot be read ({exc.strerror or exc})") from None
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f", line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        why = getattr(exc, "problem", None) or str(exc)
        context, start = getattr(exc, "context", None), getattr(exc, "context_mark", None)
        if context:
            since = f" from line {start.line + 1}" if start is not None and mark is not None and \
                start.line != mark.line else ""
            why = f"{why} ({context}{since})"
        raise ConfigError(f"{what} {str(p)!r}{where}: not valid YAML: {' '.join(str(why).split())}") from None


def load_config(path: str | Path | None = None, overrides: Mapping[str, Any] | None = None) -> Config:
    """Load a YAML scene config (or the defaults when ``path`` is None) and apply overrides."""
    if path is None:
        return from_dict({}, overrides)
    data = read_yaml(path, "config file")
    if data is None:
        raise ConfigError(f"config file {str(path)!r}: empty; a config is a YAML mapping of sections "
                          f"({', '.join([*SECTIONS, *LIST_SECTIONS])}), e.g. configs/paper.yaml")
    if not isinstance(data, Mapping):
        raise ConfigError(f"config file {str(path)!r}: must be a YAML mapping of sections "
                          f"({', '.join([*SECTIONS, *LIST_SECTIONS])}), got a {type(data).__name__}")
    return from_dict(data, overrides)


def parse_override(text: str) -> tuple[str, Any]:
    """Parse a CLI ``KEY=VALUE`` override; the value is read as YAML (numbers, true/false, words)."""
    if "=" not in text:
        raise ConfigError(f"--set {text!r}: expected KEY=VALUE, e.g. design.m2=0.008")
    key, raw = text.split("=", 1)
    try:
        value = yaml.safe_load(raw)
    except yaml.YAMLError:
        value = raw
    return key.strip(), value


def schema_rows() -> list[tuple[str, str, str, str, str]]:
    """(key, default, unit, allowed, meaning) for every field, for docs and ``aero-env schema``."""
    rows = []

    def walk(cls, prefix):
        for f in fields(cls):
            sub = f.default_factory if f.default_factory is not dataclasses.MISSING else None
            if sub is not None and dataclasses.is_dataclass(sub):
                walk(sub, f"{prefix}.{f.name}")
                continue
            m = f.metadata
            allowed = ("one of " + ", ".join(m["choices"])) if m["choices"] else (
                "true/false" if f.type in (bool, "bool") else _range_text(m))
            rows.append((f"{prefix}.{f.name}", repr(f.default), m["unit"], allowed, m["doc"]))

    for name, cls in SECTIONS.items():
        walk(cls, name)
    for name, cls in LIST_SECTIONS.items():
        for f in fields(cls):
            m = f.metadata
            default = "required" if f.name == "name" or (cls is Tunable and f.name in ("low", "high")) else repr(f.default)
            rows.append((f"{name}[].{f.name}", default, m["unit"], "", m["doc"]))
    return rows
