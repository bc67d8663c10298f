"""The row's solids as a glTF binary (``assembly.glb``), the file a browser or a CAD viewer opens.

Metres, y up (glTF's own convention, and the world's). One node per group: ``frame-<i>`` (its origin on the
frame's axis, its local z the axis, posed at the frame's angle), ``robot`` (with ``robot/torso`` and
``robot/arm``, each at the world's pose) and ``stand``; each part a mesh node under its group, named
``<group>/<part>``. The meshes are :mod:`aero_env.parts.solids`' manifolds as triangles, closed.
"""

from __future__ import annotations

import re

import numpy as np
import trimesh

from .solids import Assembly, Part3D, frame_pose, robot_poses

COLOURS = {  # RGBA, 0-1: what each part is made of, so the model reads at a glance
    "card": (0.93, 0.91, 0.85, 1.0),
    "handrail": (0.55, 0.60, 0.70, 1.0),
    "coins": (0.75, 0.76, 0.78, 1.0),  # a one-yen coin is aluminium
    "clay": (0.80, 0.35, 0.25, 1.0),
    "skewer": (0.80, 0.65, 0.40, 1.0),
    "stand": (0.45, 0.38, 0.30, 1.0),
}


def _colour(name: str) -> tuple:
    for word, key in (("coins", "coins"), ("clay", "clay"), ("skewer", "skewer"), ("handrail", "handrail"),
                      ("crossbeam", "stand"), ("upright", "stand"), ("base", "stand")):
        if word in name:
            return COLOURS[key]
    return COLOURS["card"]


def slug(name: str) -> str:
    """A part's name as a node name: "side card (near)" -> "side-card-near"."""
    return re.sub(r"[^a-z0-9.]+", "-", name.lower()).strip("-")


def mesh(part: Part3D) -> trimesh.Trimesh:
    """A part's manifold as a trimesh mesh (double vertices, the manifold's triangles), coloured by its material."""
    m = part.solid.to_mesh()
    out = trimesh.Trimesh(np.asarray(m.vert_properties, dtype=np.float64)[:, :3], np.asarray(m.tri_verts),
                          process=False)
    out.visual = trimesh.visual.TextureVisuals(material=trimesh.visual.material.PBRMaterial(
        name=part.name, baseColorFactor=[int(255 * c) for c in _colour(part.name)], metallicFactor=0.0,
        roughnessFactor=0.9))
    return out


def scene(asm: Assembly, frame_angles=None, robot_pose=None) -> trimesh.Scene:
    """The row as a trimesh scene: frames at ``frame_angles`` (rad; default at rest), the robot at ``robot_pose``
    (the world's (axle, torso angle, arm angle); default: no robot)."""
    s = trimesh.Scene()
    base = s.graph.base_frame

    def group(name: str, matrix, parts, parent=base) -> None:
        s.graph.update(frame_from=parent, frame_to=name, matrix=matrix)
        for p in parts:
            node = f"{name}/{slug(p.name)}"
            s.add_geometry(mesh(p), geom_name=node, node_name=node, parent_node_name=name)

    angles = [asm.rest] * len(asm.frames) if frame_angles is None else frame_angles
    for i, (axis, parts) in enumerate(zip(asm.axes, asm.frames)):
        group(f"frame-{i}", frame_pose(axis, angles[i]), parts)
    if robot_pose is not None:
        torso, arm = robot_poses(*robot_pose)
        s.graph.update(frame_from=base, frame_to="robot", matrix=np.eye(4))
        group("robot/torso", torso, asm.torso, parent="robot")
        group("robot/arm", arm, asm.arm, parent="robot")
    group("stand", np.eye(4), asm.stand)
    return s


def glb(asm: Assembly, frame_angles=None, robot_pose=None) -> bytes:
    """:func:`scene` as the bytes of a .glb file."""
    return scene(asm, frame_angles, robot_pose).export(file_type="glb")
