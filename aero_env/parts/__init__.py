"""The toy's parts: one description of each, read by the physics and by the kit.

``build``: how each part is made of card (and coins and clay), and its mass, centre and inertia.
``kit``: the same parts as pieces a maker cuts (the template's shapes, ``parts.json``).
``card`` and ``spring_strip``: the paper's card, and the leaf-spring strip a stiffness asks for.
"""
