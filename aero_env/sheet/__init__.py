"""A maker's sheet: a design's parts in mm and g, its card pair and spring, its robustness
(``aero_env.sheet.command``), and a 1:1 cutting template (``aero_env.sheet.template``)."""
