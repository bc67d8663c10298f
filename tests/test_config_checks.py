"""One source of truth for a value's checks: the reduced model's fast path (simulate_values) refuses a bad value
with the config's own words (Config.with_values), the design's index after the key."""

import numpy as np
import pytest

from aero_env.config import Config, ConfigError
from aero_env.models.reduced import simulate_values

BASE = Config().replace({"scene.frames": 2})
GOOD = BASE.design

BAD = [  # one field's range, then every cross-check between fields
    {"design.m2": 0.5},
    {"design.m3": -0.001},
    {"design.Lb": 0.0},
    {"design.spring_k": float("nan")},
    {"scene.pitch": 5.0},
    {"design.mu_k": 0.6, "design.mu_s": 0.3},
    {"design.alpha_max_deg": GOOD.alpha_min_deg},
    {"design.stop_angle_deg": GOOD.rest_angle_deg + 5.0},
    {"design.dT": 1.0},
    {"design.Ld": 0.001},
    {"design.arm_mass": GOOD.m2},
]


def _message(call) -> str:
    with pytest.raises(ConfigError) as exc:
        call()
    return str(exc.value)


@pytest.mark.parametrize("bad", BAD, ids=lambda b: ",".join(b))
def test_the_fast_path_refuses_a_bad_value_in_with_values_words(bad):
    single = _message(lambda: BASE.with_values(bad))
    good = {k: getattr(GOOD if k.startswith("design.") else BASE.scene, k.split(".")[1]) for k in bad}
    arrays = {k: np.array([good[k], v]) for k, v in bad.items()}  # the second design is the bad one
    fast = _message(lambda: simulate_values(BASE, arrays))
    assert "\n" not in fast and "[1] = " in fast, fast
    assert fast.replace("[1] = ", " = ", 1) == single
