#!/usr/bin/env python3
"""two_spheres_quasistatic.py -- an independent quasi-static reference for the
two_spheres_shear scene (physics-reference section 1b, lubricated-contact-notes sections 1-4).

It never imports, calls or reads the engine: it rebuilds the physics from the two documents and
prints the minimum gap and the final streamline offset of two smooth rigid spheres in simple
shear in the limit St -> 0 (no inertia).

Units: a = eta = gd = 1 (length a, viscosity eta, time 1/gd), as the scene.

Model. Two equal spheres (radius 1) at x1, x2, velocities v1, v2, spins w1, w2. Background
flow W(x) = (y, 0, 0), fluid spin Om = curl(W)/2 = (0, 0, -1/2). With no inertia the forces and
torques on each sphere sum to zero at every instant; they are linear in (v1, v2, w1, w2), so
the velocities come from one 12 x 12 linear solve per configuration, and the positions are
integrated in time (scipy solve_ivp, DOP853, tight tolerances).

  Stokes drag (per sphere):      F = -6 pi (v - W(x)),   T = -8 pi (w - Om).
  Pair, while the centre gap u = |x2 - x1| - 2 <= cutoff (rigid: the true gap is u).
  n = (x2 - x1)/|x2 - x1|, N = n n^T, P = I - N. Forces and torques on sphere 1 (notes 3-4):
    normal lubrication   F_n = (3 pi / 2) (n . (v2 - v1)) / u  n
    shear lubrication    F_s = nu_t(u) P [ 2/(2 + u) (v2 - v1) - (w1 + w2) x n ]
                         nu_t(u) = (pi/2) [ -2 + (2 + u) ln((2 + u)/u) ]
                         (the Maxwell element's rigid limit k_t dt >> nu_t: the force is the
                         dashpot on the objective shear velocity of notes 1.7)
    roll torque (u < 1)  T_r = pi (3/2 + (63/500) u) ln(1/u) P (w2 - w1)
    twist torque (u < 1) T_t = pi u ln(1/u) N (w2 - w1)
    torque arms          T1 = (1 + u/2) n x F_s + T_r + T_t,  T2 = (1 + u/2) n x F_s - T_r - T_t
  Sphere 2 gets -(F_n + F_s). With rotation off the spins stay at Om (the torques are ignored).

Geometry: sphere 1 at the origin, sphere 2 at (-x0, d0 sin(theta), d0 cos(theta)). Outside the
cut-off both spheres move exactly with the flow (drag only), so the relative position moves at
(y2 - y1, 0, 0): the script starts at the cut-off entry (computed in closed form; shear flow is
invariant under translation along x and z and Galilean-invariant along y, so the pair is put
back at the origin there) and stops at the exit, where the offset is final. The pair's
switches on entry/exit and the torques' switch at u = 1 end integration segments (events), so
no step straddles a jump of the right-hand side. The minimum gap is located by the event
(x2 - x1).(v2 - v1) = 0 (increasing), i.e. d|x2 - x1|/dt = 0.

Neglected (on purpose, it is the limit the engine approaches): inertia (St -> 0), elasticity
(Ca -> 0: no surface deflection, no Maxwell memory of the shear spring), time discretisation,
roughness and contact (smooth spheres never touch here), hydrodynamic interactions other than
the pairwise lubrication terms above (as in the law). Friction plays no part (no contact).

Usage:
  two_spheres_quasistatic.py [--cutoff 4] [--d0 0.1] [--theta-deg 90] [--x0 10]
                             [--off shear_lubrication,roll,...] [--no-rotation]
      prints name=value lines (min_gap, final_offset_y, offset_rel_change, ...)
  two_spheres_quasistatic.py --table
      prints the reference rows committed in tests/scenes/test_two_spheres_physics.c
  two_spheres_quasistatic.py --check FILE.c
      recomputes the rows of the block between "BEGIN two_spheres_quasistatic.py --table" and
      "END two_spheres_quasistatic.py" in FILE.c and fails if one differs (ctest
      scenes.two_spheres_quasistatic_ref)
"""
import argparse
import math
import re
import sys

try:
    import numpy as np
    from scipy.integrate import solve_ivp
except ImportError as e:  # ctest: SKIP_RETURN_CODE 77
    print("skipped: needs numpy and scipy (%s)" % e)
    sys.exit(77)

PI = math.pi
ZETA_T, ZETA_R = 6 * PI, 8 * PI
OM_FLUID = np.array([0.0, 0.0, -0.5])
TERMS = ("normal_lubrication", "shear_lubrication", "roll", "twist")


def cross_matrix(n):
    """C with C w = n x w."""
    return np.array([[0.0, -n[2], n[1]], [n[2], 0.0, -n[0]], [-n[1], n[0], 0.0]])


def nu_t(u):
    return 0.5 * PI * (-2.0 + (2.0 + u) * math.log((2.0 + u) / u))


def velocities(x1, x2, cutoff, terms, rotation):
    """(v1, v2, w1, w2) with zero total force and torque on both spheres."""
    # unknown z = (v1, v2, w1, w2); equations: F1, F2, T1, T2 = 0, written as A z = b
    A = np.zeros((12, 12))
    b = np.zeros(12)
    V1, V2, W1, W2 = slice(0, 3), slice(3, 6), slice(6, 9), slice(9, 12)
    eye = np.eye(3)
    for V, x in ((V1, x1), (V2, x2)):  # drag: -zeta_t v + zeta_t W(x)
        A[V, V] -= ZETA_T * eye
        b[V] -= ZETA_T * np.array([x[1], 0.0, 0.0])
    for W in (W1, W2):  # drag torque: -zeta_r w + zeta_r Om
        A[W, W] -= ZETA_R * eye
        b[W] -= ZETA_R * OM_FLUID
    d = x2 - x1
    r = np.linalg.norm(d)
    u = r - 2.0
    if u <= cutoff:
        n = d / r
        N = np.outer(n, n)
        P = eye - N
        C = cross_matrix(n)
        # force on sphere 1 = Fv (v2 - v1) + Fw (w1 + w2); shear part Sv (v2 - v1) + Sw (w1 + w2)
        nt = nu_t(u) if terms["shear_lubrication"] else 0.0
        Sv = nt * (2.0 / (2.0 + u)) * P
        Sw = nt * C  # -(w x n) = n x w, already tangential
        Fv = Sv + ((1.5 * PI / u) * N if terms["normal_lubrication"] else 0.0)
        Fw = Sw
        for rows, sign in ((V1, 1.0), (V2, -1.0)):
            A[rows, V2] += sign * Fv
            A[rows, V1] -= sign * Fv
            A[rows, W1] += sign * Fw
            A[rows, W2] += sign * Fw
        # torque arms: same lever term on both spheres
        arm = 1.0 + 0.5 * u
        for rows in (W1, W2):
            A[rows, V2] += arm * C @ Sv
            A[rows, V1] -= arm * C @ Sv
            A[rows, W1] += arm * C @ Sw
            A[rows, W2] += arm * C @ Sw
        if u < 1.0:  # roll and twist: torque on 1 = K (w2 - w1), on 2 the opposite
            lg = math.log(1.0 / u)
            cr = PI * (1.5 + 0.126 * u) * lg if terms["roll"] else 0.0
            ct = PI * u * lg if terms["twist"] else 0.0
            K = cr * P + ct * N
            A[W1, W2] += K
            A[W1, W1] -= K
            A[W2, W1] += K
            A[W2, W2] -= K
    if not rotation:  # spins prescribed = fluid spin, torque equations dropped
        z_w = np.concatenate([OM_FLUID, OM_FLUID])
        v = np.linalg.solve(A[:6, :6], b[:6] - A[:6, 6:] @ z_w)
        return v[:3], v[3:], OM_FLUID, OM_FLUID
    z = np.linalg.solve(A, b)
    return z[V1], z[V2], z[W1], z[W2]


def encounter(cutoff=4.0, d0=0.1, theta_deg=90.0, x0=10.0, off=(), rotation=True):
    terms = {t: t not in off for t in TERMS}
    th = math.radians(theta_deg)
    y0, z0 = d0 * math.sin(th), d0 * math.cos(th)
    R = 2.0 + cutoff
    if y0 <= 0 or math.hypot(y0, z0) >= R or math.hypot(x0, d0) <= R:
        raise ValueError("need d0 sin(theta) > 0, an offset below 2 + cutoff, x0 outside it")
    # entry: relative position (-sqrt(R^2 - y0^2 - z0^2), y0, z0), sphere 1 at the origin
    X = np.array([0.0, 0.0, 0.0, -math.sqrt(R * R - y0 * y0 - z0 * z0), y0, z0])

    def rhs(t, X):
        v1, v2, _, _ = velocities(X[:3], X[3:], cutoff, terms, rotation)
        return np.concatenate([v1, v2])

    def ev_exit(t, X):  # centre gap back at the cut-off (leaving)
        return np.linalg.norm(X[3:] - X[:3]) - R

    ev_exit.terminal, ev_exit.direction = True, 1.0

    def ev_unit(t, X):  # u = 1: roll/twist switch (their coefficients vanish there)
        return np.linalg.norm(X[3:] - X[:3]) - 3.0

    ev_unit.terminal = True

    def ev_min(t, X):  # d|r|/dt = 0
        v1, v2, _, _ = velocities(X[:3], X[3:], cutoff, terms, rotation)
        return float(np.dot(X[3:] - X[:3], v2 - v1))

    ev_min.direction = 1.0
    t, gaps, t_end = 0.0, [], 1e4 * R / y0
    while True:
        # start each segment just past a switch, so that its event is not found again
        sol = solve_ivp(rhs, (t, t_end), X, method="DOP853", rtol=1e-11, atol=1e-13,
                        events=(ev_exit, ev_unit, ev_min))
        if sol.status < 0:
            raise RuntimeError(sol.message)
        for Xm in sol.y_events[2]:
            gaps.append(np.linalg.norm(Xm[3:] - Xm[:3]) - 2.0)
        X, t = sol.y[:, -1], sol.t[-1]
        if sol.status == 0:
            raise RuntimeError("no exit from the cut-off before t = %g (closed orbit?)" % t_end)
        if len(sol.t_events[0]):  # left the cut-off: offset is final
            break
        # crossed u = 1: nudge past it along the motion (1e-12 in time) and go on
        X = X + 1e-12 * rhs(t, X)
        t += 1e-12
    d = X[3:] - X[:3]
    rel = math.hypot(d[1], d[2])
    return {
        "min_gap": min(gaps),
        "final_offset_y": d[1],
        "final_offset_z": d[2],
        "offset_rel_change": rel / d0 - 1.0,
        "minima": len(gaps),
        "time_in_cutoff": t,
    }


# (cutoff, d0) rows of the committed table: the grid of test_two_spheres_physics.c
TABLE_CUTOFFS = (2.0, 4.0, 7.0)
TABLE_D0 = (0.3, 0.1, 0.03, 0.01)
TABLE_FMT = "    {%g, %g, %.6g},"


def table_rows():
    rows = []
    for c in TABLE_CUTOFFS:
        for d0 in TABLE_D0:
            rows.append((c, d0, encounter(cutoff=c, d0=d0)["min_gap"]))
    return rows


def check(path):
    text = open(path).read()
    m = re.search(r"BEGIN two_spheres_quasistatic\.py --table(.*?)END two_spheres_quasistatic\.py",
                  text, re.S)
    if not m:
        print("no table block in", path)
        return 1
    num = r"([-+0-9.eE]+)"
    committed = [tuple(float(v) for v in g)
                 for g in re.findall(r"\{\s*%s\s*,\s*%s\s*,\s*%s\s*\}" % (num, num, num),
                                     m.group(1))]
    fails = 0
    if not committed:
        print("empty table block in", path)
        return 1
    for c, d0, g in committed:
        ref = encounter(cutoff=c, d0=d0)["min_gap"]
        ok = abs(ref / g - 1.0) < 1e-5  # the table has 6 significant digits
        fails += not ok
        print("%s cutoff=%g d0=%g committed=%.6g script=%.8g" % ("ok  " if ok else "FAIL", c, d0,
                                                                 g, ref))
    print("%d failure(s)" % fails)
    return fails != 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cutoff", type=float, default=4.0)
    ap.add_argument("--d0", type=float, default=0.1)
    ap.add_argument("--theta-deg", type=float, default=90.0)
    ap.add_argument("--x0", type=float, default=10.0)
    ap.add_argument("--off", default="", help="comma list of " + ", ".join(TERMS))
    ap.add_argument("--no-rotation", action="store_true")
    ap.add_argument("--table", action="store_true")
    ap.add_argument("--check", metavar="FILE")
    a = ap.parse_args()
    if a.check:
        return check(a.check)
    if a.table:
        for row in table_rows():
            print(TABLE_FMT % row)
        return 0
    off = tuple(s for s in a.off.split(",") if s)
    for s in off:
        if s not in TERMS:
            ap.error("unknown term " + s)
    res = encounter(a.cutoff, a.d0, a.theta_deg, a.x0, off, not a.no_rotation)
    for k, v in res.items():
        print("%s=%.10g" % (k, v))
    return 0


if __name__ == "__main__":
    sys.exit(main())
