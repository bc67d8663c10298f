"""How the reduced model's functions are compiled by numba, in one place.

* ``cache=True``: compiled once per version of the source, into :func:`~aero_env.models.reduced.kernel_cache_dir`.
* ``error_model="numpy"``: a division by zero gives inf or NaN, as numpy does, with no check before each division.
* No ``fastmath``: the compiled code must give the bits of the same code run as plain Python
  (``NUMBA_DISABLE_JIT=1``), so the compiler may not reorder or contract arithmetic.
* ``kernel``, for the physics (every function that neither allocates nor returns an array), also leaves out
  numba's reference counting (``_nrt=False``). With it, each call that passes the design's arrays ``p`` and ``x``
  counts references to them with atomic instructions, which ``perf`` showed to be a quarter of a batch's time.
  The arrays belong to the run (:mod:`.run`, compiled with reference counting as ``allocating``) for as long as
  any kernel holds them, so nothing is freed early; a kernel that tried to allocate would fail to compile.
"""

from __future__ import annotations

from numba import njit

allocating = njit(cache=True, error_model="numpy")
kernel = njit(cache=True, error_model="numpy", _nrt=False)
