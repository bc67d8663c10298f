"""The hooked swing's equations of motion: frame and robot joined at the hook, which sticks or slides.

Coordinates q = (theta1, s, phi_a, phi_t): the frame angle, the hook's distance along the face it
slides on (0 at the seat; held by a constraint while the hook sticks), the arm's direction hook ->
axle and the torso's direction axle -> torso centre (world angles); alpha = phi_a - phi_t - pi. The
hook is at H = R(theta1)·(seat + s·u) from the frame's axis. Each body's centre is a sum of fixed
lengths times unit vectors, so the kinetic energy has the double-pendulum form and the velocity
terms are the bodies' centripetal accelerations. The stops (the frame's rest/stop, the arm's
alpha_min/alpha_max) are constraints: a held stop removes its coordinate's acceleration.

Every function is scalar code for one design (``p``: its row of :data:`.layout.P`, ``x``: its state
row of :data:`.layout.X`), compiled by numba; with ``NUMBA_DISABLE_JIT=1`` the same code runs as
plain Python.
"""

from __future__ import annotations

import math

from .jit import kernel

from ... import units
from .constants import PIVOT_SLIP_RATE, S_CORNER
from .layout import P, X

G = units.GRAVITY


@kernel
def distance(x, y):
    """sqrt(x^2 + y^2) with the same bits compiled and as plain Python. ``math.hypot`` is not: CPython computes it
    with its own algorithm and numba calls the C library's, one ulp apart on some designs (found when a test's
    random designs moved)."""
    return math.sqrt(x * x + y * y)


@kernel
def clip(v, lo, hi):
    return min(max(v, lo), hi)


@kernel
def spring_torque(p, da, w_alpha):
    """The leaf spring's torque pushing alpha back toward alpha_min: k·da (linear), k/2·da·|da| (stiffening),
    plus the card's damping against alpha's rate, c·w_alpha (``design.spring_damping``)."""
    if p[P.stiff] > 0.0:
        return p[P.k] * da * 0.5 * abs(da) + p[P.spring_c] * w_alpha
    return p[P.k] * da + p[P.spring_c] * w_alpha


@kernel
def spring_energy(p, da):
    if p[P.stiff] > 0.0:
        return p[P.k] * abs(da) ** 3 / 6.0
    return 0.5 * p[P.k] * da * da


@kernel
def skewer_friction(p, w1):
    """The regularised dry friction of the skewer in the frame's hole, on theta1 (DRY_FRICTION_RATE)."""
    return -clip(p[P.pf_c] * w1, -p[P.pf], p[P.pf])


@kernel
def axle_friction(p, w_alpha):
    """The regularised dry friction of the arm's axle, on alpha (+ on phi_a, - on phi_t)."""
    return -clip(p[P.af_c] * w_alpha, -p[P.af], p[P.af])


@kernel
def face_end(p, x):
    """Where the hook's face ends (s, from the seat): past it the hook is on the card's rounded end."""
    return p[P.s_end_f] if x[X.face] > 0.5 else p[P.s_end_b]


@kernel
def hook_place(p, x, s):
    """The hook's centre at s along its face (frame coordinates), its direction of motion there and the face's
    inward normal there, and the path's curvature. Up to the face's end the path is the line seat + s·u; past
    it the hook rolls over the card's rounded end, a circle of the hook/card clearance about the card's end,
    with s its arc length (the hook leaves it when the normal force turns tensile, as pymunk's hook does 2-5 ms
    after the face's end). ``x[X.cap]`` says which (slide_stage sets it at each step's start)."""
    ux, uy, nx, ny = x[X.ux], x[X.uy], x[X.nx], x[X.ny]
    s_end = face_end(p, x)
    if x[X.cap] == 0.0:  # (which of the two a step is on is decided at its start: the path's curvature jumps)
        return p[P.p0x] + s * ux, p[P.p0y] + s * uy, ux, uy, nx, ny, 0.0
    r = p[P.clear]
    psi = (s - s_end) / r
    c, sn = math.cos(psi), math.sin(psi)
    cx, cy = p[P.p0x] + s_end * ux - r * nx, p[P.p0y] + s_end * uy - r * ny  # the card's end
    vx, vy = sn * ux + c * nx, sn * uy + c * ny  # from it to the hook: the normal there
    return cx + r * vx, cy + r * vy, c * ux - sn * nx, c * uy - sn * ny, vx, vy, 1.0 / r


@kernel
def hook_on_frame(p, x):
    """The hook's place in the frame's coordinates (:func:`hook_place`) and the frame's inertia about its axis
    with the robot's mass there: M00 of the hooked system."""
    px, py = hook_place(p, x, x[X.s])[:2]
    return px, py, p[P.If] + p[P.m] * (px * px + py * py)


@kernel
def hook_motion(p, x):
    """The hook's place from its frame's axis and its velocity (world), from the hooked state: the frame's point
    there turning at w1, and the hook's slide along the face at ws."""
    c1, s1 = math.cos(x[X.th1]), math.sin(x[X.th1])
    px, py, ux, uy = hook_place(p, x, x[X.s])[:4]
    Hx, Hy = c1 * px - s1 * py, s1 * px + c1 * py
    uwx, uwy = c1 * ux - s1 * uy, s1 * ux + c1 * uy
    return Hx, Hy, -Hy * x[X.w1] + uwx * x[X.ws], Hx * x[X.w1] + uwy * x[X.ws]


@kernel
def solve_hooked(A, B, C, D, E, F, r0, r1, r2, frame_held, arm_held):
    """Solve the sticking hook's [[A, D, E], [D, B, F], [E, F, C]]·q = r over (theta1, phi_a, phi_t) by cofactors,
    a held stop projecting its coordinate out: the frame's (q0 = 0), the arm's (J = (0, 1, -1)), or both (only the
    robot's rigid turn about the hook is left)."""
    if frame_held and arm_held:
        y = (r1 + r2) / (B + 2.0 * F + C)
        return 0.0, y, y
    c00, c01, c02 = B * C - F * F, E * F - D * C, D * F - E * B
    c11, c12, c22 = A * C - E * E, D * E - A * F, A * B - D * D
    inv = 1.0 / (A * c00 + D * c01 + E * c02)
    x0 = (c00 * r0 + c01 * r1 + c02 * r2) * inv
    x1 = (c01 * r0 + c11 * r1 + c12 * r2) * inv
    x2 = (c02 * r0 + c12 * r1 + c22 * r2) * inv
    if frame_held:  # x - M^-1·e0·x0/(M^-1)_00
        k = x0 / c00
        return 0.0, x1 - k * c01, x2 - k * c02
    if arm_held:
        u0, u1, u2 = c01 - c02, c11 - c12, c12 - c22
        k = (x1 - x2) / (u1 - u2)
        return x0 - k * u0, x1 - k * u1, x2 - k * u2
    return x0, x1, x2


@kernel
def stick_eval(p, x, px, py, A, th1, pa, pt, w1, wa, wt):
    """Accelerations (theta1, phi_a, phi_t) of a design whose hook sticks (s fixed), and the handrail's force on
    the hook (Fx, Fy), the stops' loads (lam1 frame, lamA arm) and the frame's cos/sin. The 3x3 mass matrix is
    inverted by cofactors; a held stop projects its coordinate out."""
    c1, s1 = math.cos(th1), math.sin(th1)
    ca, sa = math.cos(pa), math.sin(pa)
    ct, st = math.cos(pt), math.sin(pt)
    m, Pa, Pt, Pat = p[P.m], p[P.Pa], p[P.Pt], p[P.Pat]
    Hx, Hy = c1 * px - s1 * py, s1 * px + c1 * py
    D = Pa * (Hx * ca + Hy * sa)
    E = Pt * (Hx * ct + Hy * st)
    cat, sat = ca * ct + sa * st, sa * ct - ca * st
    F = Pat * cat
    B, C = p[P.Ja], p[P.Jt]
    w1s, wa2, wt2 = w1 * w1, wa * wa, wt * wt
    Bx = -m * Hx * w1s - Pa * ca * wa2 - Pt * ct * wt2  # the bodies' centripetal terms at the hook
    By = -m * Hy * w1s - Pa * sa * wa2 - Pt * st * wt2
    tau = spring_torque(p, pa - pt - p[P.alim], wa - wt)
    # the tip turning in the notch: a smooth Coulomb torque up to x[piv] (PIVOT_SLIP_RATE), and a sliding
    # hook's friction moment x[tq0]
    tp = x[X.tq0] - x[X.piv] * clip((wa - w1) * (1.0 / PIVOT_SLIP_RATE), -1.0, 1.0)
    tf, ta = skewer_friction(p, w1), axle_friction(p, wa - wt)
    hxh = w1s * (ca * Hy - sa * Hx)
    hth = w1s * (ct * Hy - st * Hx)
    r0 = -p[P.mg] * Hx + p[P.cfr] * c1 + p[P.m3gh] * s1 - (Hx * By - Hy * Bx) - tp + tf
    r1 = -p[P.Pag] * ca - tau + tp + Pa * hxh - Pat * sat * wt2 + ta
    r2 = -p[P.Ptg] * ct + tau + Pt * hth + Pat * sat * wa2 - ta
    x0, x1, x2 = solve_hooked(A, B, C, D, E, F, r0, r1, r2, x[X.lock1] > 0.0, x[X.lockA] > 0.0)
    Fx = -m * Hy * x0 - Pa * sa * x1 - Pt * st * x2 + Bx
    Fy = m * Hx * x0 + Pa * ca * x1 + Pt * ct * x2 + By + p[P.mg]
    lam1 = A * x0 + D * x1 + E * x2 - r0
    lamA = r2 - (E * x0 + F * x1 + C * x2)
    return x0, x1, x2, Fx, Fy, lam1, lamA, c1, s1


@kernel
def stick_step(p, x, px, py, A, dt, a0, a1, a2):
    """One classical RK4 step of a sticking design from its state, (a0, a1, a2) the accelerations at its start.
    Returns the new (theta1, phi_a, phi_t, w1, wa, wt)."""
    th1, pa, pt, w1, wa, wt = x[X.th1], x[X.pa], x[X.pt], x[X.w1], x[X.wa], x[X.wt]
    h = 0.5 * dt
    b0, b1, b2 = stick_eval(p, x, px, py, A, th1 + h * w1, pa + h * wa, pt + h * wt,
                            w1 + h * a0, wa + h * a1, wt + h * a2)[:3]
    v20, v21, v22 = w1 + h * a0, wa + h * a1, wt + h * a2
    c0, c1, c2 = stick_eval(p, x, px, py, A, th1 + h * v20, pa + h * v21, pt + h * v22,
                            w1 + h * b0, wa + h * b1, wt + h * b2)[:3]
    v30, v31, v32 = w1 + h * b0, wa + h * b1, wt + h * b2
    d0, d1, d2 = stick_eval(p, x, px, py, A, th1 + dt * v30, pa + dt * v31, pt + dt * v32,
                            w1 + dt * c0, wa + dt * c1, wt + dt * c2)[:3]
    v40, v41, v42 = w1 + dt * c0, wa + dt * c1, wt + dt * c2
    k6 = dt / 6.0
    return (th1 + k6 * (w1 + 2.0 * (v20 + v30) + v40), pa + k6 * (wa + 2.0 * (v21 + v31) + v41),
            pt + k6 * (wt + 2.0 * (v22 + v32) + v42), w1 + k6 * (a0 + 2.0 * (b0 + c0) + d0),
            wa + k6 * (a1 + 2.0 * (b1 + c1) + d1), wt + k6 * (a2 + 2.0 * (b2 + c2) + d2))


@kernel
def solve_eliminated(g00, g01, g02, g10, g11, g12, g20, g21, g22, g0, g1, g2, frame_held, arm_held):
    """Solve G·x = g over (theta1, phi_a, phi_t), a sliding hook's system with s eliminated (slide_eval), a held
    stop as a substitution: the frame's (x0 = 0), the arm's (x1 = x2), or both (the robot's rigid turn only)."""
    if frame_held and arm_held:  # the robot's rigid turn only
        x0 = 0.0
        x1 = x2 = (g1 + g2) / (g11 + g12 + g21 + g22)
    elif frame_held:  # rows 1, 2 in (phi_a, phi_t)
        inv2 = 1.0 / (g11 * g22 - g12 * g21)
        x0, x1, x2 = 0.0, (g1 * g22 - g12 * g2) * inv2, (g11 * g2 - g1 * g21) * inv2
    elif arm_held:  # phi_a'' = phi_t'': rows 0 and 1 + 2
        h0, h1, e1 = g01 + g02, g11 + g12 + g21 + g22, g10 + g20
        inv2 = 1.0 / (g00 * h1 - h0 * e1)
        x0 = (g0 * h1 - h0 * (g1 + g2)) * inv2
        x1 = x2 = (g00 * (g1 + g2) - e1 * g0) * inv2
    else:
        k00, k01, k02 = g11 * g22 - g12 * g21, g12 * g20 - g10 * g22, g10 * g21 - g11 * g20
        inv = 1.0 / (g00 * k00 + g01 * k01 + g02 * k02)
        x0 = (g0 * k00 + g01 * (g12 * g2 - g1 * g22) + g02 * (g1 * g21 - g11 * g2)) * inv
        x1 = (g00 * (g1 * g22 - g12 * g2) + g0 * k01 + g02 * (g10 * g2 - g1 * g20)) * inv
        x2 = (g00 * (g11 * g2 - g1 * g21) + g01 * (g1 * g20 - g10 * g2) + g0 * k02) * inv
    return x0, x1, x2


@kernel
def slide_eval(p, x, th1, s, pa, pt, w1, ws, wa, wt):
    """Accelerations (theta1, s, phi_a, phi_t) of a design whose hook slides along a face, and the face's normal
    force N and the stops' loads. The s row carries the kinetic friction -mu_k·N·sig with N linear in the
    accelerations; s is eliminated and the remaining 3x3 solved by Cramer's rule (the stops as substitutions)."""
    px, py, ux, uy, nx, ny, kap = hook_place(p, x, s)
    musig = x[X.mu_sig]
    c1, s1 = math.cos(th1), math.sin(th1)
    ca, sa = math.cos(pa), math.sin(pa)
    ct, st = math.cos(pt), math.sin(pt)
    m, Pa, Pt, Pat = p[P.m], p[P.Pa], p[P.Pt], p[P.Pat]
    Hx, Hy = c1 * px - s1 * py, s1 * px + c1 * py
    uwx, uwy = c1 * ux - s1 * uy, s1 * ux + c1 * uy
    nwx, nwy = c1 * nx - s1 * ny, s1 * nx + c1 * ny
    sat = sa * ct - ca * st
    A = p[P.If] + m * (px * px + py * py)
    M01 = m * (px * uy - py * ux)
    D, E = Pa * (Hx * ca + Hy * sa), Pt * (Hx * ct + Hy * st)
    M12, M13 = Pa * (uwy * ca - uwx * sa), Pt * (uwy * ct - uwx * st)
    F = Pat * (ca * ct + sa * st)
    w1w1, wa2, wt2 = w1 * w1, wa * wa, wt * wt
    w1ws2 = 2.0 * w1 * ws
    # the hook's centripetal + Coriolis terms, and on the rounded end its path's own turn toward the card's end
    bHx = -Hx * w1w1 - uwy * w1ws2 - kap * ws * ws * nwx
    bHy = -Hy * w1w1 + uwx * w1ws2 - kap * ws * ws * nwy
    Bx = m * bHx - Pa * ca * wa2 - Pt * ct * wt2
    By = m * bHy - Pa * sa * wa2 - Pt * st * wt2
    tau = spring_torque(p, pa - pt - p[P.alim], wa - wt)
    tp = x[X.tq0]
    tf, ta = skewer_friction(p, w1), axle_friction(p, wa - wt)
    r0 = -p[P.mg] * Hx + p[P.cfr] * c1 + p[P.m3gh] * s1 - (Hx * By - Hy * Bx) - tp + tf
    r1 = -p[P.mg] * uwy - (uwx * Bx + uwy * By)
    r2 = -p[P.Pag] * ca - tau + tp - (Pa * (ca * bHy - sa * bHx) + Pat * sat * wt2) + ta
    r3 = -p[P.Ptg] * ct + tau - (Pt * (ct * bHy - st * bHx) - Pat * sat * wa2) - ta
    f0 = m * (nwy * Hx - nwx * Hy)
    f2 = Pa * (nwy * ca - nwx * sa)
    f3 = Pt * (nwy * ct - nwx * st)
    N0 = nwx * Bx + nwy * (By + p[P.mg])
    # the s row with friction: s'' = (q1 - a0·x0 - a2·x2 - a3·x3) / m
    im = 1.0 / m
    a0, a2, a3 = (M01 + musig * f0) * im, (M12 + musig * f2) * im, (M13 + musig * f3) * im
    q1 = (r1 - musig * N0) * im
    # the other rows with s'' substituted: G x = g over (theta1, phi_a, phi_t)
    g00, g01, g02, g0 = A - M01 * a0, D - M01 * a2, E - M01 * a3, r0 - M01 * q1
    g10, g11, g12, g1 = D - M12 * a0, p[P.Ja] - M12 * a2, F - M12 * a3, r2 - M12 * q1
    g20, g21, g22, g2 = E - M13 * a0, F - M13 * a2, p[P.Jt] - M13 * a3, r3 - M13 * q1
    x0, x1, x2 = solve_eliminated(g00, g01, g02, g10, g11, g12, g20, g21, g22, g0, g1, g2,
                                  x[X.lock1] > 0.0, x[X.lockA] > 0.0)
    xs = q1 - a0 * x0 - a2 * x1 - a3 * x2
    N = f0 * x0 + f2 * x1 + f3 * x2 + N0
    lam1 = A * x0 + M01 * xs + D * x1 + E * x2 - r0
    lamA = r3 - (E * x0 + M13 * xs + F * x1 + p[P.Jt] * x2)
    return x0, xs, x1, x2, N, lam1, lamA


@kernel
def slide_step(p, x, dt, a0, a1, a2, a3):
    """One classical RK4 step of a sliding design. Returns the new (theta1, s, phi_a, phi_t, w1, ws, wa, wt)."""
    y0, y1, y2, y3 = x[X.th1], x[X.s], x[X.pa], x[X.pt]
    v0, v1, v2, v3 = x[X.w1], x[X.ws], x[X.wa], x[X.wt]
    h = 0.5 * dt
    u0, u1, u2, u3 = v0 + h * a0, v1 + h * a1, v2 + h * a2, v3 + h * a3
    b0, b1, b2, b3 = slide_eval(p, x, y0 + h * v0, y1 + h * v1, y2 + h * v2, y3 + h * v3, u0, u1, u2, u3)[:4]
    z0, z1, z2, z3 = v0 + h * b0, v1 + h * b1, v2 + h * b2, v3 + h * b3
    c0, c1, c2, c3 = slide_eval(p, x, y0 + h * u0, y1 + h * u1, y2 + h * u2, y3 + h * u3, z0, z1, z2, z3)[:4]
    e0, e1, e2, e3 = v0 + dt * c0, v1 + dt * c1, v2 + dt * c2, v3 + dt * c3
    d0, d1, d2, d3 = slide_eval(p, x, y0 + dt * z0, y1 + dt * z1, y2 + dt * z2, y3 + dt * z3, e0, e1, e2, e3)[:4]
    k6 = dt / 6.0
    return (y0 + k6 * (v0 + 2.0 * (u0 + z0) + e0), y1 + k6 * (v1 + 2.0 * (u1 + z1) + e1),
            y2 + k6 * (v2 + 2.0 * (u2 + z2) + e2), y3 + k6 * (v3 + 2.0 * (u3 + z3) + e3),
            v0 + k6 * (a0 + 2.0 * (b0 + c0) + d0), v1 + k6 * (a1 + 2.0 * (b1 + c1) + d1),
            v2 + k6 * (a2 + 2.0 * (b2 + c2) + d2), v3 + k6 * (a3 + 2.0 * (b3 + c3) + d3))


@kernel
def wrap(a):
    return (a + math.pi) % (2.0 * math.pi) - math.pi


@kernel
def friction_cone(p, s, face, Fx, Fy, c1, s1, phi):
    """Where the handrail's force (or impulse) (Fx, Fy) on the hook falls against the notch's friction cones.

    Returns (release, slide, face, sig): release where no face can push (tensile); slide where the force leaves
    the static cone with a compressive face (face 0 back, 1 front; sig +1 outward along the face, -1 toward the
    corner). Otherwise the hook holds. ``s``: the hook's place along its face (in the corner at 0); ``phi``: the
    cone's half-angle, atan of the friction coefficient the contact has now."""
    flx, fly = c1 * Fx + s1 * Fy, c1 * Fy - s1 * Fx
    dl = wrap(math.atan2(fly, flx) - p[P.beta])
    half = 0.5 * math.pi
    if s <= S_CORNER:  # in the corner: the union of both faces' cones
        cone_half = p[P.face_off] + phi
        out_b, out_f = dl < -cone_half, dl > cone_half
        comp_b, comp_f = dl + p[P.face_off] > -half, dl - p[P.face_off] < half
        release = (out_b and not comp_b) or (out_f and not comp_f)
        slide = (out_b and comp_b) or (out_f and comp_f)
        return release, slide, 1.0 if out_f else 0.0, 1.0
    kappa = 2.0 * face - 1.0  # on one face: -1 back, +1 front
    rho = dl - kappa * p[P.face_off]
    tensile = abs(rho) > half
    return tensile, abs(rho) > phi and not tensile, face, 1.0 if kappa * rho > 0.0 else -1.0


@kernel
def normal_sum(p, x, Fx, Fy, c1, s1, mu):
    """The sum of the faces' normal forces under the joint force F of a sticking hook, for its turning friction.
    In the corner F = sum_i N_i·(n_i + mu·sig·perp(n_i)): each face's normal force plus the friction of the tip
    turning on it (sig: the sense of the arm's rotation relative to the frame), which bounds the torque at high
    friction (mu -> inf: the wedge carries the load by friction alone). On one face: that face's normal force."""
    flx, fly = c1 * Fx + s1 * Fy, c1 * Fy - s1 * Fx
    if x[X.s] > S_CORNER:
        return max(flx * x[X.nx] + fly * x[X.ny], 0.0)
    ms = mu if x[X.wa] >= x[X.w1] else -mu
    bx, by, fx, fy = p[P.nbx], p[P.nby], p[P.nfx], p[P.nfy]
    abx, aby = bx - ms * by, by + ms * bx  # n + mu·sig·perp(n)
    afx, afy = fx - ms * fy, fy + ms * fx
    det = abx * afy - aby * afx
    nb = (flx * afy - fly * afx) / det
    nf = (abx * fly - aby * flx) / det
    k = 1.0 / (1.0 + mu * mu)  # one face: F's component along n + mu·sig·perp(n)
    if nb < 0.0:
        return max(flx * afx + fly * afy, 0.0) * k
    if nf < 0.0:
        return max(flx * abx + fly * aby, 0.0) * k
    return nb + nf


@kernel
def hook_from_com(p, pa, pt):
    """The hook's position relative to the robot's centre of mass (world)."""
    return (-(p[P.Pa] * math.cos(pa) + p[P.Pt] * math.cos(pt)) / p[P.m],
            -(p[P.Pa] * math.sin(pa) + p[P.Pt] * math.sin(pt)) / p[P.m])


@kernel
def com_velocity_from_hook(p, pa, pt, wa, wt):
    """d/dt (centre of mass - hook)."""
    return (-(p[P.Pa] * math.sin(pa) * wa + p[P.Pt] * math.sin(pt) * wt) / p[P.m],
            (p[P.Pa] * math.cos(pa) * wa + p[P.Pt] * math.cos(pt) * wt) / p[P.m])


@kernel
def theta2(p, pa, pt):
    """The runner's theta2: the angle of the line from the robot's centre of mass to the hook."""
    hx, hy = hook_from_com(p, pa, pt)
    return math.atan2(hy, hx)


@kernel
def hooked_mass(p, x, s):
    """The hooked system's mass matrix over (theta1, s, phi_a, phi_t) with the hook at s: its off-diagonal entries
    M01, M02, M03, M12, M13, M23 and M00 (M11 = m, M22 = Ja, M33 = Jt), then the hook's place from the frame's axis
    (world) and sin(theta1), cos(theta1)."""
    th1, pa, pt = x[X.th1], x[X.pa], x[X.pt]
    px, py, ux, uy = hook_place(p, x, s)[:4]
    c1, s1 = math.cos(th1), math.sin(th1)
    ca, sa = math.cos(pa), math.sin(pa)
    ct, st = math.cos(pt), math.sin(pt)
    m, Pa, Pt = p[P.m], p[P.Pa], p[P.Pt]
    Hx, Hy = c1 * px - s1 * py, s1 * px + c1 * py
    uwx, uwy = c1 * ux - s1 * uy, s1 * ux + c1 * uy
    M00 = p[P.If] + m * (px * px + py * py)
    M01 = m * (px * uy - py * ux)
    M02, M03 = Pa * (Hx * ca + Hy * sa), Pt * (Hx * ct + Hy * st)
    M12, M13 = Pa * (uwy * ca - uwx * sa), Pt * (uwy * ct - uwx * st)
    M23 = p[P.Pat] * (ca * ct + sa * st)
    return M00, M01, M02, M03, M12, M13, M23, Hx, Hy, s1, c1


@kernel
def hooked_energy(p, x, oy):
    """Mechanical energy (J) of the hooked frame and robot (kinetic, gravitational, spring); oy: the frame axis'
    height."""
    pa, pt = x[X.pa], x[X.pt]
    w1, ws, wa, wt = x[X.w1], x[X.ws], x[X.wa], x[X.wt]
    M00, M01, M02, M03, M12, M13, M23, Hx, Hy, s1, c1 = hooked_mass(p, x, x[X.s])
    m, Pa, Pt = p[P.m], p[P.Pa], p[P.Pt]
    sa, st = math.sin(pa), math.sin(pt)
    kin = (0.5 * (M00 * w1 * w1 + m * ws * ws + p[P.Ja] * wa * wa + p[P.Jt] * wt * wt)
           + M01 * w1 * ws + M02 * w1 * wa + M03 * w1 * wt + M12 * ws * wa + M13 * ws * wt + M23 * wa * wt)
    pot = (p[P.frame_m] * G * oy - p[P.cfr] * s1 + p[P.m3gh] * c1
           + G * (m * (oy + Hy) + Pa * sa + Pt * st)
           + spring_energy(p, pa - pt - p[P.alim]))
    return kin + pot


@kernel
def first_crossing(d, v, a):
    """The first h > 0 at which v·h + a·h²/2 reaches d (inf if never)."""
    best = math.inf
    if a == 0.0:
        if v != 0.0 and d / v > 0.0:
            best = d / v
        return best
    disc = v * v + 2.0 * a * d
    if disc < 0.0:
        return best
    r = math.sqrt(disc)
    for h in ((-v - r) / a, (-v + r) / a):
        if 0.0 < h < best:
            best = h
    return best


@kernel
def stop_lets_go(kind, lam, friction):
    """Whether a stop holding a joint (kind 1 its lower stop, 2 its upper, 0 none) lets go under the load lam the
    stop must supply (positive: pressed into the lower stop): once the pull exceeds the joint's dry friction. At
    rest on a stop the joint's Coulomb friction holds the rest, as the pymunk world's capped motor does (the
    regularised friction would let it creep)."""
    return (kind == 1.0 and lam < -friction) or (kind == 2.0 and lam > friction)
