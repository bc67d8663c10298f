"""``aero-env calibrate``: fit the model's unknowns to a measured swing or to the paper's figures.

The pieces, each along one seam:

* :mod:`.swing_metrics`: one swing cut out of a traced run (catch to slip-off, time from the
  catch, degrees) and the numbers measured on it (duration, angles at catch and detach, the arm
  angle when the robot is lowest, ...).
* :mod:`.measured`: a measured swing as a video tool (Kinovea) exports it, read and checked.
* :mod:`.targets`: the paper's figures with tolerances (a YAML file), read and checked.
* :mod:`.scoring`: how far one simulated run is from a measurement or from the targets.
* :mod:`.fit`: the ``--fit KEY=LOW:HIGH`` boxes and the search over them (grid + golden
  section for one key, Optuna's CMA-ES for several).
* :mod:`.report`: the JSON object, the table, the calibrated config and the overlay plot.
* :mod:`.command`: the ``aero-env calibrate`` subcommand.

Nothing here is imported by the physics, the models or the environment.
"""
