"""``aero-env cycle``: does the robot settle into a limit cycle along a long row?

A run on a long row (100 frames by default) is cut at its catches: the state at each catch
(theta2, where the hook sits relative to the handrail's seat, the frame's and the robot's speed)
and what each swing ends in (its duration, the slip-off angle, the time between catches). Over
the last K catches each quantity gets its spread (mean, std, min, max) and a drift measure, so
"the cycle settles" is a measured claim.

The pieces, each along one seam:

* :mod:`.catches`: the per-catch quantities (name, unit, how to read one from the run's swings)
  and the window of the last K catches.
* :mod:`.spread`: the statistics of one series: spread, least-squares trend, halves, the verdict.
* :mod:`.report`: the run and the statistics as one JSON object, and the table.
* :mod:`.command`: the ``aero-env cycle`` subcommand and its checks.

Nothing here is imported by the physics, the models or the environment.
"""

from .catches import QUANTITIES, Quantity, catch_series, window_of
from .report import cycle_report, table
from .spread import SETTLE_FACTOR, series_spread

__all__ = ["QUANTITIES", "Quantity", "catch_series", "window_of", "cycle_report", "table", "SETTLE_FACTOR",
           "series_spread"]
