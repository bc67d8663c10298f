"""Design agents: black-box tuning (:mod:`agents.tune`, Optuna) and RL (:mod:`agents.rl`, SB3).

Both score designs through the environment (:mod:`agents.design_eval`). They use ``aero_env``;
nothing in ``aero_env`` imports this package (its ``aero-env`` subcommands plug in through the
``aero_env.commands`` entry point, :mod:`agents.commands`).
"""
