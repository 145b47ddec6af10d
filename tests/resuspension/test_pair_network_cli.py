#!/usr/bin/env python3
"""The interaction network of the resuspension scene (/pair_network in result.h5, spec member
/pair_network; engine/pair_network.h, engine/network_output.h) through the CLI (fast suite):
 1. "snapshots", gradient orientation: a frame with every particle snapshot, at its step; in
    each, i < j, i a free particle, j a free particle or a floor sphere (index >= n); for two
    free particles the branch vector is x_j - x_i of that snapshot's unwrapped positions up to
    a cell vector (integer multiples of the edges, to 1e-9 a) and the centre gap is
    |branch| - r_i - r_j, and the pairs of free particles are exactly those a brute force
    (minimum image) finds inside the cut-off; contact flags follow gap < eps a, sliding
    contacts sit at the Coulomb limit; units are stated;
 2. the same spec without /pair_network: no group, and the same summary results and time
    series (the network changes nothing in the run);
 3. "final": one frame, equal bit for bit to the last frame of 1;
 4. 1 stopped by SIGTERM and continued with --resume: the same frames as 1, bit for bit;
    4b. a run stopped and continued with /strain equal to the strain done: the series and
    results of a run made straight to it, no sample, snapshot or frame taken twice;
 5. the vorticity orientation (a sheared cell), "final": branch vectors as in 1;
 6. the clients: client_examples/pair_network.py gives the coordination of the free particles,
    a pair with a floor sphere counted once (Z_contact and the --series lines; they used to
    count it twice), and client_examples/read_result.py reads a failed run's file whose
    network has no frame (it used to raise IndexError).
Usage: test_pair_network_cli.py LUBDEM WORKDIR"""
import json
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "framework"))
from network_cli import FAIL, check, frame, load, observables, stop_midway  # noqa: E402
from network_cli import run as run_spec  # noqa: E402


def run(lubdem, work, name, spec):
    return run_spec(lubdem, work, name, dict(spec, scene="resuspension"), "--threads", "1")


def check_frame(name, fk, snap, at):
    law = snap["spec"]["law"]
    eps, mu, cutoff = law["eps"], law["mu"], snap["spec"]["cutoff"]
    x, edges, r = snap["position/value"][at], snap["box/edges/value"][at], snap["radius"]
    n = len(r)
    i, j = fk["i"], fk["j"]
    check(len(i) > 0 and np.all(i < j) and np.all(i < n), name + ": i < j, i a free particle")
    free = j < n
    check(np.any(~free), name + ": pairs with floor spheres (j >= n) are there")
    d = fk["branch"][free] - (x[j[free]] - x[i[free]])
    m = d @ np.linalg.inv(edges)  # rows of edges are the cell vectors
    check(np.abs(m - np.round(m)).max() < 1e-9,
          name + ": branch = x_j - x_i up to a cell vector (%.2e)" % np.abs(m - np.round(m)).max())
    cg = np.linalg.norm(fk["branch"][free], axis=1) - r[i[free]] - r[j[free]]
    check(np.abs(cg - fk["centre_gap"][free]).max() < 1e-12, name + ": centre gap")
    a = 0.5 * (r[i[free]] + r[j[free]])
    check(np.all((fk["gap"][free] < eps * a) == (fk["contact"][free] == 1)),
          name + ": contact exactly when gap < eps a")
    fs = np.linalg.norm(fk["force_tangential_contact"], axis=1)
    lim = mu * np.abs(fk["force_normal_contact"])
    sl = fk["sliding"] == 1
    check(np.all(fk["contact"][sl] == 1) and
          (not sl.any() or np.abs(fs[sl] - lim[sl]).max() <= 1e-12 * (1 + lim[sl].max())) and
          np.all(fs[~sl] <= lim[~sl] * (1 + 1e-12)),
          name + ": sliding contacts at mu |F_c|, the others below it")
    # brute force over the free particles (minimum image in the cell)
    ii, jj = np.triu_indices(n, 1)
    s = (x[jj] - x[ii]) @ np.linalg.inv(edges)
    s -= np.round(s)
    un = np.linalg.norm(s @ edges, axis=1) - r[ii] - r[jj]
    keep = un <= cutoff * 0.5 * (r[ii] + r[jj])
    want = set(zip(ii[keep].tolist(), jj[keep].tolist()))
    got = set(zip(i[free].tolist(), j[free].tolist()))
    check(got == want, name + ": the free pairs inside the cut-off (%d; brute force %d)"
          % (len(got), len(want)))


def main():
    lubdem, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    # 2 strain: long enough (a few seconds) for the stop of 4 to land inside the run
    base = {"n": 150, "width": 12, "strain": 2, "average_from": 0.2, "sample_strain": 0.05,
            "inertial_number": 0.05, "density_ratio": 10, "shear_drag_viscosity": 3,
            "snapshots": 4}

    # 1. a frame with every snapshot
    out = run(lubdem, work, "snapshots", dict(base, pair_network="snapshots"))
    net, snap = load(out)
    summ = json.load(open(os.path.join(out, "summary.json")))
    check(net is not None, "snapshots: /pair_network written")
    if net is None:
        return 1
    frames = len(net["step"])
    check(frames == 4 and np.array_equal(net["step"], snap["position/step"]) and
          np.array_equal(net["row_start"],
                         np.concatenate([[0], np.cumsum(net["row_count"])[:-1]])),
          "snapshots: a frame at each snapshot's step (%s; snapshots %s)"
          % (net["step"].tolist(), snap["position/step"].tolist()))
    for k in range(min(frames, len(snap["position/step"]))):
        check_frame("snapshots frame %d" % k, frame(net, k), snap, k)
    u = snap["units"]
    check(u["force_normal_contact"] == "eta*gd*a^2" and u["time"] == "1/gd" and
          u["torque_roll"] == "eta*gd*a^3" and u["branch"] == "a", "units %s" % u)
    print("pair_network_frames=%d" % frames)
    print("pair_network_rows_last=%d" % net["row_count"][-1])

    # 2. without it: the same run
    out2 = run(lubdem, work, "without", base)
    plain, _ = load(out2)
    s2 = json.load(open(os.path.join(out2, "summary.json")))
    obs, obs2 = observables(out), observables(out2)
    check(plain is None and s2["results"] == summ["results"] and len(obs) > 0 and
          sorted(obs) == sorted(obs2) and all(np.array_equal(obs[k], obs2[k]) for k in obs),
          "without: no group, the same results and time series")

    # 3. final only
    out3 = run(lubdem, work, "final", dict(base, pair_network="final"))
    fnet, _ = load(out3)
    last = frame(net, frames - 1)
    check(fnet is not None and len(fnet["step"]) == 1 and
          all(np.array_equal(last[k], fnet[k]) for k in fnet if k != "row_start"),
          "final: one frame, equal bit for bit to the last of \"snapshots\"")

    # 4. stopped and continued
    out4, code = stop_midway(lubdem, work, "resumed",
                             dict(base, scene="resuspension", pair_network="snapshots"), 0.3, 0.9,
                             "--threads", "1")
    path = os.path.join(work, "resumed.json")
    tnet, _ = load(out4)
    st = json.load(open(os.path.join(out4, "summary.json")))
    check(code == 5 and tnet is not None and int(tnet["step"][-1]) == st["steps"],
          "resumed: stopped (exit %s) with the network of its stop (%s, steps %s)"
          % (code, tnet["step"].tolist() if tnet else None, st.get("steps")))
    p = subprocess.run([lubdem, "run", path, "--out", out4, "--quiet", "--threads", "1",
                        "--resume"], capture_output=True, text=True, timeout=600)
    rnet, _ = load(out4)
    check(p.returncode == 0 and rnet is not None and sorted(rnet) == sorted(net) and
          all(np.array_equal(rnet[k], net[k]) for k in net),
          "resumed: the continuation's frames equal the uninterrupted run's bit for bit (exit %s, "
          "steps %s against %s)" % (p.returncode, rnet["step"].tolist() if rnet else None,
                                    net["step"].tolist()))

    # 4b. stopped and continued with /strain equal to the strain done (a sample every step, so
    # that the stop's step has one): the samples of that step are not taken again, and the
    # series and results are those of a run made straight to that strain (until 2026-12-07 the
    # end forced them a second time: one row and one averaged profile too many)
    every = dict(base, sample_strain=1e-5, snapshots=3,
                 pair_network="snapshots")
    outb, code = stop_midway(lubdem, work, "resumed_at_done",
                             dict(every, scene="resuspension"), 0.3, 0.9, "--threads", "1")
    done = float(observables(outb)["center_of_mass_height/time"][-1]) if code == 5 else None
    check(code == 5, "resumed at the strain done: stopped (exit %s)" % code)
    if done is not None:
        with open(os.path.join(work, "resumed_at_done.json"), "w") as f:
            json.dump(dict(every, scene="resuspension", strain=done), f)
        p = subprocess.run([lubdem, "run", os.path.join(work, "resumed_at_done.json"), "--out",
                            outb, "--quiet", "--threads", "1", "--resume"],
                           capture_output=True, text=True, timeout=600)
        straight = run(lubdem, work, "straight_to_done", dict(every, strain=done))
        ob, os_ = observables(outb), observables(straight)
        sb = json.load(open(os.path.join(outb, "summary.json")))
        ss = json.load(open(os.path.join(straight, "summary.json")))
        bnet, bsnap = load(outb)
        rows, rows_straight = len(ob["center_of_mass_height/step"]), len(os_["center_of_mass_height/step"])
        check(p.returncode == 0 and sb["steps"] == ss["steps"] and rows == rows_straight and
              sorted(ob) == sorted(os_) and all(np.array_equal(ob[k], os_[k]) for k in ob) and
              sb["results"] == ss["results"],
              "resumed at the strain done: the series and results of the run made straight "
              "(exit %s, steps %s / %s, rows %d / %d, averaged samples %s / %s)"
              % (p.returncode, sb.get("steps"), ss.get("steps"), rows, rows_straight,
                 sb["results"].get("averaged_samples"), ss["results"].get("averaged_samples")))
        check(bnet is not None and np.all(np.diff(bnet["step"]) > 0) and
              np.all(np.diff(bsnap["position/step"]) > 0),
              "resumed at the strain done: no snapshot or network frame taken twice (frames %s, "
              "snapshots %s)" % (bnet["step"].tolist() if bnet else None,
                                 bsnap["position/step"].tolist() if bsnap else None))

    # 5. vorticity orientation: a sheared cell
    out5 = run(lubdem, work, "vorticity", dict(base, orientation="vorticity",
                                               pair_network="final", snapshots=2))
    vnet, vsnap = load(out5)
    check(vnet is not None and len(vnet["step"]) == 1 and
          int(vnet["step"][0]) == int(vsnap["position/step"][-1]),
          "vorticity: one frame at the last snapshot's step")
    if vnet is not None:
        check_frame("vorticity", frame(vnet, 0), vsnap, -1)

    # 6. the clients
    clients = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                           "client_examples")
    h5 = os.path.join(out, "result.h5")

    def figures(*argv):
        p = subprocess.run([sys.executable, os.path.join(clients, argv[0]), *argv[1:]],
                           capture_output=True, text=True, timeout=120)
        return p.returncode, p.stdout, dict(line.split("=", 1) for line in p.stdout.splitlines()
                                            if "=" in line and " " not in line.split("=")[0])
    n = len(snap["radius"])
    ends = []
    for k in range(frames):
        fk = frame(net, k)
        jc = fk["j"][fk["contact"] == 1]
        ends.append(2 * int((jc < n).sum()) + int((jc >= n).sum()))
    floor_contacts = sum(int((frame(net, k)["j"][frame(net, k)["contact"] == 1] >= n).sum())
                         for k in range(frames))
    code, _, one = figures("pair_network.py", h5)
    code2, _, ser = figures("pair_network.py", h5, "--series")
    check(code == 0 and code2 == 0 and floor_contacts > 0 and
          abs(float(one.get("Z_contact", "nan")) - ends[-1] / n) < 1e-5 and
          all(abs(float(ser.get("frame_%d_Z_contact" % k, "nan")) - ends[k] / n) < 1e-5
              for k in range(frames)),
          "clients: Z_contact of the %d particles counts a floor contact once (%s; ends %s, "
          "%d floor contacts in all)" % (n, one.get("Z_contact"), ends, floor_contacts))
    # a step far too large: exit 3 (numerical failure) with a network group of no frame
    bad = os.path.join(work, "failed")
    with open(bad + ".json", "w") as f:
        json.dump({"scene": "resuspension", "n": 100, "width": 12, "strain": 0.5,
                   "average_from": 0.1, "dt": 0.5, "pair_network": "final"}, f)
    p = subprocess.run([lubdem, "run", bad + ".json", "--out", bad, "--quiet"],
                       capture_output=True, text=True, timeout=600)
    check(p.returncode == 3, "failed: exit %s (3 expected) %s" % (p.returncode, p.stderr[-200:]))
    empty, _ = load(bad)
    code, text, _ = figures("read_result.py", os.path.join(bad, "result.h5"))
    check(empty is not None and len(empty["step"]) == 0 and code == 0 and
          "pair network: no frame" in text,
          "clients: read_result.py reads a failed run's network of no frame (exit %s)" % code)
    return 1 if FAIL else 0



if __name__ == "__main__":
    sys.exit(main())
