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
       [--max-mean F] [--max-frame F] (exit 1 if the mean / the largest missed fraction
       exceeds F; ctest shear.delaunay_qhull)
Prints delaunay_missed_mean=, delaunay_missed_max= and delaunay_frames= lines at the end.
Exact degeneracies (lattices) are not handled: Qhull splits them arbitrarily.
"""
import argparse
import itertools
import sys

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
    simplices = hull.simplices[hull.equations[:, 3] < 0]  # the lower hull
    p = np.concatenate([simplices[:, a] for a, b in itertools.combinations(range(4), 2)])
    q = np.concatenate([simplices[:, b] for a, b in itertools.combinations(range(4), 2)])
    home = ~(image[p].any(axis=1) & image[q].any(axis=1))  # both images: seen with a home sphere
    p, q = p[home], q[home]
    i, j, shift = owner[p], owner[q], image[q] - image[p]
    # the canonical orientation: i < j, or i == j with the shift's first non-zero component > 0
    first = np.take_along_axis(shift, np.argmax(shift != 0, axis=1)[:, None], axis=1)[:, 0]
    flip = (i > j) | ((i == j) & (first < 0))
    i, j = np.where(flip, j, i), np.where(flip, i, j)
    shift = np.where(flip[:, None], -shift, shift)
    keys, first_row = np.unique(np.column_stack([i, j, shift]), axis=0, return_index=True)
    gap = np.linalg.norm(pts[q] - pts[p], axis=1) - r[owner[p]] - r[owner[q]]
    reduced = gap / (0.5 * (r[owner[p]] + r[owner[q]]))
    return {tuple(int(v) for v in k): float(reduced[row]) for k, row in zip(keys, first_row)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("h5")
    ap.add_argument("--cutoff", type=float, default=2.0)
    ap.add_argument("--skip", type=int, default=0)
    ap.add_argument("--max-mean", type=float, default=None)
    ap.add_argument("--max-frame", type=float, default=None)
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
    print("delaunay_frames=%d\ndelaunay_missed_mean=%.6f\ndelaunay_missed_max=%.6f"
          % (len(fr), fr.mean(), fr.max()))
    bad = []
    if args.max_mean is not None and not fr.mean() <= args.max_mean:
        bad.append("mean missed fraction %.4f above %g" % (fr.mean(), args.max_mean))
    if args.max_frame is not None and not fr.max() <= args.max_frame:
        bad.append("largest missed fraction %.4f above %g" % (fr.max(), args.max_frame))
    for b in bad:
        print("FAIL " + b, file=sys.stderr)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
