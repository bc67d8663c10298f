"""Design agents (black-box tuning and RL) live here; they arrive with the agents issue.

They use the environment and the physics; nothing in ``aero_env`` imports this package.
"""
