"""Benchmarks: what accuracy costs in time (``aero-env bench``).

| command                         | measures                                                                 |
|---------------------------------|--------------------------------------------------------------------------|
| ``bench accuracy CONFIG``       | every fidelity on the same designs: wall time, real-time factor, speed-up |
|                                 | over ``reference``, outcome agreement and detach errors against it        |
| ``bench effects CONFIG``        | each effect's cost (drag, static/kinetic switching, live frames) and      |
|                                 | whether it changes any outcome                                           |
| ``bench overhead CONFIG``       | the Python layer's cost over bare ``space.step`` calls, piece by piece    |
| ``bench throughput [CONFIG]``   | designs per second at every fidelity: the single env, the vector env (one |
|                                 | reduced call; a process pool), and 1 and 2 Gymnasium vector workers       |

Times are medians over repeats, and every ratio compares runs measured in the same call, so a
noisy machine shifts both sides alike. Designs are drawn from the environment's action space
with a fixed seed: the same command measures the same designs. Nothing here is imported by the
physics, the models or the environments.
"""
