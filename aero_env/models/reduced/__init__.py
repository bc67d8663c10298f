"""The ``reduced`` fidelity: a whole run along the row without pymunk, compiled, many designs at once.

The cheapest rung of the fidelity ladder. Each design is one row of constants (:mod:`.params`) and
its run is scalar code (:mod:`.run`: a fixed-step loop whose phases are branches) compiled by numba
and spread over the cores, one design per task. ``simulate_batch`` / ``simulate_values`` run a batch
(``BatchResult``), ``simulate_reduced`` one config as the pymunk runner's ``SimResult``,
``swing_trace`` samples a first swing. The compiled code is cached on disk (``kernel_cache_dir()``);
a new source or numba version compiles once, ``compile_kernels()`` does it on purpose and says how
long it took. With ``NUMBA_DISABLE_JIT=1`` the same code runs as plain Python (slow: for checks).

The files are the phases: :mod:`.hooked_dynamics` (the hooked swing's equations), :mod:`.hooked_phase`
(a hooked step and its events), :mod:`.impacts` (the stops), :mod:`.next_card` (the next frame's card in
a hooked hook's way), :mod:`.transitions` (release, slide, swing start, end), :mod:`.flight` (flight),
:mod:`.notch` (the hook meeting the next notch's cards), :mod:`.catch` (the landing and the catch impulse),
:mod:`.hook_impulse` (the impulse at the hook where it meets a card face), :mod:`.run` (the loop and the
kernels), :mod:`.outputs` (results and sentences).

**The swing (hooked).** Coordinates: the frame angle theta1, the arm's direction phi_a (hook ->
axle) and the torso's phi_t (axle -> torso centre), the hook in the handrail's notch. This is the
paper's two-link model (frame + robot jointed at the handrail, A25/A30) with the robot link taken
*from its parts*, as the pymunk robot is built (``arm_length``, ``arm_mass``: the kit's laminated plates (aero_env/parts),
``torso_com``, and the torso inertia :mod:`aero_env.physics.engine_params` derives so the robot,
fully bent, has the paper's I2 about its centre). While the arm sits on its stop (alpha_max: the
robot's weight holds the leaf spring there on a working design, the prototype all swing long) the
chain *is* the two-link model with Lc = the hook-to-centre distance of the parts at alpha_max
(44.4 mm for the prototype, not the design's 30 mm) and I2 = m2/3·(Ld²+Ld·Lc+Lc²) (the design's
Lc, Ld): the stop is a constraint, and ``swing_trace`` reproduces ``two_link.simulate`` with that
Lc. When the spring lifts the arm off its stop, alpha (interior angle at the axle; spring torque
k·(alpha - alpha_min), or k/2·da² for ``spring_law: stiffening``) is a third coordinate; the arm's
stops are inelastic.

Why the parts and not the design's Lc: the pymunk robot is the parts, only the parts give the arm
its own motion, and that motion is a failure a quarter of random designs meet: a stiff spring snaps
the arm off its stop at the catch and the hook pops out. Either rigid link alone misses the
prototype's first swing by ~2 deg RMS: what both lack is the friction of the hook's round tip
(``hook_radius``) turning in the notch, mu·r·(sum of the faces' normal forces), which slows pymunk's
swing by ~2 deg at 0.3 s. The torque saturates at high friction because the wedge then carries the
load by friction: the normal forces come from F = sum_i N_i·(n_i + mu·sig·perp(n_i)).

**Slip and detach.** The joint force F (handrail on robot) follows from the accelerations every
step. The notch is two card faces (``design.notch_*``, as :mod:`aero_env.physics.swing_frame` builds
them, turning with the frame); with the hook in the corner it holds while F lies in the union of the
faces' static friction cones (atan(mu_s) about each inward normal). F leaving it on one face's side,
pressing on that face, starts a slide along the face with kinetic friction (a fourth coordinate s;
-mu_k·N·sign(s') with N solved together with the accelerations). Past the face's end (length minus the
hook/card clearance) the hook rolls on over the card's rounded end, a circle of the clearance about the
card's end with s its arc length, and lets go where N turns tensile, as pymunk's hook does 2-5 ms after
the face's end; a slide that stops on the face sticks again, one that reaches the corner stops there in
an inelastic impact (:func:`.hook_impulse.corner_stop`: the momenta of the frame angle and the robot's two
angles carry through it). A hook pulled off one face inside the notch crosses to the corner unless the
corner's cones would let it go too. F pulling on both faces lets go at once. The tip turning in the corner faster
than ``sim.slip_speed`` holds with mu_k, as the pymunk world's static/kinetic switch reads the slip at the
contact; on one face it rolls (its contact point at rest on the card: mu_s, no turning friction, the hook
creeping r·turn along the face), and the static friction that holds it there, acting at the tip's surface,
turns the robot about the tip's centre as a slide's kinetic friction does. The frame's end stop with the hook
out on one face is an impact with that face (:func:`.impacts.end_stop_on_face`). On a steep row the next
frame's card can be in a hooked hook's way (:mod:`.next_card`). Impacts (:mod:`.impacts`) are inelastic,
and every stop is one-sided in them: a frame on its rest stop that the arm's impact throws forward leaves the
stop. A stop that holds a joint at rest
lets go only once the pull on it exceeds the joint's dry friction (the skewer's ``pivot_friction``, the
axle's ``axle_friction``): the pymunk world's capped motors hold a joint still there, where the
regularised friction (``DRY_FRICTION_RATE``) would let it creep off the stop.

**Flight and catch** (:mod:`.flight`, :mod:`.notch`, :mod:`.catch`): a ballistic centre of mass, the arm snapping
about it (a step in which it reaches its stop is split there), and the hook's landing in the next
notch. Past the notch's mouth the hook meets a card's flat side or the top of its rounded end (one that
meets a card's end on its far side, or passes beside it, grazes); the landing is an inelastic impact
along the card's normal there (on the rounded end, the normal of the end's circle at the hook), with the
card's friction along it: the hook stops on the card where the impulse that stops it lies in the static
cone, and slides on with kinetic friction otherwise (the impulse from the robot's and the frame's
inertia at the hook, the arm as it is at that instant; a stop, the frame's rest stop or the arm's,
holds only where the impulse presses its body into it, so a landing may lift the arm off its stop). The hooked motion then decides, as the
pymunk runner does: a touch held ``sim.contact_hold`` that came within ``sim.catch_seat`` of the seat is
a catch; a hook that leaves the card before that grazes, and the flight goes on, the frame it touched
swinging with what the touch gave it. A hook that reaches the seat's depth beside the corner (that the
faces would guide in) is set on the seat with an inelastic catch impulse at once.

**Outcomes and times** follow :mod:`aero_env.physics.run` (its thresholds are restated in the
phases): ``t_detach`` is when the hook leaves the handrail, ``t_catch`` when it enters the next
mouth, ``sim_time`` when the runner would stop (a decided miss: the centre of mass reaching the
floor, in closed form, or the flight timeout; the end of the step in which the last frame carried
the robot through its lowest point; a catch that did not hold: its detach + ``contact_hold``).
A catch is a traversal only once its frame has carried the robot through its lowest point
(``physics.swing_rules.CARRIED_THETA1_DEG``, read at the end of each hooked step and at the detach, ``t_carried``);
a caught robot that lets go before that ends the run (``missed_catch``: a catch that did not hold).
Stalls the runner only ends by its timeouts are ended early (``STALL_WINDOW``) and reported at the
runner's time.

**Numerics.** RK4 with a fixed step (``STEP``; ``sim.dt`` when the config's ``sim.model`` is
``reduced``), events at step ends, release and catch times interpolated, float64 throughout. A slide
within reach of the corner or of its face's end is stepped at ``CAP_STEP`` and split where it meets them.
Deterministic: a design gives bit-identical results alone or in any batch, on any number of threads.

Not modelled: air drag (<0.1% in the paper and in the pymunk world), contact bounces and the hook
riding a face's outside (a hook that lands on a card's end from outside and stays there, as pymunk's
sometimes does, grazes here), the hook rolling in the corner, the slip of a turning tip setting the sense
of a face's friction, the ``hook: pin`` scene (that is
``aero_env.models.two_link``). Agreement with the pymunk world and speed: ``aero-env bench accuracy``,
``aero-env bench throughput``, docs/fidelity.md.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from ...config import Config, ConfigError, check_values, real_field
from ...jit_cache import cache_dir, caching_in

_KERNEL_FILES = ("jit.py", "layout.py", "constants.py", "hooked_dynamics.py", "hook_impulse.py", "transitions.py",
                 "impacts.py",
                 "next_card.py", "hooked_phase.py", "catch.py", "notch.py", "flight.py", "run.py")


def kernel_cache_dir(source: Path | None = None) -> Path:
    """Where the compiled kernels are cached: one folder per version of their source, numba and Python
    (:func:`aero_env.jit_cache.cache_dir`). ``source``: the folder whose kernel files make the key (default:
    this package's)."""
    return cache_dir(Path(__file__).parent if source is None else Path(source), _KERNEL_FILES)


def _import_kernels():
    with caching_in(kernel_cache_dir()):
        from . import run
    return run


_run = _import_kernels()

from .constants import STEP  # noqa: E402
from .layout import O, OUTCOMES, W  # noqa: E402
from .outputs import BatchResult, batch_result, sim_result  # noqa: E402
from .params import (DESIGN_KEYS, SCENE_KEYS, check_raw, check_scene, param_table,  # noqa: E402
                     raw_from_configs, set_friction_law, step_for)

# the dotted config keys the model reads (simulate_values takes these)
READ_KEYS = frozenset([f"design.{k}" for k in DESIGN_KEYS] + [f"scene.{k}" for k in SCENE_KEYS])

__all__ = ["BatchResult", "OUTCOMES", "READ_KEYS", "STEP", "compile_kernels", "kernel_cache_dir", "simulate_batch",
           "simulate_designs", "simulate_reduced", "simulate_values", "swing_trace"]


_loaded = False


def compile_kernels() -> float:
    """Compile (or load from the disk cache) the kernels; returns the seconds it took. A later call costs ~0.
    Every entry point calls it before it starts its clock, so no run's wall time holds the one-time cost."""
    global _loaded
    t0 = time.perf_counter()
    if not _loaded:
        folder = kernel_cache_dir()
        if not any(folder.rglob("run.run_batch-*.nbi")):  # numba's index of the batch kernel: not compiled yet
            print(f"aero-env: compiling the reduced model for this version of its source, numba and Python (once: "
                  f"half a minute to a few minutes on a busy machine; later runs load it from {folder})",
                  file=sys.stderr, flush=True)
        table = param_table(raw_from_configs([Config()]), STEP)
        frames = 2  # any row length: the kernels take it as an argument
        for kernel in (_run.run_one, _run.run_batch):
            kernel(table, frames, STEP, False, np.empty((1, len(O))), np.empty((1, len(W), frames)))
        _run.trace_first_swing(table[0], frames, STEP, True, 1, np.empty((2, 6)))
        _loaded = True
    return time.perf_counter() - t0


def _run_table(table: np.ndarray, frames: int, dt: float, detail: bool) -> BatchResult:
    compile_kernels()
    wall0 = time.perf_counter()
    n = table.shape[0]
    out = np.empty((n, len(O)))
    sw = np.empty((n, len(W), frames))
    kernel = _run.run_one if n == 1 else _run.run_batch
    kernel(table, frames, float(dt), detail, out, sw)
    return batch_result(table, out, sw, frames, time.perf_counter() - wall0, detail)


def simulate_batch(cfgs: Sequence[Config], dt: float | None = None) -> BatchResult:
    """Run every config of ``cfgs`` (all with the same ``scene.frames``) through the reduced model at once.

    ``dt``: the integration step; default: ``sim.dt`` of the configs when their ``sim.model`` is ``reduced``,
    else :data:`STEP`."""
    frames = check_scene(cfgs)
    if dt is None:
        steps = {step_for(c) for c in cfgs}
        if len(steps) != 1:
            raise ConfigError(f"simulate_batch: the configs ask for different steps {sorted(steps)}: one batch "
                              f"runs one step (pass dt=)")
        dt = steps.pop()
    return _run_table(param_table(raw_from_configs(cfgs), dt), frames, dt, detail=False)


def simulate_values(base: Config, values: Mapping[str, np.ndarray], dt: float | None = None) -> BatchResult:
    """The fast path: the designs ``base`` with ``values`` (dotted ``design.*``/``scene.*`` keys -> arrays of
    one length, or scalars) set, without building a Config per design. Each value is checked against its
    field's range and the design's cross-checks by the config's own checks, vectorised
    (:func:`aero_env.config.check_values`, :func:`aero_env.config.check_design`): ``Config.with_values``' words,
    the design's index after the key."""
    check_scene([base])
    raw = raw_from_configs([base])
    n = None
    for key, v in values.items():
        a = np.atleast_1d(np.asarray(v, dtype=float))
        if a.ndim != 1 or (n is not None and len(a) not in (1, n)):
            raise ConfigError(f"simulate_values: {key} has shape {np.shape(v)}: every value must be a scalar or a "
                              f"1-D array of one common length")
        if len(a) > 1:
            n = len(a) if n is None else n
    n = n or 1
    raw = {k: np.broadcast_to(v, (n,)).copy() for k, v in raw.items()}
    for key, v in values.items():
        f = real_field(key, "key")
        if key not in raw:
            raise ConfigError(f"simulate_values: {key} is not read by the reduced model (it reads "
                              f"{', '.join(sorted(k for k in raw if '.' in k))})")
        a = np.broadcast_to(np.asarray(v, dtype=float), (n,)).copy()
        check_values(key, f, a)
        raw[key] = a
    set_friction_law(raw, base.scene.effects.friction)
    check_raw(raw)
    dt = step_for(base) if dt is None else dt
    return _run_table(param_table(raw, dt), base.scene.frames, dt, detail=False)


def simulate_designs(base: Config, designs: Sequence[Mapping[str, float]], dt: float | None = None) -> BatchResult:
    """:func:`simulate_values` of one dict per design (every dict with the same dotted keys, all in
    :data:`READ_KEYS`): the designs ``base`` with each dict's values set, in order."""
    if not designs:
        raise ConfigError("simulate_designs: no designs; pass at least one dict of values")
    keys = list(designs[0])
    if not keys and all(not d for d in designs):  # nothing set: the base design, once per entry
        return simulate_batch([base] * len(designs), dt)
    for i, d in enumerate(designs):
        if d.keys() != designs[0].keys():
            raise ConfigError(f"simulate_designs: designs[{i}] sets {sorted(d)}, designs[0] sets {sorted(keys)}; "
                              f"every design must set the same keys")
    return simulate_values(base, {k: np.array([d[k] for d in designs], dtype=float) for k in keys}, dt)


def simulate_reduced(cfg: Config, dt: float | None = None):
    """One config through the reduced model, as a :class:`~aero_env.results.SimResult` (the pymunk
    runner's fields; the energy is the model's: frames, robot parts and spring; health is all zeros)."""
    compile_kernels()
    wall0 = time.perf_counter()
    frames = check_scene([cfg])
    dt = step_for(cfg) if dt is None else dt
    res = _run_table(param_table(raw_from_configs([cfg]), dt), frames, dt, detail=True)
    res.wall_time = time.perf_counter() - wall0
    return sim_result(res, 0, cfg.sim.fidelity)


def swing_trace(cfg: Config, t_end: float, dt: float | None = None, detach: bool = False) -> dict:
    """The first swing of ``cfg`` sampled every step, for comparisons: t, theta1, theta2, alpha (rad), omega1
    (rad/s), energy (J, the hooked frame and robot). With ``detach=False`` the hook holds whatever the force
    (it never slips or lets go), so the swing runs on to ``t_end`` against the stops."""
    frames = check_scene([cfg])
    dt = step_for(cfg) if dt is None else dt
    table = param_table(raw_from_configs([cfg]), dt)
    n_steps = int(np.ceil(t_end / dt - 1e-9))
    samples = np.empty((n_steps + 1, 6))
    compile_kernels()
    filled = _run.trace_first_swing(table[0], frames, float(dt), not detach, n_steps, samples)
    names = ("t", "theta1", "theta2", "alpha", "omega1", "energy")
    return {k: samples[:filled, i].copy() for i, k in enumerate(names)}
