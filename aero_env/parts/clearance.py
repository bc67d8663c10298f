"""Do the toy's parts clear each other? The static sweep over :mod:`aero_env.parts.solids`.

Each frame is turned from its rest angle to its end stop in steps; at every step each of its parts is
intersected (manifold3d) with every part of each other frame, that frame at rest and at its end stop, and with
every part of the stand. Two parts *meet* where their common volume passes ``TOUCH`` (1 mm³): parts that touch
(a frame on its stopper skewer) share a face or a polygon's corner, no volume. A cheap bound comes first: a
part is only intersected with a part whose box it can reach (its farthest corner from the axis, swept round).

A meeting is a :class:`Contact`: the frame, the part, the other part and its pose, the first angle at which
they meet and the largest common volume over the sweep.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .solids import Assembly, frame_pose, placed

TOUCH = 1e-9  # m³: 1 mm³, the most two parts may share and still clear (issue 49)
STEP_DEG = 1.0  # the sweep's step in theta1


@dataclass(frozen=True)
class Contact:
    """Frame ``frame``'s ``part`` meets ``other`` (``where``: "frame 4 at rest", "frame 4 at its end stop",
    "the stand") from theta1 = ``angle_deg`` on; ``volume`` (m³) is the most they share over the sweep."""
    frame: int
    part: str
    other: str
    where: str
    angle_deg: float
    volume: float

    def line(self) -> str:
        other = f"the stand's {self.other}" if self.where == "the stand" else f"the {self.other} of {self.where}"
        return (f"frame {self.frame}'s {self.part} meets {other} from theta1 = {self.angle_deg:.1f} deg "
                f"({self.volume * 1e9:.0f} mm³ shared at most)")


def _box(solid) -> tuple[np.ndarray, np.ndarray]:
    b = solid.bounding_box()  # (xmin, ymin, zmin, xmax, ymax, zmax)
    return np.array(b[:3]), np.array(b[3:])


def _reach(solid) -> tuple[float, float, float]:
    """(farthest xy distance from the group's origin, zmin, zmax): the cylinder a part sweeps turning about z."""
    lo, hi = _box(solid)
    r = max(math.hypot(x, y) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]))
    return r, lo[2], hi[2]


def _overlaps(lo1, hi1, lo2, hi2) -> bool:
    return bool(np.all(lo1 < hi2) and np.all(lo2 < hi1))


def angles(asm: Assembly, step_deg: float = STEP_DEG) -> np.ndarray:
    """The sweep's frame angles (rad): rest to end stop, both ends included, steps of at most ``step_deg``."""
    n = max(1, math.ceil(math.degrees(asm.stop - asm.rest) / step_deg - 1e-9))
    return np.linspace(asm.rest, asm.stop, n + 1)


def obstacles(asm: Assembly, i: int) -> list[tuple[str, str, object]]:
    """What frame ``i`` must clear: (where, part name, solid in the world) for every other frame at rest and at its
    end stop, and every part of the stand."""
    out = []
    for j, parts in enumerate(asm.frames):
        if j == i:
            continue
        for where, theta in ((f"frame {j} at rest", asm.rest), (f"frame {j} at its end stop", asm.stop)):
            pose = frame_pose(asm.axes[j], theta)
            out += [(where, p.name, placed(p.solid, pose)) for p in parts]
    return out + [("the stand", p.name, p.solid) for p in asm.stand]


def static_sweep(asm: Assembly, step_deg: float = STEP_DEG, frames=None) -> list[Contact]:
    """Every meeting of a turning frame's part with another frame (at rest, at its end stop) or the stand, one
    :class:`Contact` per pair of parts; empty when the row clears. ``frames``: which frames turn (default all)."""
    thetas = angles(asm, step_deg)
    found: dict[tuple, Contact] = {}
    for i in (range(len(asm.frames)) if frames is None else frames):
        ax, ay = asm.axes[i]
        others = [(where, name, solid, *_box(solid)) for where, name, solid in obstacles(asm, i)]
        for part in asm.frames[i]:
            r, z0, z1 = _reach(part.solid)
            reach_lo, reach_hi = np.array([ax - r, ay - r, z0]), np.array([ax + r, ay + r, z1])
            near = [o for o in others if _overlaps(reach_lo, reach_hi, o[3], o[4])]
            if not near:
                continue
            for theta in thetas:
                moved = placed(part.solid, frame_pose((ax, ay), theta))
                lo, hi = _box(moved)
                for where, name, solid, olo, ohi in near:
                    if not _overlaps(lo, hi, olo, ohi):
                        continue
                    volume = (moved ^ solid).volume()
                    if volume <= TOUCH:
                        continue
                    key = (i, part.name, where, name)
                    seen = found.get(key)
                    found[key] = Contact(i, part.name, name, where, seen.angle_deg if seen else math.degrees(theta),
                                         max(volume, seen.volume if seen else 0.0))
    return sorted(found.values(), key=lambda c: (c.frame, c.angle_deg, c.part, c.where, c.other))


# ---- the kit's verdict, as a scene effect reads it ---------------------------------------------------------------
@dataclass(frozen=True)
class KitClearance:
    """Whether the kit drawn for a design (:func:`aero_env.parts.layout.kit_layout`) clears as its frames turn:
    ``first`` the earliest meeting (None: it clears), ``meetings`` how many pairs of parts meet (as ``turned``
    turns: the frames swept), ``refused`` why the nested layout does not serve the design ("" where the kit draws
    it)."""
    first: Contact | None
    meetings: int
    refused: str
    turned: tuple[int, ...] = ()

    @property
    def clears(self) -> bool:
        return self.first is None

    def reason(self) -> str:
        """The run's one line where the parts meet (``collides``): the first meeting, then how the kit is laid out."""
        if self.first is None:
            return "the kit's parts clear each other through every frame's swing"
        how = (f"every frame drawn alike, as the nested layout does not serve this design: {self.refused}"
               if self.refused else "in the nested layout")
        which = f" as frame {self.turned[0]} turns" if len(self.turned) == 1 else ""
        return (f"the kit's parts meet ({self.meetings} pairs{which}): {self.first.line()}; {how} "
                f"(scene.effects.clearance)")


KIT_CLEARANCE_KEPT = 256  # designs whose verdict a process keeps (a layout fit and a sweep take seconds each)
_VERDICTS: dict = {}


def kit_clearance(cfg) -> KitClearance:
    """The static sweep (:func:`static_sweep`, 1 deg steps) of the row as the kit draws it for ``cfg``: the nested
    layout where it is found, every frame turned; else every frame alike, where frame 1 turning is enough to say so
    (the whole row if frame 1 meets nothing). Kept per design and row (the same design on another seed or another
    draw of the scene's context costs nothing more); the first call for a design fits the layout (seconds) and
    sweeps the row (seconds)."""
    from .layout import nested_refusal
    from .solids import assembly

    key = _verdict_key(cfg)
    if key not in _VERDICTS:
        s = cfg.scene
        asm, refused = assembly(cfg), nested_refusal(cfg)
        turned = (min(1, s.frames - 1),) if refused else tuple(range(s.frames))
        contacts = static_sweep(asm, frames=turned)
        if not contacts and len(turned) < s.frames:
            turned = tuple(range(s.frames))
            contacts = static_sweep(asm, frames=turned)
        first = min(contacts, key=lambda c: (c.angle_deg, c.frame, c.part, c.where, c.other), default=None)
        if len(_VERDICTS) >= KIT_CLEARANCE_KEPT:
            _VERDICTS.pop(next(iter(_VERDICTS)))
        _VERDICTS[key] = KitClearance(first, len(contacts), refused, turned)
    return _VERDICTS[key]


def _verdict_key(cfg) -> tuple:
    s = cfg.scene
    return (cfg.design, s.frames, s.pitch, s.rise, s.floor_drop)


def forget_verdicts(cfg=None) -> None:
    """Drop the kept verdicts and layouts, or only ``cfg``'s (a benchmark times a design's first check, and keeps
    what the other designs cost)."""
    from . import layout

    if cfg is None:
        _VERDICTS.clear()
    else:
        _VERDICTS.pop(_verdict_key(cfg), None)
    layout.forget(cfg)
