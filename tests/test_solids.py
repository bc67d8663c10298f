"""The toy as 3D solids (aero_env/parts/solids.py), their clearance sweep (clearance.py) and ``assembly.glb``.

The .glb is read back here by hand (the binary glTF container, its JSON and its buffers), not through the library
that wrote it; the expected geometry comes from the config's numbers and plane geometry written out here."""

import json
import math
import struct

import numpy as np
import pytest

from aero_env.cli import main
from aero_env.config import load_config
from aero_env.parts.clearance import static_sweep
from aero_env.parts.solids import assembly, identical_layout

from .conftest import PAPER, per_test_under_mutmut
from .test_kit_readback import card_half_length, hollow_card

CARD_T = 0.4e-3  # m, the paper's card (Sec. 6)
GRAMMAGE = 0.310  # kg/m²
END = 4e-3  # m of card past the farthest mark (docs/make-your-own.md)


# ---- reading a .glb back by hand ----
def read_glb(data: bytes) -> tuple[dict, bytes]:
    magic, version, length = struct.unpack("<4sII", data[:12])
    assert magic == b"glTF" and version == 2 and length == len(data)
    json_len, kind = struct.unpack("<I4s", data[12:20])
    assert kind == b"JSON"
    gltf = json.loads(data[20:20 + json_len])
    at = 20 + json_len
    bin_len, kind = struct.unpack("<I4s", data[at:at + 8])
    assert kind == b"BIN\x00"
    return gltf, data[at + 8:at + 8 + bin_len]


def accessor(gltf: dict, binary: bytes, i: int) -> np.ndarray:
    a = gltf["accessors"][i]
    view = gltf["bufferViews"][a["bufferView"]]
    dtype = {5126: "<f4", 5125: "<u4", 5123: "<u2", 5121: "u1"}[a["componentType"]]
    width = {"SCALAR": 1, "VEC3": 3}[a["type"]]
    start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    return np.frombuffer(binary, dtype, a["count"] * width, start).reshape(a["count"], width)


def world_nodes(gltf: dict) -> dict[str, tuple[np.ndarray, dict]]:
    """Every node by name: (its transform to the world, the node)."""
    out = {}

    def walk(i: int, parent: np.ndarray) -> None:
        node = gltf["nodes"][i]
        local = np.array(node.get("matrix", np.eye(4).ravel()), dtype=float).reshape(4, 4).T  # column-major
        assert "rotation" not in node and "translation" not in node  # the writer uses matrices only
        out[node["name"]] = (parent @ local, node)
        for c in node.get("children", []):
            walk(c, parent @ local)

    for root in gltf["scenes"][gltf.get("scene", 0)]["nodes"]:
        walk(root, np.eye(4))
    return out


def mesh_of(gltf: dict, binary: bytes, node: dict) -> tuple[np.ndarray, np.ndarray]:
    (prim,) = gltf["meshes"][node["mesh"]]["primitives"]
    assert prim.get("mode", 4) == 4  # triangles
    return (accessor(gltf, binary, prim["attributes"]["POSITION"]).astype(float),
            accessor(gltf, binary, prim["indices"]).reshape(-1, 3))


def closed_volume(vertices: np.ndarray, triangles: np.ndarray) -> float:
    """The volume a triangle mesh encloses, after checking it is closed and consistently oriented: every directed
    edge appears once and its reverse once."""
    edges = {}
    for tri in triangles:
        for a, b in ((tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])):
            edges[(a, b)] = edges.get((a, b), 0) + 1
    assert all(n == 1 and edges.get((b, a)) == 1 for (a, b), n in edges.items()), "not a closed, oriented surface"
    v = vertices[triangles]
    return float(np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6.0)


def turn(angle: float, x: float, y: float) -> tuple[float, float]:
    c, s = math.cos(angle), math.sin(angle)
    return c * x - s * y, s * x + c * y


# ---- the model the sheet writes ----
@pytest.fixture(scope=per_test_under_mutmut)
def glb(tmp_path_factory):
    out = tmp_path_factory.mktemp("glb") / "assembly.glb"
    assert main(["sheet", str(PAPER), "--out", str(out), "--draws", "0"]) == 0
    return read_glb(out.read_bytes())


def test_the_glb_has_a_node_per_frame_on_its_axis_turning_about_local_z(glb, paper_cfg):
    """The prototype's row in its nested layout (docs/make-your-own.md): even frames narrow, their side cards' inner
    faces 30 mm apart, the counterbalance halved onto their inner faces; odd frames wide, their cards 1 mm outside the
    narrow cards' outer faces, the coins halved onto their outer faces (the odd coin near, the clay far), each stack
    on its coin seat."""
    gltf, binary = glb
    nodes = world_nodes(gltf)
    d, s = paper_cfg.design, paper_cfg.scene
    roots = {gltf["nodes"][i]["name"] for i in gltf["scenes"][0]["nodes"]}
    assert roots == {f"frame-{i}" for i in range(s.frames)} | {"robot", "stand"}
    rest = math.radians(d.rest_angle_deg)
    seats = 2 * 22e-3**2 * GRAMMAGE  # the counterbalance's two coin seats, part of m3
    coins = math.floor((d.m3 - seats) / 1e-3 + 1e-9)
    clay_g = round((d.m3 - seats - coins * 1e-3) * 1e3, 1)
    half = card_half_length(d) * 1e-3

    def extent(name):
        v, _ = mesh_of(gltf, binary, nodes[name][1])
        return v.min(axis=0), v.max(axis=0)

    narrow_t = extent("frame-0/side-card-near")[1][2] - extent("frame-0/side-card-near")[0][2]
    span = {0: 0.030, 1: 0.030 + 2 * narrow_t + 2 * 1e-3}  # m: each kind's cards' inner faces apart
    for i in range(s.frames):
        pose, _ = nodes[f"frame-{i}"]
        np.testing.assert_allclose(pose[:3, 3], [i * s.pitch, i * s.rise, 0.0], atol=1e-12)  # origin on the axis
        np.testing.assert_allclose(pose[:3, 2], [0.0, 0.0, 1.0], atol=1e-12)  # local z: the axis
        np.testing.assert_allclose(pose[:3, 0], [math.cos(rest), math.sin(rest), 0.0], atol=1e-12)  # at rest
        # the side cards run to the hollow card's ends (test_kit_readback works them out), either way along local x (the
        # narrow frames' cut away no further); their inner faces span apart, the near card on +z
        wide = i % 2
        for card, sign in (("near", 1), ("far", -1)):
            lo, hi = extent(f"frame-{i}/side-card-{card}")
            assert lo[0] >= -half - 1e-7 and hi[0] <= half + 1e-7
            if wide:  # the hollow card, whole
                assert lo[0] == pytest.approx(-half, abs=1e-7) and hi[0] == pytest.approx(half, abs=1e-7)
            inner = lo[2] if sign > 0 else -hi[2]
            assert inner == pytest.approx(span[wide] / 2, abs=1e-7), (i, card)
        # the counterbalance sits on (La, h); a positive turn is the world's: rest -> end stop. Two stacks, each on
        # its coin seat (one layer of card) on a card's face: the narrow frames' inner faces, the wide frames' outer
        # ones; the odd coin near, the rest and the clay far
        near_face = extent(f"frame-{i}/side-card-near")[1 if wide else 0][2]
        way = 1.0 if wide else -1.0  # from the near card's face towards its stack
        for card, sign, n in (("near", 1.0, (coins + 1) // 2), ("far", -1.0, coins // 2)):
            face, out = sign * near_face, sign * way
            seat_lo, seat_hi = extent(f"frame-{i}/coin-seat-{card}")
            assert sorted((seat_lo[2], seat_hi[2])) == pytest.approx(sorted((face, face + out * CARD_T)), abs=1e-7)
            assert (seat_hi - seat_lo)[:2] == pytest.approx([22e-3, 22e-3], abs=1e-9)  # a square 22 mm a side
            lo, hi = extent(f"frame-{i}/counterbalance-coins-{card}-{n}")
            start = face + out * CARD_T
            assert sorted((lo[2], hi[2])) == pytest.approx(sorted((start, start + out * n * 1.5e-3)), abs=1e-7)
            if card == "far":
                clay_lo, clay_hi = extent(f"frame-{i}/counterbalance-clay-{clay_g}-g")
                end = start + out * n * 1.5e-3
                assert (clay_hi[2] if out < 0 else clay_lo[2]) == pytest.approx(end, abs=1e-7)  # on the far coins
        centre = (lo + hi) / 2
        assert centre[:2] == pytest.approx([d.La, d.h], abs=1e-6)
        world = pose @ np.array([*centre[:2], 0.0, 1.0])
        expect = turn(rest, d.La, d.h)
        assert world[:2] == pytest.approx([i * s.pitch + expect[0], i * s.rise + expect[1]], abs=1e-6)


def test_every_mesh_in_the_glb_is_closed_and_weighs_what_its_part_does(glb, paper_cfg):
    gltf, binary = glb
    d = paper_cfg.design
    volumes = {}
    for name, (_, node) in world_nodes(gltf).items():
        if "mesh" in node:
            volumes[name] = closed_volume(*mesh_of(gltf, binary, node))
            assert volumes[name] > 0, name
    # a side card is m1/2 of the paper's card, the narrow frames' cut-away one too: its volume at the card's density
    # (grammage / thickness)
    for i in (0, 1):
        assert volumes[f"frame-{i}/side-card-near"] * GRAMMAGE / CARD_T == pytest.approx(d.m1 / 2, rel=2e-3)
    # six one-yen coins (7.2 g less the seats' 0.30 g), 20 mm across and 1.5 mm thick, as a 32-sided prism:
    # (32/2)·sin(2π/32)·r² per 1.5 mm, three on each card; a coin seat 22 mm a side, one layer of card
    prism = 16 * math.sin(2 * math.pi / 32)
    for i in (0, 1):
        coins = volumes[f"frame-{i}/counterbalance-coins-near-3"]
        assert coins == pytest.approx(3 * 1.5e-3 * prism * 0.01**2, rel=1e-5)
        assert volumes[f"frame-{i}/coin-seat-far"] == pytest.approx(CARD_T * 0.022**2, rel=1e-9)
    # the handrail: its two faces, each its card's thickness, across the 30 mm between the narrow frames' side cards
    legs = d.notch_back_face + d.notch_front_face
    assert volumes["frame-0/handrail"] == pytest.approx(legs * d.handrail_thickness * 0.030, rel=0.03)


def test_the_robot_hangs_its_hook_on_the_first_handrail(glb, paper_cfg):
    gltf, binary = glb
    nodes = world_nodes(gltf)
    d = paper_cfg.design
    pose, node = nodes["robot/arm/arm"]
    v, _ = mesh_of(gltf, binary, node)
    # the arm: a laminate at most 26 mm wide, END behind the axle to the hook and a 3 mm lip; its lip folded at
    # the tip, as thick as the arm, its middle on the tip
    layers = math.ceil(d.arm_mass / GRAMMAGE / ((END + d.arm_length + 3e-3) * 0.026))
    assert v[:, 0].max() == pytest.approx(d.arm_length + layers * CARD_T / 2, abs=1e-7)
    hook = pose @ np.array([d.arm_length, 0.0, 0.0, 1.0])
    seat = turn(math.radians(d.rest_angle_deg), -d.Lb, 0.0)  # frame 0's seat, its axis at the origin
    assert math.dist(hook[:2], seat) < 1e-4


# ---- clearance ----
def rectangle(cx, cy, angle, half_length, half_depth):
    u, w = (math.cos(angle), math.sin(angle)), (-math.sin(angle), math.cos(angle))
    return [(cx + a * half_length * u[0] + b * half_depth * w[0], cy + a * half_length * u[1] + b * half_depth * w[1])
            for a, b in ((1, 1), (-1, 1), (-1, -1), (1, -1))]


def ring(cx, cy, angle, half_length, half_depth, end, strip=3e-3, hub=6e-3):
    """The hollow side card as the rectangles it is made of, placed: two end bars, two long strips, the hub bar."""
    u, w = (math.cos(angle), math.sin(angle)), (-math.sin(angle), math.cos(angle))
    inner = half_length - end  # where the windows end

    def part(a, b, half_a, half_b):  # a rectangle centred at (a, b) in the card's own axes
        return rectangle(cx + a * u[0] + b * w[0], cy + a * u[1] + b * w[1], angle, half_a, half_b)
    return [part(s * (inner + end / 2), 0.0, end / 2, half_depth) for s in (1, -1)] + \
        [part(0.0, s * (half_depth - strip / 2), inner, strip / 2) for s in (1, -1)] + [part(0.0, 0.0, hub / 2, half_depth)]


def rings_overlap(p, q) -> bool:
    return any(rectangles_overlap(a, b) for a in p for b in q)


def rectangles_overlap(p, q) -> bool:
    """Separating axes: two rectangles overlap unless one of their four edge normals separates them."""
    for poly in (p, q):
        for k in range(4):
            (x0, y0), (x1, y1) = poly[k], poly[(k + 1) % 4]
            n = (y0 - y1, x1 - x0)
            a = [n[0] * x + n[1] * y for x, y in p]
            b = [n[0] * x + n[1] * y for x, y in q]
            if max(a) <= min(b) or max(b) <= min(a):
                return False
    return True


def test_todays_layout_collides_where_plane_geometry_says(paper_cfg):
    """Every frame alike, its cards in the same planes (the kit before issue 49): turning frame 3 meets frame 4's
    card at rest from the angle at which the two cards (each the rectangles a hollow card is made of) first overlap
    in the plane."""
    d, s = paper_cfg.design, paper_cfg.scene
    half = card_half_length(d) * 1e-3
    layers, depth_mm, end_mm = hollow_card(d)  # the article's hollow side card, worked out in test_kit_readback
    depth = depth_mm * 1e-3  # its outline; the windows lie inside it, its end bars (solid) reach its corners
    assert end_mm > 3.0
    rest, stop = math.radians(d.rest_angle_deg), math.radians(d.stop_angle_deg)
    still = ring(4 * s.pitch, 4 * s.rise, rest, half, depth / 2, end_mm * 1e-3)
    onset = next(a for a in np.arange(d.rest_angle_deg, d.stop_angle_deg, 0.01)
                 if rings_overlap(ring(3 * s.pitch, 3 * s.rise, math.radians(a), half, depth / 2, end_mm * 1e-3), still))
    # the sweep counts a meeting from 1 mm³ shared: a corner entering a corner shares area slowly, so the angle at
    # which the two cards' common area (2D, manifold3d's CrossSection) reaches 1 mm³ over the card's thickness
    import manifold3d as m3

    def area(polys):
        return m3.CrossSection([np.asarray(p) * 1e3 for p in polys], m3.FillRule.NonZero)
    thickness_mm = layers * CARD_T * 1e3
    still_cs = area(still)
    counted = next(a for a in np.arange(onset, d.stop_angle_deg, 0.05)
                   if (area(ring(3 * s.pitch, 3 * s.rise, math.radians(a), half, depth / 2, end_mm * 1e-3)) ^ still_cs)
                   .area() * thickness_mm > 1.0)
    asm = assembly(paper_cfg, identical_layout(paper_cfg))
    contacts = static_sweep(asm, frames=[3])
    hit = [c for c in contacts if (c.part, c.other, c.where) == ("side card (near)", "side card (near)",
                                                                 "frame 4 at rest")]
    assert len(hit) == 1
    # the sweep steps whole degrees from the rest angle and counts a meeting from 1 mm³ shared
    assert onset <= counted <= hit[0].angle_deg <= counted + 1.0, (onset, counted, hit[0])
    assert any(c.where == "frame 2 at its end stop" for c in contacts)
    assert not rectangles_overlap(rectangle(3 * s.pitch, 3 * s.rise, stop, half, depth / 2),
                                  rectangle(5 * s.pitch, 5 * s.rise, stop, half, depth / 2))  # two apart: clear
    assert not any(c.where.startswith(("frame 1 ", "frame 5 ")) for c in contacts)


def test_frames_far_apart_clear_and_touch_only_their_own_stoppers():
    """At a 200 mm pitch nothing of one frame can reach another or another's skewers; each frame turns from its
    rest stopper to its end stopper, touching both (they hold it there) and sharing no volume with either."""
    cfg = load_config(PAPER, overrides={"scene.pitch": 0.2, "scene.frames": 3})
    assert static_sweep(assembly(cfg)) == []


@pytest.mark.parametrize("config", sorted((PAPER.parent / "scenes/solutions").glob("*.yaml")), ids=lambda p: p.stem)
def test_every_stored_solution_stands_up_as_closed_solids(config, tmp_path):
    """Each stored scene solution's row, written as assembly.glb: one node per frame on its axis, every mesh closed
    with a positive volume; and in the kit's layout each frame turned from rest to its end stop meets nothing (the
    nested layout), or the kit says why no nested layout serves the design (and then its parts do meet)."""
    from aero_env.parts.layout import nested_refusal

    cfg = load_config(config)
    refused, contacts = nested_refusal(cfg), static_sweep(assembly(cfg))
    assert (contacts == []) is (refused == ""), (refused, contacts[:1])
    if refused:  # a row so steep that its handrails meet in any layout (test_nested_layout.py)
        assert refused.startswith("a frame's handrail lies in its neighbour's handrail's path"), refused
    out = tmp_path / "row.glb"
    assert main(["sheet", str(config), "--out", str(out)]) == 0
    gltf, binary = read_glb(out.read_bytes())
    nodes = world_nodes(gltf)
    s = cfg.scene
    for i in range(s.frames):
        np.testing.assert_allclose(nodes[f"frame-{i}"][0][:3, 3], [i * s.pitch, i * s.rise, 0.0], atol=1e-12)
    meshes = [node for _, node in nodes.values() if "mesh" in node]
    assert len(meshes) >= 5 * s.frames
    for node in meshes:
        assert closed_volume(*mesh_of(gltf, binary, node)) > 0, node["name"]
