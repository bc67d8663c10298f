"""The paper's analytical models beside the pymunk world: one swing compared (Figs. 40, 42, 43),
the paper's own descriptions of that swing checked point by point, and where each model holds
(Fig. 29)."""

from .domain_map import MAP_MASSES, MAP_RATIOS, available_energy, domain_map, moment_ratio, plot_domain_map
from .mbd import FALLBACK_ANGLE_DEG, FLIGHT_ENTERED, MbdSwing, mbd_swing
from .three_models import analytical, compare, drag_effect, plot_comparison, sign_changes_deg

__all__ = ["MAP_MASSES", "MAP_RATIOS", "available_energy", "domain_map", "moment_ratio", "plot_domain_map",
           "FALLBACK_ANGLE_DEG", "FLIGHT_ENTERED", "MbdSwing", "analytical", "compare", "drag_effect", "mbd_swing",
           "plot_comparison", "sign_changes_deg"]
