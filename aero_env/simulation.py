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
"""

from __future__ import annotations

from .config import Config, ConfigError, pymunk_fidelities
from .physics import SimResult
from .physics import simulate as simulate_mbd


def simulate(cfg: Config, trace: bool = False, poses_every: float | None = None) -> SimResult:
    """Simulate ``cfg`` with the engine its fidelity names. Deterministic for a config."""
    if cfg.sim.model == "reduced":
        if trace or poses_every:
            raise ConfigError(f"sim.fidelity = {cfg.sim.fidelity!r} (sim.model = reduced) has no trace or animation: "
                              f"it never builds the machine's bodies; use a pymunk fidelity "
                              f"({pymunk_fidelities()}) for --trace, --plot, --gif or rendering")
        from .models.reduced import simulate_reduced

        return simulate_reduced(cfg)
    return simulate_mbd(cfg, trace=trace, poses_every=poses_every)
