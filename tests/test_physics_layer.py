"""The Python layer around pymunk: the friction switch's one-read slip against pymunk's own point
calls, the run's inputs that let bare ``space.step`` calls replay it, and ``bench overhead``."""

from __future__ import annotations

import json
import math

import pytest

from aero_env.bench.designs import draw_designs
from aero_env.bench.overhead import replay
from aero_env.cli import main as cli_main
from aero_env.physics import World
from aero_env.physics.run import simulate

from .conftest import PAPER


def pymunk_slip(law, frames) -> float:
    """The slip asked of pymunk point by point (the switch's reading before it read each body once):
    the fastest sliding of the tip's contact point over any face of the touched frame it touches."""
    frame = frames[next(iter(law.touching))]
    body, faces, rail_radius = frame.body, frame.faces, frame.rail_radius
    centre = law.arm.local_to_world(law.tip_local)
    local = body.world_to_local(centre)
    found, nearest = [], None
    for ax, ay, ux, uy, length in faces:
        along = min(max((local.x - ax) * ux + (local.y - ay) * uy, 0.0), length)
        qx, qy = ax + along * ux, ay + along * uy
        gap = math.hypot(local.x - qx, local.y - qy)
        item = (gap, qx, qy, ux, uy)
        if nearest is None or gap < nearest[0]:
            nearest = item
        if gap <= law.hook.radius + rail_radius + law.contact_band:
            found.append(item)
    fastest = 0.0
    for gap, qx, qy, ux, uy in found or [nearest]:
        f = rail_radius / gap if gap > 0.0 else 0.0
        point = body.local_to_world((qx + (local.x - qx) * f, qy + (local.y - qy) * f))
        tangent = (ux * math.cos(body.angle) - uy * math.sin(body.angle),
                   ux * math.sin(body.angle) + uy * math.cos(body.angle))
        v = law.arm.velocity_at_world_point(point) - body.velocity_at_world_point(point)
        fastest = max(fastest, abs(v.dot(tangent)))
    return fastest


@pytest.mark.parametrize("dt,views", [(0.0005, "struct"), (0.001, "struct"), (0.0005, "getters")])
def test_the_switch_reads_the_slip_pymunk_would_give_bit_for_bit(paper_cfg, dt, views, monkeypatch):
    # At every step of the row with the hook on a handrail, the switch's slip is pymunk's to the last
    # bit: with the threshold at pymunk's slip it does not slide, one ulp below it it does. The compiled test
    # reads the bodies' C structs; "getters": as it would with a pymunk whose struct it does not know.
    from aero_env.physics import body_state

    if views == "getters":
        monkeypatch.setattr(body_state, "MEMORY_LAYOUT_HOLDS", False)
    cfg = paper_cfg.replace({"sim.dt": dt, "scene.frames": 3})
    world = World(cfg)
    law = world.contact.law
    threshold, checked = law.slip_speed, 0
    while world.t < 1.6 and world.active < 2:
        if law.touching:
            slip = pymunk_slip(law, world.frames)
            law.slip_speed = slip
            assert not law.slides(), world.steps
            if slip > 0.0:
                law.slip_speed = math.nextafter(slip, 0.0)
                assert law.slides(), world.steps
            law.slip_speed = threshold
            checked += 1
        world.step()
        if world.active == 0 and world.contact.touches(1):
            world.set_active(1)  # a bare world's live window stays put: move it as the runner would
    assert checked > 0.8 / cfg.sim.dt  # most of two swings


def test_the_runners_c_reads_are_pymunks_properties_bit_for_bit(paper_cfg):
    # body_state reads Chipmunk's getters without pymunk's Vec2d properties, and a frame's seat is computed from
    # a read state: at every step of two swings (the frames turning, the robot in flight and caught) each value
    # is the one pymunk's own properties and local_to_world give, to the last bit
    from aero_env.physics import body_state

    cfg = paper_cfg.replace({"scene.frames": 3})
    world = World(cfg)
    bodies = [*(f.body for f in world.frames), *world.robot.bodies]
    seats_checked = 0
    while world.t < 1.6:
        for b in bodies:
            x, y, a, vx, vy, w = body_state.read(b)
            assert (x, y, a, vx, vy, w) == (*b.position, b.angle, *b.velocity, b.angular_velocity)
            assert body_state.pose(body_state.handle(b)) == (x, y, a)
            assert body_state.memory_state(body_state.memory(b)) == (x, y, a, vx, vy, w)  # what compiled code reads
        for f in world.frames:
            seat = f.hook_seat_world()
            assert f.hook_seat_at(body_state.read(f.body)) == (seat.x, seat.y)
            seats_checked += f.body.angle != f.rest_angle
        world.step()
        if world.active == 0 and world.contact.touches(1):
            world.set_active(1)
    assert seats_checked > 1000  # turned frames, not only the rest angle's


def test_python_hypot_is_math_hypot_bit_for_bit():
    # the compiled switch's hypot (CPython's algorithm; numba's math.hypot is the C library's, which differs), over
    # the normal range and the edge cases; pairs that are both subnormal can differ in the last bit (slip_kernel's
    # docstring), and only these two are checked there
    import random

    from aero_env.physics.slip_kernel import python_hypot

    rng = random.Random(5)
    pairs = [(0.0, 0.0), (-0.0, 3.0), (3.0, -4.0), (1e-310, 3e-311), (5e-324, 0.0), (1e308, 1e308), (math.inf, math.nan),
             (math.nan, 1.0), (-math.inf, 0.0), (1.0, 1.0 + 2.0 ** -52)]
    pairs += [(rng.gauss(0.0, 1.0) * 10.0 ** rng.randint(-9, 4), rng.gauss(0.0, 1.0) * 10.0 ** rng.randint(-9, 4))
              for _ in range(50_000)]
    for a, b in pairs:
        got, want = python_hypot(a, b), math.hypot(a, b)
        assert got == want or (math.isnan(got) and math.isnan(want)), (a, b, got.hex(), want.hex())


def test_the_world_steps_through_pymunks_wrapper_only_after_it_changed_the_space(paper_cfg, monkeypatch):
    # World.step calls cpSpaceStep itself, except on the step after frames joined or left the space, which goes
    # through pymunk's Space.step: its check of the added bodies is then done, and nothing waits in pymunk's
    # bookkeeping after any step
    import aero_env.physics.world as world_module

    cfg = paper_cfg.replace({"scene.frames": 3})
    world = World(cfg)
    calls = {"wrapper": 0, "c": 0}
    wrapper, c_step = world.space.step, world_module._cp_space_step

    def through_wrapper(dt):
        calls["wrapper"] += 1
        wrapper(dt)

    def direct(cs, dt):
        calls["c"] += 1
        c_step(cs, dt)

    world.space.step = through_wrapper
    monkeypatch.setattr(world_module, "_cp_space_step", direct)
    run = simulate(cfg, world=world)
    moves = sum(what == "active" for _, what, _ in world.inputs)
    assert run.outcome == "completed" and moves == 2
    assert calls == {"wrapper": 1 + moves, "c": world.steps - 1 - moves}
    space = world.space
    assert not (space._bodies_to_check or space._add_later or space._remove_later or space._post_step_callbacks)


def _sampled_both_ways(cfg):
    """Run ``cfg`` with every check's sample taken by the compiled read and by sample_python; their reprs
    (every bit, signed zeros and NaN included) and how many checks compared."""
    world = World(cfg)
    compiled, pairs = world.sample, []

    def both():
        a = compiled()
        pairs.append((repr(a), repr(world.sample_python())))
        return a

    world.sample = both
    simulate(cfg, world=world)
    return world, pairs


def test_the_compiled_check_reads_what_sample_python_reads_bit_for_bit(paper_cfg):
    # energy, fastest body, theta2, hook, health and the live frames' states, at every check of runs that catch,
    # let go, fly, graze and fall, with a moving live window, air drag and two substeps a runner step
    cfgs = [paper_cfg.replace({"scene.frames": 4}), paper_cfg.replace({"scene.frames": 3, "sim.fidelity": "mbd-fine"}),
            paper_cfg.replace({"scene.frames": 2, "scene.effects.drag": True}),
            *draw_designs(paper_cfg.replace({"scene.frames": 3}), 6, seed=8).configs]
    checks = 0
    for cfg in cfgs:
        world, pairs = _sampled_both_ways(cfg)
        assert world._check is not None
        for a, b in pairs:
            assert a == b
        checks += len(pairs)
    assert checks > 2000


def test_a_pinned_hook_world_is_read_by_sample_python(paper_cfg):
    # the kernel covers the jointed robot on a hook contact; the two-link scene takes the Python read
    world = World(paper_cfg.replace({"scene.effects.hook": "pin", "scene.effects.friction": "static"}))
    assert world._check is None and world.sample() == world.sample_python()


def test_the_compiled_parts_run_as_plain_python_with_the_same_result(paper_cfg, tmp_path):
    # NUMBA_DISABLE_JIT=1 runs the kernels' own code as Python (how to step through them): the same run, bit for bit
    import subprocess
    import sys

    script = ("import json, sys\nfrom aero_env.config import load_config\nfrom aero_env.physics.run import simulate\n"
              "r = simulate(load_config(sys.argv[1]).replace({'scene.frames': 3}), trace=True).to_json_dict()\n"
              "r.pop('wall_time'); print(json.dumps(r, sort_keys=True, default=lambda v: v.tolist()))")
    outs = []
    for disable in ("0", "1"):
        env = {**__import__("os").environ, "NUMBA_DISABLE_JIT": disable}
        done = subprocess.run([sys.executable, "-c", script, str(PAPER)], capture_output=True, text=True, env=env,
                              timeout=600)
        assert done.returncode == 0, done.stderr
        outs.append(json.loads(done.stdout))
    assert outs[0] == outs[1] and outs[0]["outcome"] == "completed"


def test_bare_steps_with_the_runs_inputs_end_where_the_run_ends(paper_cfg):
    # bench overhead's baseline: pymunk alone, given the run's window moves and friction changes,
    # ends in the run's final state bit for bit (the energy reads every live body)
    cfgs = [paper_cfg.replace({"scene.frames": 3}), paper_cfg.replace({"scene.frames": 3, "sim.fidelity": "mbd-fine"}),
            paper_cfg.replace({"scene.frames": 2, "scene.effects.drag": True}),
            *draw_designs(paper_cfg.replace({"scene.frames": 3}), 4, seed=3).configs]
    for cfg in cfgs:
        world = World(cfg)
        run = simulate(cfg, world=world)
        kinds = {what for _, what, _ in world.inputs}
        assert kinds <= {"active", "friction"} and world.steps * cfg.sim.dt * cfg.sim.substeps == pytest.approx(
            run.sim_time)
        for c_step in (False, True):  # through pymunk's Space.step, or Chipmunk's cpSpaceStep as the runner calls it
            bare = World(cfg)
            replay(bare, world.inputs, world.steps, c_step)
            assert bare.energy() == run.energy["final"], (run.outcome, c_step)


def test_bench_overhead_reports_the_python_layer_against_a_replayed_bare_run(capsys):
    assert cli_main(["bench", "overhead", str(PAPER), "--set", "scene.frames=2", "--repeats", "1", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["bare_replays_run"] is True and report["replayed_inputs"] > 0
    assert [r["name"] for r in report["rows"]] == ["bare", "c_step", "loop", "loop+friction", "full"]
    walls = {r["name"]: r["wall"] for r in report["rows"]}
    assert report["python_layer_ratio"] == report["rows"][-1]["ratio_vs_bare"] == walls["full"] / walls["bare"] > 0.0
    assert report["layer_ratio_vs_c_step"] == walls["full"] / walls["c_step"]
    assert report["pymunk_steps"] == round(report["sim_time"] / 0.0005)
    assert cli_main(["bench", "overhead", str(PAPER), "--set", "sim.fidelity=reduced", "--repeats", "1"]) == 2
