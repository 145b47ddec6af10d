#!/usr/bin/env python3
"""The interaction network of simple_shear (/pair_network in result.h5, spec member
/pair_network; engine/pair_network.h) through the CLI (fast suite):
 1. imposed volume, cut-off set: the network's step is the last snapshot's and the run's last;
    with that snapshot's positions and box, every branch vector is x_j + H image - x_i and
    every centre gap |branch| - r_i - r_j (to 1e-12 a); the pairs are exactly those a brute
    force over all pairs (minimum image) finds inside the cut-off; contact flags follow
    gap < eps a, sliding contacts sit at the Coulomb limit; units are stated;
 2. imposed pressure with the Delaunay set: the pairs are a subset of those inside the cut-off,
    forces in units of P a^2;
 3. without /pair_network (the default) there is no /pair_network group, and the network does
    not change the run: the summaries of 1 and of the same spec without it are equal;
 4. a completed run without the network (--keep-checkpoint), extended with --resume to a
    larger /strain with /pair_network true (a continuation may change it), ends with the
    network, equal bit for bit to that of the run asked for the larger strain with it;
 5. a run stopped by SIGTERM (exit 5, partial) writes the network of the state it stopped in,
    at the step of its last snapshot, with records consistent with that snapshot;
 6. client_examples/pair_network.py on the network of 1: its pair and contact counts, Z_c, a
    fabric of trace 1 and the four parts' sigma_xy and sigma_yy equal those computed here.
The element-by-element agreement of the forces with the next step's stress sample is checked
in C (shear.pair_network). Usage: test_pair_network_cli.py LUBDEM WORKDIR [--sanitized]"""
import json
import os
import shutil
import signal
import subprocess
import sys

import h5py
import numpy as np

FAIL = []


def check(cond, what):
    if not cond:
        FAIL.append(what)
        print("FAIL:", what)


def run(lubdem, work, name, spec, *extra, fresh=True):
    out = os.path.join(work, name)
    if fresh:
        shutil.rmtree(out, ignore_errors=True)
    path = os.path.join(work, name + ".json")
    with open(path, "w") as f:
        json.dump(dict(spec, scene="simple_shear"), f)
    p = subprocess.run([lubdem, "run", path, "--out", out, "--quiet", *extra],
                       capture_output=True, text=True, timeout=600)
    check(p.returncode == 0, "%s: exit %s: %s" % (name, p.returncode, p.stderr[-500:]))
    return out


def network(out):
    with h5py.File(os.path.join(out, "result.h5"), "r") as f:
        if "pair_network" not in f:
            return None, None
        g = f["pair_network"]
        net = {k: g[k][()] for k in g}
        units = {k: g[k].attrs["unit"] for k in g}
        units = {k: (u.decode() if isinstance(u, bytes) else u) for k, u in units.items()}
        snap = {k: f["particles/all/" + k][()] for k in
                ("position/value", "position/step", "box/edges/value", "radius")}
    return net, dict(snap, units=units)


def inside_cutoff(x, edges, r, cutoff):
    """(i, j) of every pair whose nearest-image centre gap is <= cutoff * a_ij."""
    H = edges.T  # columns: edge vectors
    Hinv = np.linalg.inv(H)
    ii, jj = np.triu_indices(len(r), 1)
    s = (x[jj] - x[ii]) @ Hinv.T
    s -= np.round(s)
    d = s @ H.T
    un = np.linalg.norm(d, axis=1) - r[ii] - r[jj]
    keep = un <= cutoff * 0.5 * (r[ii] + r[jj])
    return set(zip(ii[keep].tolist(), jj[keep].tolist()))


def check_records(name, net, snap, eps, mu):
    x = snap["position/value"][-1]
    edges = snap["box/edges/value"][-1]
    r = snap["radius"]
    i, j = net["i"], net["j"]
    check(np.all(i < j) and i.min() >= 0 and j.max() < len(r), name + ": indices i < j < n")
    br = x[j] + net["image"] @ edges - x[i]
    check(np.abs(br - net["branch"]).max() <= 1e-12 * np.abs(x).max(),
          name + ": branch = x_j + H image - x_i with the last snapshot (%.3g)"
          % np.abs(br - net["branch"]).max())
    cg = np.linalg.norm(net["branch"], axis=1) - r[i] - r[j]
    check(np.abs(cg - net["centre_gap"]).max() <= 1e-12,
          name + ": centre gap = |branch| - r_i - r_j")
    a = 0.5 * (r[i] + r[j])
    check(np.all((net["gap"] < eps * a) == (net["contact"] == 1)),
          name + ": contact exactly when gap < eps a")
    fs = np.linalg.norm(net["force_tangential_contact"], axis=1)
    lim = mu * np.abs(net["force_normal_contact"])
    sl = net["sliding"] == 1
    check(sl.any() and np.all(net["contact"][sl] == 1) and
          np.abs(fs[sl] - lim[sl]).max() <= 1e-12 * (1 + lim[sl].max()) and
          np.all(fs[~sl] <= lim[~sl] * (1 + 1e-12)),
          name + ": sliding contacts at mu |F_c|, the others below it (%d sliding)" % sl.sum())
    check(np.all(net["force_normal_contact"] <= 0), name + ": contact forces repulsive (<= 0)")


def check_example(out, net, snap):
    """6: client_examples/pair_network.py on the network of `out`."""
    example = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                           "client_examples", "pair_network.py")
    p = subprocess.run([sys.executable, example, os.path.join(out, "result.h5")],
                       capture_output=True, text=True, timeout=120)
    vals = dict(line.split("#")[0].strip().split("=", 1) for line in p.stdout.splitlines()
                if "=" in line)
    contacts = int(np.sum(net["contact"] == 1))
    n = len(snap["radius"])
    fabric = sum(float(vals.get("fabric_%s" % k, "nan")) for k in ("xx", "yy", "zz"))
    edges = snap["box/edges/value"][-1]
    volume = abs(np.linalg.det(edges))
    nvec = net["branch"] / np.linalg.norm(net["branch"], axis=1)[:, None]
    parts = {"normal_contact": nvec * net["force_normal_contact"][:, None],
             "tangential_contact": net["force_tangential_contact"],
             "normal_lubrication": nvec * net["force_normal_lubrication"][:, None],
             "tangential_lubrication": net["force_tangential_lubrication"]}
    worst = 0.0
    for name, force in parts.items():
        for comp, (a, b) in (("xy", (0, 1)), ("yy", (1, 1))):
            want = np.sum(force[:, a] * net["branch"][:, b]) / volume
            got = float(vals.get("stress_%s_%s" % (name, comp), "nan"))
            worst = max(worst, abs(got - want) / max(abs(want), 1e-300))
    check(p.returncode == 0 and int(vals.get("pairs", -1)) == len(net["i"]) and
          int(vals.get("contacts", -1)) == contacts and
          abs(float(vals.get("Z_contact", "nan")) - 2.0 * contacts / n) < 1e-5 and
          abs(fabric - 1.0) < 1e-5 and worst < 1e-5,
          "example: pair_network.py agrees (exit %s, stress parts within %.1e): %s"
          % (p.returncode, worst, p.stderr[-300:]))


def main():
    lubdem, work = sys.argv[1], sys.argv[2]
    sanitized = "--sanitized" in sys.argv
    os.makedirs(work, exist_ok=True)
    strain = 0.4 if sanitized else 1.0
    base = {"n_particles": 300, "phi": 0.52, "stiffness": 1e4, "strain": strain,
            "snapshots": 2, "transient_strain": 0.1, "sample_strain": 0.02}

    # 1. imposed volume, cut-off set
    out = run(lubdem, work, "volume", dict(base, pair_network=True))
    net, snap = network(out)
    summ = json.load(open(os.path.join(out, "summary.json")))
    check(net is not None, "volume: /pair_network written")
    if net is not None:
        check(int(net["step"][0]) == int(snap["position/step"][-1]) == summ["steps"],
              "volume: the network's step (%s) is the last snapshot's (%s) and the run's (%s)"
              % (net["step"][0], snap["position/step"][-1], summ["steps"]))
        check_records("volume", net, snap, 0.02, 0.5)
        want = inside_cutoff(snap["position/value"][-1], snap["box/edges/value"][-1],
                             snap["radius"], 2.0)
        got = set(zip(net["i"].tolist(), net["j"].tolist()))
        check(got == want and len(got) == len(net["i"]),
              "volume: the pairs are those inside the cut-off (%d; brute force %d, missing %d, "
              "extra %d)" % (len(got), len(want), len(want - got), len(got - want)))
        u = snap["units"]
        check(u["force_normal_contact"] == "eta*gd*a^2" and u["branch"] == "a" and
              u["time"] == "1/gd" and u["torque_roll"] == "eta*gd*a^3",
              "volume: units %s" % u)
        print("pair_network_pairs=%d" % len(got))
        check_example(out, net, snap)

    # 2. imposed pressure, Delaunay set
    out = run(lubdem, work, "pressure", dict(base, control="pressure", Iv=0.1, pair_network=True,
                                             lubrication_pairs="delaunay", phi=0.45))
    pnet, psnap = network(out)
    check(pnet is not None, "pressure: /pair_network written")
    if pnet is not None:
        check_records("pressure", pnet, psnap, 0.02, 0.5)
        want = inside_cutoff(psnap["position/value"][-1], psnap["box/edges/value"][-1],
                             psnap["radius"], 2.0)
        got = set(zip(pnet["i"].tolist(), pnet["j"].tolist()))
        check(0 < len(got) < len(want) and got <= want,
              "pressure: the Delaunay pairs (%d) are a subset of those inside the cut-off (%d)"
              % (len(got), len(want)))
        check(psnap["units"]["force_tangential_lubrication"] == "P*a^2" and
              psnap["units"]["time"] == "eta/P", "pressure: units %s" % psnap["units"])

    # 3. not asked for: no group, and the same run
    out = run(lubdem, work, "without", base)
    plain, _ = network(out)
    check(plain is None, "without: no /pair_network")
    s2 = json.load(open(os.path.join(out, "summary.json")))
    check(s2["results"] == summ["results"] and s2["steps"] == summ["steps"],
          "without: the network does not change the run's results")

    # 4. added by an extension
    first = dict(base, strain=0.5 * strain)
    out = run(lubdem, work, "extended", first, "--keep-checkpoint")
    check(os.path.exists(os.path.join(out, "checkpoint.h5")), "extended: checkpoint kept")
    run(lubdem, work, "extended", dict(base, pair_network=True), "--resume", fresh=False)
    enet, esnap = network(out)
    check(enet is not None and net is not None and
          all(np.array_equal(enet[k], net[k]) for k in net),
          "extended: the extension's network equals the longer run's, bit for bit")

    # 5. stopped by SIGTERM once past a third of a longer run
    out = os.path.join(work, "stopped")
    shutil.rmtree(out, ignore_errors=True)
    path = os.path.join(work, "stopped.json")
    with open(path, "w") as f:
        json.dump(dict(base, scene="simple_shear", strain=10 * strain, pair_network=True), f)
    proc = subprocess.Popen([lubdem, "run", path, "--out", out], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    for line in proc.stdout:
        if line.startswith("progress ") and 0.3 <= float(line.split("fraction=")[1].split()[0]) < 1:
            proc.send_signal(signal.SIGTERM)
            break
    proc.communicate(timeout=600)
    snet, ssnap = network(out)
    st = json.load(open(os.path.join(out, "summary.json")))
    check(proc.returncode == 5 and st["status"] == "partial" and snet is not None and
          int(snet["step"][0]) == int(ssnap["position/step"][-1]) == st["steps"],
          "stopped: exit %s, %s, network at step %s (last snapshot %s, steps %s)"
          % (proc.returncode, st["status"], snet["step"][0] if snet else None,
             ssnap["position/step"][-1] if ssnap else None, st["steps"]))
    if snet is not None:
        check_records("stopped", snet, ssnap, 0.02, 0.5)
    return 1 if FAIL else 0


if __name__ == "__main__":
    sys.exit(main())
