"""The paper's analytical models of the swing: quasi-static single link (Eq. 1) and the
dynamic two-link double pendulum (Eqs. A25, A30). Pure numpy/scipy on SI designs; they
share the inertias (:mod:`aero_env.inertia`) and drag law (:mod:`aero_env.drag_law`) with the
pymunk world but never touch it.
"""

from . import quasi_static, two_link

__all__ = ["quasi_static", "two_link"]
