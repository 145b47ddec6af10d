#!/usr/bin/env python3
"""shear.hand_stress: the full stress of known configurations, against a computation by hand.

A few spheres in a periodic cell under simple shear (L = gd e_x e_y), with prescribed velocity
fluctuations and spins; one lub_shear_step sampling the stress (hand_stress_case.c) gives the
five parts (normal contact NC, tangential contact SC, normal lubrication NL, tangential
lubrication SL, kinetic KIN; all 9 components, F_i l_j) and the pair counts. This script
computes them independently with numpy from the law as written in the project's notes
(shared/spec/lubricated-contact-notes.md §1, §2.6, §2.9, §2.10, §3, §6, §9) and the README's
conventions where the engine states its own (README "Contact law", Conventions: eps is the physical
roughness, contact when u < eps a; the quasi-static law at eta = 0 with its static floor
e^-700; a new pair starts at u_n, or at the quasi-static gap when u_n <= 0; the consistent
slip split). It calls no engine code.

  case A: the 6^3 cube, gd = 1; a crushed contact through the y-image (c = (0, -1, 0)), a
          direct contact with the asperities not crushed, a lubricated pair out of contact
          through the y-image;
  case B: a tilted, non-cubic cell (h_1 = (1.5, 7, 0), volume 273), gd = 0.7; a crushed
          contact through the tilted y-image, a contact through the x-image, a lubricated
          pair through the z-image.
Each at eta = 0 and 1, mu = 0.3 (every contact sticks) and 0.006 (contacts slip), 1 and 2
threads. Pass: every component of each part within TOL times the part's largest entry of
the hand value (parts that are 0 by hand, NL and SL at eta = 0: within TOL times 1e-6 of the
case's largest entry over all parts), and the counts (active, contacts, crushed, sliding)
exact. A configuration premise (which pairs are contacts, crushed, out of
contact, through an image; stick and slip both met) is asserted too, so that an edit of the
cases cannot leave a branch of the law untested.

usage: test_hand_stress.py HAND_STRESS_CASE [--verbose]
"""
import itertools
import subprocess
import sys

import numpy as np

# Round-off only: the engine and this script evaluate the same formulas in other orders (the
# normal root in the README's scaled form b = 1 - h(s + alpha_c eps) against §2.6's
# B = 1/h - s - alpha_c eps; ln x from delta; the sum over pairs and threads in another
# order). Measured worst 1.1e-15 of a part's largest entry, so 1e-13 leaves a factor 90; an
# error of the law or of the stress sums is O(1) or at least O(dt) = 1e-3 relative (README,
# shear.hand_stress: the mutants tried).
TOL = 1e-13
STATIC_FLOOR = np.exp(-700.0)  # README: LUB_DELTA_STATIC_FLOOR
PARTS = ("NC", "SC", "NL", "SL", "KIN")

CASES = {
    "A": {
        "H": np.diag([6.0, 6.0, 6.0]),
        "gd": 1.0,
        "r": [1.0, 0.9, 1.1],
        "x": [[3.0, 0.5, 3.0], [3.6, 4.8, 3.3], [5.085, 0.6, 3.1]],
        "vp": [[0.1, -0.2, 0.05], [-0.3, 0.1, 0.2], [0.05, 0.15, -0.1]],
        "w": [[0.1, 0.0, -0.5], [0.0, 0.2, -0.3], [-0.2, 0.1, 0.4]],
    },
    "B": {
        "H": np.array([[6.0, 1.5, 0.0], [0.0, 7.0, 0.0], [0.0, 0.0, 6.5]]),
        "gd": 0.7,
        "r": [1.0, 0.9, 1.1, 0.95],
        "x": [[2.0, 0.4, 5.0], [4.4, 5.9, 5.5], [5.91, 0.45, 5.1], [4.7, 5.5, 0.97]],
        "vp": [[-0.05, 0.1, 0.2], [0.2, -0.15, 0.05], [0.1, 0.05, -0.2], [-0.1, 0.2, 0.1]],
        "w": [[0.3, -0.1, 0.2], [-0.2, 0.0, 0.4], [0.1, 0.3, -0.2], [0.0, -0.3, 0.1]],
    },
}
LAW = {"k_bulk": 1e3, "alpha": 1.0, "k_t": 500.0, "eps": 0.02}
RHO, CUTOFF, SKIN, DT = 2.0, 0.5, 0.1, 1e-3


def nearest_image(H, xi, xj):
    """d = x_j + H c - x_i of the shortest |d| over c in {-1, 0, 1}^3, and c"""
    best = None
    for c in itertools.product((-1, 0, 1), repeat=3):
        d = xj + H @ np.array(c, float) - xi
        if best is None or d @ d < best[0] @ best[0]:
            best = (d, np.array(c, float))
    return best


def normal_gap(s, xm, h, alpha, e):
    """§2.6: backward-Euler gap x+ and contact flag from x- (h = dt/tau; h = inf: the
    quasi-static law of the README, eta = 0)"""
    if np.isinf(h):
        if s >= e:
            return s, False
        x = (s + alpha * e) / (1.0 + alpha)
        return (x if x > 0.0 else STATIC_FLOOR), True

    def root(ac):
        A, B, C = 1.0 + ac, 1.0 / h - s - ac * e, xm / h
        D = B * B + 4.0 * A * C
        return 2.0 * C / (B + np.sqrt(D)) if B > 0.0 else (np.sqrt(D) - B) / (2.0 * A)

    x = root(0.0)
    if x >= e:
        return x, False
    return root(alpha), True


def hand(case, eta, mu):
    """the five parts (divided by V) and the counts, with one record per active pair"""
    H, gd = case["H"], case["gd"]
    r, x = np.array(case["r"]), np.array(case["x"])
    vp, w = np.array(case["vp"]), np.array(case["w"])
    L = np.zeros((3, 3))
    L[0, 1] = gd
    v = x @ L.T + vp  # absolute velocities (§9: v = L x + fluctuation)
    g, alpha, kt, e = LAW["k_bulk"], LAW["alpha"], LAW["k_t"], LAW["eps"]
    V = np.linalg.det(H)
    parts = {p: np.zeros((3, 3)) for p in PARTS}
    counts = [0, 0, 0, 0]  # active, contacts, crushed, sliding
    pairs = []
    for i, j in itertools.combinations(range(len(r)), 2):
        d, c = nearest_image(H, x[i], x[j])  # §1.1
        dist = np.linalg.norm(d)
        n = d / dist
        un = dist - r[i] - r[j]  # §1.2
        a = 0.5 * (r[i] + r[j])  # §1.4
        s = un / a
        if un > CUTOFF * a:  # §5.3
            continue
        # new pair (§2.10, README): x- = u_n/a, or the quasi-static gap when u_n <= 0
        if s > 0.0:
            xm = s
        else:
            xq = (s + alpha * e) / (1.0 + alpha)
            xm = xq if xq > 0.0 else STATIC_FLOOR
        nu_n = 1.5 * np.pi * eta * a * a  # §0.2
        h = DT * g * a / nu_n if eta > 0.0 else np.inf  # §2.2
        xp, contact = normal_gap(s, xm, h, alpha, e)
        # §2.9 (eta = 0: README, the whole F_n is contact force, F_l = 0)
        fn = g * a * (s - xp)
        if np.isinf(h):
            fnc, fnl = (fn if contact else 0.0), 0.0
        else:
            ac = alpha if contact else 0.0
            fnc = -alpha * g * a * (e - xp) if contact else 0.0
            fnl = g * a * (s + ac * e - (1.0 + ac) * xp)  # g a R+
        # §1.7 objective increment with the image velocity L H c (§1.5, §9.4); a new pair has
        # no stored shear force to rotate (§1.8)
        v2 = v[j] + L @ (H @ c)
        ar = (r[i] + r[j]) / (r[i] + r[j] + un)
        wobj = ar * (v2 - v[i]) - np.cross(r[i] * w[i] + r[j] * w[j], n)
        fstar = kt * DT * (wobj - (wobj @ n) * n)  # §3.2.2
        # §3.1 nu_t at the end-of-step gap
        nut = 0.5 * np.pi * eta * a * ((2.0 + xp) * (np.log(2.0 + xp) - np.log(xp)) - 2.0)
        slip = False
        if not contact:  # §3.2.3
            fsc, fsl = np.zeros(3), nut * fstar / (nut + kt * DT)
        elif np.linalg.norm(fstar) <= mu * abs(fnc):  # §3.2.4 stick
            fsc, fsl = fstar, np.zeros(3)
        else:  # §3.2.5 slip, the consistent split (README)
            slip = True
            fsc = mu * abs(fnc) * fstar / np.linalg.norm(fstar)
            fsl = nut * (fstar - fsc) / (nut + kt * DT)
        # §6.1-6.2: sigma_ij = (1/V) sum F_i l_j, forces on body i, l = d
        parts["NC"] += np.outer(fnc * n, d)
        parts["NL"] += np.outer(fnl * n, d)
        parts["SC"] += np.outer(fsc, d)
        parts["SL"] += np.outer(fsl, d)
        crushed = contact and un < -alpha * e * a
        counts[0] += 1
        counts[1] += contact
        counts[2] += crushed
        counts[3] += slip
        pairs.append({"pair": (i, j), "c": tuple(int(k) for k in c), "s": s,
                      "contact": contact, "crushed": crushed, "slip": slip,
                      "stick": contact and not slip})
    m = 4.0 / 3.0 * np.pi * r**3 * RHO
    for i in range(len(r)):  # §6.1 kinetic part, v' = v - L x
        parts["KIN"] -= m[i] * np.outer(vp[i], vp[i])
    return {p: parts[p] / V for p in PARTS}, counts, pairs


def engine(exe, case, eta, mu, threads):
    H = case["H"]
    lines = [" ".join(f"{H[a, b]!r}" for a in range(3) for b in range(3)), repr(case["gd"]),
             f"{eta!r} {LAW['k_bulk']!r} {LAW['alpha']!r} {LAW['k_t']!r} {LAW['eps']!r} {mu!r}",
             f"{RHO!r} {CUTOFF!r} {SKIN!r} {DT!r} {threads}", str(len(case["r"]))]
    for k in range(len(case["r"])):
        lines.append(" ".join(repr(float(q)) for q in
                              [case["r"][k], *case["x"][k], *case["vp"][k], *case["w"][k]]))
    p = subprocess.run([exe], input="\n".join(lines) + "\n", capture_output=True, text=True,
                       timeout=60)
    if p.returncode != 0:
        raise RuntimeError(f"{exe} exit {p.returncode}: {p.stderr.strip()}")
    out = {}
    for line in p.stdout.splitlines():
        f = line.split()
        if f and f[0] == "counts":
            out["counts"] = [int(q) for q in f[1:]]
        elif f and f[0] in PARTS:
            out[f[0]] = np.array([float(q) for q in f[1:]]).reshape(3, 3)
    return out


def main():
    exe = sys.argv[1]
    verbose = "--verbose" in sys.argv
    bad, worst, met = [], 0.0, set()
    for name, case in CASES.items():
        for eta, mu in itertools.product((0.0, 1.0), (0.3, 0.006)):
            ref, counts, pairs = hand(case, eta, mu)
            for q in pairs:
                met |= {k for k in ("contact", "crushed", "slip", "stick") if q[k]}
                met |= {"lubricated" if not q["contact"] and eta > 0 else "dry_apart"}
                if q["contact"] and not q["crushed"]:
                    met.add("contact_not_crushed")
                if q["contact"] and any(q["c"]):
                    met.add("image_contact")
                if not q["contact"] and any(q["c"]):
                    met.add("image_lubricated")
            scale = max(np.abs(ref[p]).max() for p in PARTS)
            for threads in (1, 2):
                tag = f"case {name} eta={eta:g} mu={mu:g} threads={threads}"
                try:
                    eng = engine(exe, case, eta, mu, threads)
                except (RuntimeError, subprocess.TimeoutExpired) as e:
                    bad.append(f"{tag}: {e}")
                    continue
                if eng.get("counts") != counts:
                    bad.append(f"{tag}: counts (active, contacts, crushed, sliding) "
                               f"{eng.get('counts')}, by hand {counts}")
                for p in PARTS:
                    if p not in eng:
                        bad.append(f"{tag}: no {p} part")
                        continue
                    err = np.abs(eng[p] - ref[p]).max()
                    norm = max(np.abs(ref[p]).max(), 1e-6 * scale)
                    worst = max(worst, err / norm)
                    if err > TOL * norm:
                        bad.append(f"{tag}: {p} off by {err:.3e} (largest hand entry "
                                   f"{np.abs(ref[p]).max():.3e}): engine {eng[p].ravel()}, "
                                   f"hand {ref[p].ravel()}")
                    if verbose:
                        print(f"{tag} {p:3s} max|engine - hand| {err:.2e} "
                              f"(over the part's scale {err / norm:.1e})")
            print(f"case {name} eta={eta:g} mu={mu:g}: counts {counts}, pairs "
                  + "; ".join(f"{q['pair']} c={q['c']} s={q['s']:.4f} "
                              + ("crushed " if q["crushed"] else "")
                              + ("slip" if q["slip"] else "stick" if q["stick"] else "apart")
                              for q in pairs)
                  + f"; sigma_xy {sum(ref[p][0, 1] for p in PARTS):.6e}")
    want = {"contact", "crushed", "contact_not_crushed", "slip", "stick", "lubricated",
            "image_contact", "image_lubricated"}
    if want - met:
        bad.append(f"premise: the cases no longer meet {sorted(want - met)}")
    print(f"hand_stress worst |engine - hand| over the part's scale: {worst:.2e} (TOL {TOL:g})")
    for b in bad:
        print("FAIL:", b, file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
