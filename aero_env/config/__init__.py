"""Scene configuration: schema, defaults, loading, overrides and validation.

A config has three sections, all in SI units with the paper's symbols:

* ``design``: what a designer of the toy changes (lengths, masses, spring, friction pair,
  hook geometry, angle limits).
* ``scene``: the row of swing frames, the start state, and the ``effects`` the scene
  switches on (each effect is a part the physics builder adds only when named).
* ``sim``: the fidelity (a named preset of model, time step, solver iterations and substeps),
  tolerances and time limits.

Four more sections describe the design problem that the Gymnasium environment poses
(the physics never reads them):

* ``tunable``: the action space, a list of ``{name, low, high, scale, linked}``; one action
  dimension per entry, mapped onto [low, high] (linear or log).
* ``context``: the observation, a list of ``{name, low, high}``; what a designer knows of the
  scene. Drawn uniformly at each reset; without low/high it stays at the config's value.
* ``tolerance``: a list of ``{name, relative, absolute}``; manufacturing error the designer does
  not know, drawn at each reset and applied to the built machine.
* ``env``: episode options (out-of-box actions, reward shaping, rendering).

A number may carry its unit, in a file or in ``--set``: ``m2: 7.71 g``, ``La: "48.3 mm"``,
``spring_k: 0.877 N*mm/rad``, ``rest_angle_deg: 55 deg`` (:mod:`aero_env.quantities` lists the
spellings); a plain number is in the key's own unit. The allowed ranges are those of a card toy
(masses up to 100 g, a spring up to 100 N·mm/rad, friction torques up to 10 N·mm, a row rising
at most 10 cm a frame), so that a plain number written in the usual smaller unit
(``design.m2=7.7`` for 7.7 g) is out of range and the error asks "did you mean 7.7 g?".

Every field is declared once, in :mod:`.sections` and :mod:`.design_problem`, with its default, unit,
allowed range and meaning; the schema table of docs/configuration.md is generated from the same
declarations (``aero-env schema``).
``load_config(path, overrides={"design.m2": 0.008})`` returns a validated, immutable
:class:`Config`. Bad input raises :class:`ConfigError` naming the key, the value and
the allowed range. A value in range that lies orders of magnitude from anything that can swing
(``design.m3=7.2e-3g``: 7.2 mg for 7.2 g; ``design.rest_angle_deg=0.96``: radians) runs, with one
:class:`UnitSlipWarning` line naming the likely slip (:mod:`.plausible`). A YAML mapping naming a key twice, in
a file or a ``--set`` value, is refused (PyYAML would keep the last silently).

The modules, each importing only those above it:

* ``validation``: :class:`ConfigError` and the check of one value (or an array of them) against its declaration.
* ``sections``: the ``design``, ``scene``, ``sim`` and ``env`` declarations, fidelity presets and the design's
  cross-checks (``check_design``, on one design or on arrays of them).
* ``design_problem``: the ``tunable``, ``context`` and ``tolerance`` entries and their checks.
* ``plausible``: the band of values per kind of quantity past which a value reads as a unit slip, and its warning.
* ``loading``: :class:`Config`, ``from_dict``, ``load_config``, overrides and the schema table.
"""

from .design_problem import (CARD_PAIRS, DEFAULT_CONTEXT, DEFAULT_TUNABLES, LIST_SECTIONS, TABLE3_CARD_PAIRS,
                             ContextRange, Tolerance, Tunable, linked_keys)
from .loading import Config, from_dict, load_config, parse_override, read_yaml, schema_rows
from .plausible import UnitSlipWarning, unit_slips, warn_unit_slips
from .sections import (DEFAULT_FIDELITY, FIDELITY_PRESETS, SECTIONS, Design, Effects, EnvOptions, Scene, Sim, check_design,
                       pymunk_fidelities, real_field, real_keys, spec)
from .validation import ConfigError, MissingExtra, check_value, check_values, did_you_mean, shown

__all__ = [
    "CARD_PAIRS", "Config", "ConfigError", "ContextRange", "DEFAULT_CONTEXT", "DEFAULT_FIDELITY", "DEFAULT_TUNABLES", "Design",
    "Effects", "EnvOptions", "FIDELITY_PRESETS", "LIST_SECTIONS", "MissingExtra", "SECTIONS", "Scene", "Sim", "TABLE3_CARD_PAIRS", "Tolerance",
    "Tunable",
    "check_design", "check_value", "check_values", "did_you_mean", "from_dict", "linked_keys", "load_config", "parse_override",
    "pymunk_fidelities", "read_yaml", "real_field", "real_keys",
    "schema_rows", "shown", "spec", "UnitSlipWarning", "unit_slips", "warn_unit_slips",
]
