"""Run a scene at its fidelity: the one entry point the CLI, the environment and the benchmarks use.

``sim.model`` (set by the ``sim.fidelity`` preset) picks the engine:

=========  ==========================================================================
``mbd``    the pymunk world (:func:`aero_env.physics.simulate`): frames, robot, spring,
           frictional hook contact; traces and animations
``reduced`` the two-link swing, ballistic flight and a geometric catch test
           (:mod:`aero_env.models.reduced`): no pymunk, compiled, many designs at once
=========  ==========================================================================

Both return a :class:`~aero_env.results.SimResult`. This module sits above the physics
and the models; neither of them imports it.

``scene.effects.clearance`` (off by default: a design's first check takes seconds) asks first whether the kit
drawn for the design clears as its frames turn (:func:`aero_env.parts.clearance.kit_clearance`: the static sweep
of the row as the kit lays it out). Where its parts meet, the run ends there, outcome ``collides``, nothing
simulated: a toy that cannot be built earns no traversal.
"""

from __future__ import annotations

import time

from .config import Config, ConfigError, pymunk_fidelities
from .physics import SimResult
from .physics import simulate as simulate_mbd
from .results import COLLIDES


def simulate(cfg: Config, trace: bool = False, poses_every: float | None = None) -> SimResult:
    """Simulate ``cfg`` with the engine its fidelity names. Deterministic for a config."""
    if cfg.scene.effects.clearance:
        collided = collides(cfg)
        if collided is not None:
            return collided
    if cfg.sim.model == "reduced":
        if trace or poses_every:
            raise ConfigError(f"sim.fidelity = {cfg.sim.fidelity!r} (sim.model = reduced) has no trace or animation: "
                              f"it never builds the machine's bodies; use a pymunk fidelity "
                              f"({pymunk_fidelities()}) for --trace, --plot, --gif or rendering")
        from .models.reduced import simulate_reduced

        return simulate_reduced(cfg)
    return simulate_mbd(cfg, trace=trace, poses_every=poses_every)


def collides(cfg: Config) -> SimResult | None:
    """The run of a design whose kit's parts meet (:func:`aero_env.parts.clearance.kit_clearance`): outcome
    ``collides``, no traversal, nothing simulated; None where the parts clear."""
    from .parts.clearance import kit_clearance  # manifold3d's import waits for the first check

    t0 = time.perf_counter()
    verdict = kit_clearance(cfg)
    if verdict.clears:
        return None
    return SimResult(traversals=0, frames=cfg.scene.frames, outcome=COLLIDES, reason=verdict.reason(), swings=[],
                     energy={}, sim_time=0.0, wall_time=time.perf_counter() - t0, fidelity=cfg.sim.fidelity)
