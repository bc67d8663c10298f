"""Robustness to hand-building: does a design still traverse its row when it is cut from card?

``aero-env robustness CONFIG`` draws N builds of the config's design within a hand-made toy's
tolerances, simulates each at the config's fidelity and reports the share that complete the row
(with a 95 % Wilson interval), the outcome counts, and which parameters matter most.

Modules: :mod:`.tolerances` (the default table, the ``--tolerances`` file, how a draw builds a
value), :mod:`.draws` (the seeded draws, building and simulating in order), :mod:`.study` (one
study: nominal, single changes, draws), :mod:`.report` (the Wilson interval, single changes,
effects, JSON and table), :mod:`.command` (the subcommand).
"""

from .study import Study, assess
from .tolerances import DEFAULT_TOLERANCES, Tol, load_tolerances, parse_tolerances

__all__ = ["DEFAULT_TOLERANCES", "Study", "Tol", "assess", "load_tolerances", "parse_tolerances"]
