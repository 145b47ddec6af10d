#!/usr/bin/env python3
"""pair_network.py - first look at the interaction network of a simple_shear or resuspension
result.h5.

    python3 client_examples/pair_network.py result.h5 [--frame K] [--bins N]
    python3 client_examples/pair_network.py result.h5 --series

The run must have asked for it ("pair_network": "final" or "snapshots"; /pair_network in
result.h5, README "Interaction network"). Prints, for one frame of the network (the last
unless --frame K; K < 0 counts from the end; one `name=value` line per figure): the number of
frames, the frame's step, pairs and contacts, coordination numbers Z = 2 pairs/N and Z_c =
2 contacts/N of the N particles (a pair with a floor sphere of resuspension counts once), the
sliding fraction of the contacts, the contact fabric tensor <n n> over the
contacts, the stress each part of the pair forces carries, (1/V) sum F (x) branch (with the
box of the particle snapshot of the frame's step, so the run needs "snapshots" >= 1 for it),
and a histogram of the normal contact forces over their mean. Units as in the file (forces
eta gd a^2 or P a^2, stresses eta gd or P). With --series, one line per figure and frame
instead (frame_K_step, _time, _pairs, _contacts, _Z_contact, _sliding_fraction): how the
network evolves along a run written with "pair_network": "snapshots".
(Debian: apt-get install python3-h5py python3-numpy.)"""
import argparse

import h5py
import numpy as np

def ends_on_particles(j, n):
    """Pair ends that belong to the N particles: pair (i, j) counts twice, once for each, and
    once when j >= N names a fixed floor sphere of resuspension (j - N), whose coordination
    is not counted."""
    return 2 * int(np.count_nonzero(j < n)) + int(np.count_nonzero(j >= n))


PARTS = (("normal_contact", "force_normal_contact", None),
         ("tangential_contact", None, "force_tangential_contact"),
         ("normal_lubrication", "force_normal_lubrication", None),
         ("tangential_lubrication", None, "force_tangential_lubrication"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("result")
    ap.add_argument("--frame", type=int, default=-1,
                    help="which frame (default -1: the last; 0: the first)")
    ap.add_argument("--bins", type=int, default=8, help="histogram bins of f/<f> (default 8)")
    ap.add_argument("--series", action="store_true",
                    help="counts of every frame instead of one frame's analysis")
    a = ap.parse_args()
    if a.series:
        series(a.result)
        return
    with h5py.File(a.result, "r") as f:
        if "pair_network" not in f:
            raise SystemExit("%s has no /pair_network (run with \"pair_network\": \"final\")"
                             % a.result)
        g = f["pair_network"]
        steps = g["step"][()]
        if not -len(steps) <= a.frame < len(steps):
            raise SystemExit("--frame %d: %s holds %d frames" % (a.frame, a.result, len(steps)))
        k = a.frame % len(steps)
        # frame k: rows row_start[k] .. row_start[k] + row_count[k] - 1 of every column
        first, count = int(g["row_start"][k]), int(g["row_count"][k])
        net = {key: g[key][first:first + count] for key in g
               if key not in ("step", "time", "row_start", "row_count")}
        unit = g["force_normal_contact"].attrs["unit"]
        unit = unit.decode() if isinstance(unit, bytes) else str(unit)
        n = len(f["particles/all/radius"]) if "particles/all/radius" in f else None
        edges = None  # the box of the snapshot taken at the frame's step
        if "particles/all/box/edges/value" in f:
            at = np.flatnonzero(f["particles/all/position/step"][()] == steps[k])
            if len(at):
                edges = f["particles/all/box/edges/value"][at[-1]]
    contact = net["contact"] == 1
    pairs, contacts = len(contact), int(contact.sum())
    print("frames=%d" % len(steps))
    print("step=%d" % steps[k])
    print("pairs=%d" % pairs)
    print("contacts=%d" % contacts)
    print("sliding_fraction=%.6g" % (net["sliding"][contact].mean() if contacts else 0.0))
    if n:  # pairs with the floor of resuspension count once (ends_on_particles)
        print("Z=%.6g" % (ends_on_particles(net["j"], n) / n))
        print("Z_contact=%.6g" % (ends_on_particles(net["j"][contact], n) / n))
    branch = net["branch"]
    normal = branch / np.linalg.norm(branch, axis=1)[:, None]
    if contacts:
        fabric = np.einsum("ka,kb->ab", normal[contact], normal[contact]) / contacts
        for a_, b_ in ((0, 0), (1, 1), (2, 2), (0, 1)):
            print("fabric_%s%s=%.6g" % ("xyz"[a_], "xyz"[b_], fabric[a_, b_]))
    if edges is not None:
        volume = abs(np.linalg.det(edges))
        print("stress_unit=%s" % unit.replace("*a^2", ""))
        for name, normal_key, vector_key in PARTS:
            force = (normal * net[normal_key][:, None]) if normal_key else net[vector_key]
            sigma = force.T @ branch / volume  # sigma_ab = sum F_a branch_b / V
            print("stress_%s_xy=%.6g" % (name, sigma[0, 1]))
            print("stress_%s_yy=%.6g" % (name, sigma[1, 1]))
    if contacts:
        fn = -net["force_normal_contact"][contact]  # repulsive: positive
        hist, bounds = np.histogram(fn / fn.mean(), bins=a.bins, range=(0.0, 4.0))
        print("contact_force_mean=%.6g  # %s" % (fn.mean(), unit))
        for k in range(a.bins):
            print("contact_force_hist_%.2f_%.2f=%.6g"
                  % (bounds[k], bounds[k + 1], hist[k] / contacts))
        print("contact_force_above_%.2f=%.6g" % (bounds[-1], np.mean(fn / fn.mean() > 4.0)))


def series(path):
    """frame_K_<figure>=value lines for every frame of the network in path."""
    with h5py.File(path, "r") as f:
        if "pair_network" not in f:
            raise SystemExit("%s has no /pair_network" % path)
        g = f["pair_network"]
        idx = {key: g[key][()] for key in ("step", "time", "row_start", "row_count")}
        contact, sliding = g["contact"][()] == 1, g["sliding"][()] == 1
        j = g["j"][()]
        n = len(f["particles/all/radius"]) if "particles/all/radius" in f else None
    print("frames=%d" % len(idx["step"]))
    for k in range(len(idx["step"])):
        rows = slice(int(idx["row_start"][k]), int(idx["row_start"][k] + idx["row_count"][k]))
        c = int(contact[rows].sum())
        print("frame_%d_step=%d" % (k, idx["step"][k]))
        print("frame_%d_time=%.9g" % (k, idx["time"][k]))
        print("frame_%d_pairs=%d" % (k, idx["row_count"][k]))
        print("frame_%d_contacts=%d" % (k, c))
        if n:
            print("frame_%d_Z_contact=%.6g" % (k, ends_on_particles(j[rows][contact[rows]], n) / n))
        print("frame_%d_sliding_fraction=%.6g"
              % (k, sliding[rows][contact[rows]].mean() if c else 0.0))


if __name__ == "__main__":
    main()
