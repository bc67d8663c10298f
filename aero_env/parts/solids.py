"""The toy as 3D solids: every part :mod:`aero_env.parts.build` describes, placed for the whole row, in metres.

The world is 2D; the toy is not. This module stands each part up as a closed solid (a manifold3d ``Manifold``:
closed by construction, booleans by the library) so that :mod:`aero_env.parts.clearance` can check that the parts
clear each other through the swing, and ``aero-env sheet`` can write the row as ``assembly.glb``.

**Axes.** x along the row and y up, as in the 2D world; z across the row (x cross y), so every skewer runs
along z and a positive turn about +z is the world's positive angle: a frame turns from rest towards its end stop.

**Groups**, each in its own coordinates:

- ``frame-<i>``: origin on the frame's axis, local z the axis, local x along the frame line towards the
  counterbalance (the world's frame-local coordinates). Posed at the angle theta1 by :func:`frame_pose`.
- ``robot``: the torso (origin at the axle, the torso down -y) and the arm (origin at the axle, +x to the
  hook), each posed by the world's torso and arm angles (:func:`robot_poses`).
- ``stand``: the crossbeams, the skewers (axes and stoppers), the uprights and the base, in world coordinates.

**The layout** (:class:`aero_env.parts.layout.RowLayout`) says where each frame's parts sit across the row.
:func:`identical_layout` is the kit as drawn: every frame's side cards ``RAIL_SPAN`` apart in the same two planes.
:func:`aero_env.parts.layout.nested_layout` is the layout that clears: narrow and wide frames alternating, the
cards a neighbour's part crosses cut away. Every skewer spans the stand, from crossbeam to crossbeam, and the
crossbeams stand clear of every frame's parts.

Not yet stood up (issue 49, items 4-5): the handrail's glue tabs (they lie flat on their own side card's inner
face), the arm's card stops and the spring strip, and the robot's joint as built: here the arm is the plate the
model swings, across the plane and centred on it, which the torso plate (in the plane, centred on it) crosses
at the axle; the robot is drawn, not checked against itself.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import manifold3d as m3
import numpy as np

from . import build
from .build import stopper_offsets
from .kit import CROSSBEAM_LAYERS, UPRIGHT_WIDTH, axle_length, crossbeam_band, skewer_lengths
from .layout import FrameKind, RowLayout, counterbalance_stacks, crossbeam_gap, kit_layout
from .layout import identical_layout  # noqa: F401 (the kit as first drawn, for callers of this module)

MM = 1e-3  # m per mm: the kit's crossbeam lay-out is in mm
SEGMENTS = 32  # a round part's sides: a skewer, a coin (the polygon sits inside the circle)
BASE_THICKNESS = 5.0e-3  # m: the board the uprights stand on (the kit says "any stiff board")


@dataclass(frozen=True)
class Part3D:
    """One closed solid of the toy: ``name`` says which part, ``solid`` is in its group's coordinates (m)."""
    name: str
    solid: m3.Manifold


# ---- primitives -------------------------------------------------------------------------------------------------
def box(x0, x1, y0, y1, z0, z1) -> m3.Manifold:
    """An axis-aligned box between the given planes."""
    return m3.Manifold.cube((x1 - x0, y1 - y0, z1 - z0)).translate((x0, y0, z0))


def rod(x, y, r, z0, z1) -> m3.Manifold:
    """A round rod (a skewer, a coin stack) of radius ``r`` along z from z0 to z1, its axis at (x, y)."""
    return m3.Manifold.cylinder(z1 - z0, r, circular_segments=SEGMENTS).translate((x, y, z0))


def slab(start, end, thickness, z0, z1) -> m3.Manifold:
    """A flat strip of card ``thickness`` thick whose middle line runs from ``start`` to ``end`` in the xy plane,
    from z0 to z1 across: a handrail face."""
    (ax, ay), (bx, by) = start, end
    length = math.hypot(bx - ax, by - ay)
    plate = box(0.0, length, -thickness / 2, thickness / 2, z0, z1)
    return plate.rotate((0.0, 0.0, math.degrees(math.atan2(by - ay, bx - ax)))).translate((ax, ay, 0.0))


def pose_matrix(x, y, angle) -> np.ndarray:
    """A 4x4 transform: a turn of ``angle`` (rad) about z, then a shift to (x, y, 0)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0, x], [s, c, 0.0, y], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]])


def placed(solid: m3.Manifold, matrix: np.ndarray) -> m3.Manifold:
    """``solid`` moved by a 4x4 rigid transform."""
    return solid.transform(np.ascontiguousarray(matrix[:3, :4]))


# ---- a swing frame ------------------------------------------------------------------------------------------------
def frame_parts(d, kind: FrameKind) -> list[Part3D]:
    """A swing frame's parts in its own coordinates: the two side cards (``kind.outline``, hole included), the
    handrail L between them, the counterbalance's coin seats, coins and clay (:func:`counterbalance_parts`)."""
    t = kind.layers * build.CARD_THICKNESS
    span = kind.span
    card = kind.outline.scale((MM, MM))  # the outline's mm to m
    out = []
    for side, z0 in (("near", span / 2), ("far", -span / 2 - t)):
        out.append(Part3D(f"side card ({side})", m3.Manifold.extrude(card, t).translate((0.0, 0.0, z0))))
    faces = build.notch_faces(d.Lb, math.radians(d.notch_angle_deg), math.radians(d.notch_opening_deg),
                              math.radians(d.rest_angle_deg), d.notch_back_face, d.notch_front_face,
                              d.handrail_thickness / 2 + d.hook_radius)
    rail = m3.Manifold.batch_boolean([slab(a, b, d.handrail_thickness, -span / 2, span / 2) for a, b in faces],
                                     m3.OpType.Add)
    out.append(Part3D("handrail", rail))
    out += counterbalance_parts(d, span / 2 + t if kind.coins_outside else span / 2, kind.coins_outside)
    return out


def counterbalance_parts(d, face: float, outside: bool) -> list[Part3D]:
    """The counterbalance on (La, h), stacked as :func:`aero_env.parts.layout.counterbalance_stacks` says: each
    stack on its coin seat (a square of card ``COIN_RIM`` wider than a coin), the seat on the face of a side card
    ``face`` off the frame's middle plane (the near card on +z), on its outer side (``outside``) or its inner one;
    the clay on the far stack's coins."""
    load = build.counterbalance_load(d.m3)
    clay = float(load["clay"])
    r, c, t = build.YEN_COIN_RADIUS, build.YEN_COIN_THICKNESS, build.CARD_THICKNESS
    s = r + build.COIN_RIM  # the seat's half side
    clay_height = clay / build.CLAY_DENSITY / (math.pi * r**2)
    out = []
    for where, n, with_clay in counterbalance_stacks(d):
        card_side = 1.0 if where == " (near)" else -1.0
        way = card_side if outside else -card_side  # from the card's face towards the stack
        z_seat = card_side * face
        z0 = z_seat + way * t
        out.append(Part3D(f"coin seat{where}",
                          box(d.La - s, d.La + s, d.h - s, d.h + s, min(z_seat, z0), max(z_seat, z0))))
        z1 = z0 + way * n * c
        if n:
            out.append(Part3D(f"counterbalance coins{where} ({n})", rod(d.La, d.h, r, min(z0, z1), max(z0, z1))))
        if with_clay and clay > 0:
            z2 = z1 + way * clay_height
            out.append(Part3D(f"counterbalance clay ({clay * 1e3:.1f} g)", rod(d.La, d.h, r, min(z1, z2), max(z1, z2))))
    return out


def frame_pose(axis, theta) -> np.ndarray:
    """Frame group to world at the frame angle ``theta`` (rad, the world's theta1)."""
    return pose_matrix(axis[0], axis[1], theta)


# ---- the stand ----------------------------------------------------------------------------------------------------
def stand_parts(cfg, layout: RowLayout) -> list[Part3D]:
    """The stand in world coordinates: two crossbeams (the kit's band, along the incline), every axis and stopper
    skewer from crossbeam to crossbeam, the two uprights under the first and last axis on each side, the base."""
    d, s = cfg.design, cfg.scene
    band = crossbeam_band(cfg)
    t_beam = CROSSBEAM_LAYERS * build.CARD_THICKNESS
    inner = crossbeam_gap(cfg, layout) / 2  # the crossbeams clear every frame's parts
    z_out = inner + t_beam
    beam_length = ((s.frames - 1) * band["step"] + band["u_hi"] - band["u_lo"]) * MM
    out = []
    for side, z0, z1 in (("near", inner, z_out), ("far", -z_out, -inner)):
        beam = box(band["u_lo"] * MM, band["u_lo"] * MM + beam_length, band["v_lo"] * MM, band["v_hi"] * MM, z0, z1)
        out.append(Part3D(f"crossbeam ({side})", beam.rotate((0.0, 0.0, math.degrees(band["beta"])))))
    rest, stop = stopper_offsets(d)
    half = skewer_lengths(cfg, layout)["axis"] / 2
    r = build.SKEWER_D / 2
    for i in range(s.frames):
        ax, ay = i * s.pitch, i * s.rise
        out.append(Part3D(f"axis skewer {i}", rod(ax, ay, r, -half, half)))
        for what, (ox, oy) in (("rest", rest), ("end", stop)):
            out.append(Part3D(f"{what} stopper skewer {i}", rod(ax + ox, ay + oy, r, -half, half)))
    floor = -s.floor_drop  # the base's top, under frame 0's axis
    w = UPRIGHT_WIDTH * MM
    for i in (0, s.frames - 1):
        ax, ay = i * s.pitch, i * s.rise
        for side, z0, z1 in (("near", z_out, z_out + t_beam), ("far", -z_out - t_beam, -z_out)):
            out.append(Part3D(f"upright {i} ({side})", box(ax - w / 2, ax + w / 2, floor, ay, z0, z1)))
    x_lo, x_hi = -max(d.La, d.Lb) - 10 * MM, (s.frames - 1) * s.pitch + max(d.La, d.Lb) + 10 * MM
    out.append(Part3D("base", box(x_lo, x_hi, floor - BASE_THICKNESS, floor, -z_out - t_beam - 10 * MM,
                                  z_out + t_beam + 10 * MM)))
    return out


# ---- the robot ----------------------------------------------------------------------------------------------------
def torso_parts(d) -> list[Part3D]:
    """The torso in its own coordinates (axle at the origin, the torso down -y): the card plate in the plane,
    centred on it, its axle hole; the coins flat on its near face, flush with its bottom; the axle skewer."""
    torso_length = float(d.torso_length)
    plate = build.torso_plate(d, torso_length)
    w, t = float(plate["width"]), float(plate["layers"]) * build.CARD_THICKNESS
    axle = axle_length(d)  # through the torso and across the arm's width, centred on the plane
    card = box(-w / 2, w / 2, -torso_length, build.END, -t / 2, t / 2) - rod(0.0, 0.0, build.HOLE_D / 2, -t, t)
    coins = build.coin_stack(d)["coins"] * build.YEN_COIN_THICKNESS
    return [Part3D("torso", card),
            Part3D("torso coins", rod(0.0, -float(d.coin_offset), d.coin_radius, t / 2, t / 2 + coins)),
            Part3D("axle skewer", rod(0.0, 0.0, build.SKEWER_D / 2, -axle / 2, axle / 2))]


def arm_parts(d) -> list[Part3D]:
    """The arm in its own coordinates (axle at the origin, +x to the hook): the plate the model swings, across
    the plane (its width along z), and the hook's lip folded 90 deg at the tip."""
    a = build.arm_plate(d)
    w, t = float(a["width"]), float(a["layers"]) * build.CARD_THICKNESS
    plate = box(-build.END, d.arm_length, -t / 2, t / 2, -w / 2, w / 2)
    lip = box(d.arm_length - t / 2, d.arm_length + t / 2, -build.HOOK_LIP, t / 2, -w / 2, w / 2)
    return [Part3D("arm", plate + lip)]


def robot_poses(axle, torso_angle, arm_angle) -> tuple[np.ndarray, np.ndarray]:
    """(torso, arm) group to world, from the world's pose (:meth:`aero_env.physics.world.World.pose`)."""
    return pose_matrix(axle[0], axle[1], torso_angle), pose_matrix(axle[0], axle[1], arm_angle)


# ---- the whole row ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Assembly:
    """The row's solids: ``frames[i]`` in frame i's coordinates, its axis at ``axes[i]``; the stand in the
    world's; the torso's and the arm's parts in their own. ``rest`` and ``stop`` are the frames' angles (rad)."""
    layout: RowLayout
    axes: tuple[tuple[float, float], ...]
    rest: float
    stop: float
    frames: tuple[tuple[Part3D, ...], ...]
    stand: tuple[Part3D, ...]
    torso: tuple[Part3D, ...]
    arm: tuple[Part3D, ...]


def assembly(cfg, layout: RowLayout | None = None) -> Assembly:
    """Every part of ``cfg``'s row as a closed solid, in ``layout`` (default: the kit's,
    :func:`aero_env.parts.layout.kit_layout`: the nested layout where it is found, else every frame alike)."""
    d, s = cfg.design, cfg.scene
    layout = layout or kit_layout(cfg)
    if len(layout.kinds) != s.frames:
        raise ValueError(f"layout {layout.name!r}: {len(layout.kinds)} frames for {s.frames}")
    frames = tuple(tuple(frame_parts(d, kind)) for kind in layout.kinds)
    return Assembly(layout, tuple((i * s.pitch, i * s.rise) for i in range(s.frames)),
                    math.radians(d.rest_angle_deg), math.radians(d.stop_angle_deg), frames,
                    tuple(stand_parts(cfg, layout)), tuple(torso_parts(d)), tuple(arm_parts(d)))
