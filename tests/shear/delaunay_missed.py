"""Missed Delaunay edges of a "delaunay" simple_shear run, frame by frame.

For every /pair_network frame of result.h5 (the run needs "pair_network": "snapshots"), the
regular (radius-weighted) triangulation of the spheres and their 26 periodic images is built
independently of the engine: the lower convex hull of the points (x, |x|^2 - r^2) (scipy's
Qhull). Its edges with a gap u_n <= cutoff a_ij are the Delaunay edges inside the cut-off; the
frame's interaction network holds the pairs the engine allowed. Prints, per frame, the edges,
those missing from the network ("missed") and the network pairs that are no edge ("extra": the
contacts kept by the guard), then the mean, smallest and largest missed fraction.

usage: /usr/bin/python3 tests/shear/delaunay_missed.py RUN_DIR/result.h5 [--cutoff 2]
       [--skip N] (frames to leave out at the start, default 0)
Exact degeneracies (lattices) are not handled: Qhull splits them arbitrarily.
"""
import argparse
import itertools

import h5py
import numpy as np
from scipy.spatial import ConvexHull


def delaunay_edges(x, r, box):
    """{(i, j, image): u_n / a_ij} of the regular triangulation's edges with i < j (or i == j
    across a boundary), image the shift of j; box columns are the cell vectors."""
    shifts = np.array(list(itertools.product((-1, 0, 1), repeat=3)))
    n = len(r)
    pts = np.concatenate([x + box @ s for s in shifts])
    owner = np.tile(np.arange(n), len(shifts))
    image = np.repeat(shifts, n, axis=0)
    lift = np.einsum("ij,ij->i", pts, pts) - r[owner] ** 2
    hull = ConvexHull(np.column_stack([pts, lift]), qhull_options="Qt Qbb")
    edges = {}
    for simplex in hull.simplices[hull.equations[:, 3] < 0]:  # the lower hull
        for p, q in itertools.combinations(simplex, 2):
            if image[p].any() and image[q].any():
                continue  # both images: the same edge appears once with a home sphere
            i, j = owner[p], owner[q]
            shift = image[q] - image[p]
            if i > j or (i == j and tuple(shift) < (0, 0, 0)):
                i, j, shift = j, i, -shift
            key = (int(i), int(j)) + tuple(int(v) for v in shift)
            if key not in edges:
                gap = np.linalg.norm(pts[q] - pts[p]) - r[i] - r[j]
                edges[key] = gap / (0.5 * (r[i] + r[j]))
    return edges


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("h5")
    ap.add_argument("--cutoff", type=float, default=2.0)
    ap.add_argument("--skip", type=int, default=0)
    args = ap.parse_args()
    fractions = []
    with h5py.File(args.h5, "r") as f:
        net, part = f["pair_network"], f["particles/all"]
        r = part["radius"][:]
        for fr in range(args.skip, len(net["step"])):
            s0, c = int(net["row_start"][fr]), int(net["row_count"][fr])
            x = part["position/value"][fr]
            edges_h5 = part["box/edges/value"][fr]
            i, j = net["i"][s0:s0 + c], net["j"][s0:s0 + c]
            img, branch = net["image"][s0:s0 + c], net["branch"][s0:s0 + c]
            # which way the box matrix is stored: the one that reproduces the branch vectors
            box = min((edges_h5, edges_h5.T),
                      key=lambda b: np.abs(x[j] + img @ b.T - x[i] - branch).max())
            edges = delaunay_edges(x, r, box)
            inside = {k for k, u in edges.items() if u <= args.cutoff}
            network = {(int(a), int(b)) + tuple(int(v) for v in s) for a, b, s in zip(i, j, img)}
            missed, extra = inside - network, network - inside
            frac = len(missed) / max(len(inside), 1)
            fractions.append(frac)
            print("frame %d step %d: delaunay_edges_inside=%d network=%d missed=%d (%.4f) extra=%d"
                  % (fr, net["step"][fr], len(inside), len(network), len(missed), frac,
                     len(extra)))
    fr = np.array(fractions)
    print("missed fraction over %d frames: mean %.4f, min %.4f, max %.4f"
          % (len(fr), fr.mean(), fr.min(), fr.max()))


if __name__ == "__main__":
    main()
