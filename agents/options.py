"""Checks for the agents' command-line options: errors name the option, the value and the range."""

from __future__ import annotations

from typing import Any, Iterable

from aero_env.config import ConfigError

# The fixed choices of the agents' options, here so that the command line can offer them without
# importing Optuna or torch.
SAMPLERS = ("cmaes", "tpe", "random")
ALGOS = ("ppo", "sac")


def check_choice(option: str, value: Any, choices: Iterable[str]) -> None:
    choices = tuple(choices)
    if value not in choices:
        raise ConfigError(f"--{option} {value!r}: must be one of {', '.join(choices)}")


def check_ints(settings: Any, ranges: Iterable[tuple[str, int, int]]) -> None:
    """Each named field of ``settings`` is an integer (not a bool) in its closed range [lo, hi]."""
    for name, lo, hi in ranges:
        v = getattr(settings, name)
        if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
            raise ConfigError(f"--{name.replace('_', '-')} {v!r}: must be a whole number in [{lo}, {hi}]")
