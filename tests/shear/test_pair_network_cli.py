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
    fabric of trace 1 and the four parts' sigma_xy and sigma_yy equal those computed here;
 7. "pair_network": "snapshots": a frame with every particle snapshot (the first at step 0),
    each at its snapshot's step, with records consistent with that snapshot and exactly the
    pairs inside the cut-off; the frames' rows are numbered as row_start and row_count say;
    the run's summary results and time series are those of the same run with "final" only,
    whose network equals the last frame bit for bit; the time series' Z and Z_contact at the
    samples nearest the frames are the frames' 2 x pairs / N and 2 x contacts / N; "final" writes one frame, true is read
    as "final" (the resolved spec says so); a value out of the enum is refused naming
    /pair_network; client_examples/pair_network.py --frame 2 reads frame 2 (its step, counts
    and stress parts with that snapshot's box), --series every frame's counts;
 8. that run stopped by SIGTERM and continued with --resume: the continuation's file holds
    the same frames as the uninterrupted run's, bit for bit (the stopped run's copied, then
    its own), and the stopped run's file ends with the network of its stop;
 9. that run under a file-size limit (RLIMIT_FSIZE) 64 MiB + 1.2 MB: the frames that would
    come within 64 MiB of it are skipped (the first ones written), the run completes with its
    snapshots and results, and the summary's warnings say how many frames from which step.
The element-by-element agreement of the forces with the next step's stress sample is checked
in C (shear.pair_network). Usage: test_pair_network_cli.py LUBDEM WORKDIR [--sanitized]"""
import json
import os
import resource
import shutil
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "framework"))
from network_cli import FAIL, check, frame, observables, stop_midway  # noqa: E402
from network_cli import load as network  # noqa: E402
from network_cli import run as run_spec  # noqa: E402


def run(lubdem, work, name, spec, *extra, fresh=True):
    return run_spec(lubdem, work, name, dict(spec, scene="simple_shear"), *extra, fresh=fresh)


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


def check_records(name, net, snap, eps, mu, at=-1):
    """net: one frame; at: the index of its particle snapshot."""
    x = snap["position/value"][at]
    edges = snap["box/edges/value"][at]
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
    check((sl.any() or at == 0) and np.all(net["contact"][sl] == 1) and
          np.abs(fs[sl] - lim[sl]).max() <= 1e-12 * (1 + lim[sl].max()) and
          np.all(fs[~sl] <= lim[~sl] * (1 + 1e-12)),
          name + ": sliding contacts at mu |F_c|, the others below it (%d sliding)" % sl.sum())
    check(np.all(net["force_normal_contact"] <= 0), name + ": contact forces repulsive (<= 0)")


def check_frames(name, net, snap):
    """7, 8: one frame per snapshot, at its step, consistent with it, the rows numbered as
    the index says; each frame's pairs are those inside the cut-off."""
    frames = len(net["step"])
    starts = np.concatenate([[0], np.cumsum(net["row_count"])[:-1]])
    check(frames == len(snap["position/step"]) and
          np.array_equal(net["step"], snap["position/step"]) and
          np.array_equal(net["row_start"], starts) and
          int(net["row_count"].sum()) == len(net["i"]),
          "%s: a frame at each snapshot's step (%s; snapshots %s), rows as indexed"
          % (name, net["step"].tolist(), snap["position/step"].tolist()))
    if frames != len(snap["position/step"]):
        return
    for k in range(frames):
        fk = frame(net, k)
        check_records("%s frame %d" % (name, k), fk, snap, 0.02, 0.5, at=k)
        want = inside_cutoff(snap["position/value"][k], snap["box/edges/value"][k],
                             snap["radius"], 2.0)
        got = set(zip(fk["i"].tolist(), fk["j"].tolist()))
        check(got == want and len(got) == len(fk["i"]),
              "%s frame %d: the pairs inside the cut-off (%d; brute force %d)"
              % (name, k, len(got), len(want)))


def same_observables(out_a, out_b):
    a, b = observables(out_a), observables(out_b)
    return len(a) > 0 and sorted(a) == sorted(b) and all(np.array_equal(a[k], b[k]) for k in a)


def check_example(out, net, snap, k=None):
    """6, 7: client_examples/pair_network.py on frame k (None: its default, the last; net is
    that frame, snap the particle snapshots) of the network of `out`."""
    example = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                           "client_examples", "pair_network.py")
    p = subprocess.run([sys.executable, example, os.path.join(out, "result.h5")] +
                       (["--frame", str(k)] if k is not None else []),
                       capture_output=True, text=True, timeout=120)
    vals = dict(line.split("#")[0].strip().split("=", 1) for line in p.stdout.splitlines()
                if "=" in line)
    contacts = int(np.sum(net["contact"] == 1))
    n = len(snap["radius"])
    fabric = sum(float(vals.get("fabric_%s" % k, "nan")) for k in ("xx", "yy", "zz"))
    at = -1 if k is None else k
    edges = snap["box/edges/value"][at]
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
          int(vals.get("step", -1)) == int(snap["position/step"][at]) and
          int(vals.get("contacts", -1)) == contacts and
          abs(float(vals.get("Z_contact", "nan")) - 2.0 * contacts / n) < 1e-5 and
          abs(fabric - 1.0) < 1e-5 and worst < 1e-5,
          "example: pair_network.py agrees (exit %s, stress parts within %.1e): %s"
          % (p.returncode, worst, p.stderr[-300:]))


def check_series(out, net, n):
    """7: client_examples/pair_network.py --series: every frame's step, pairs, contacts, Z_c."""
    example = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                           "client_examples", "pair_network.py")
    p = subprocess.run([sys.executable, example, os.path.join(out, "result.h5"), "--series"],
                       capture_output=True, text=True, timeout=120)
    vals = dict(line.split("=", 1) for line in p.stdout.splitlines() if "=" in line)
    good = p.returncode == 0 and int(vals.get("frames", -1)) == len(net["step"])
    for k in range(len(net["step"])):
        fk = frame(net, k)
        c = int(np.sum(fk["contact"] == 1))
        good = good and int(vals.get("frame_%d_step" % k, -1)) == int(fk["step"][0]) and \
            int(vals.get("frame_%d_pairs" % k, -1)) == len(fk["i"]) and \
            int(vals.get("frame_%d_contacts" % k, -1)) == c and \
            abs(float(vals.get("frame_%d_Z_contact" % k, "nan")) - 2.0 * c / n) < 1e-5
    check(good, "example: pair_network.py --series agrees with every frame (exit %s: %s)"
          % (p.returncode, p.stderr[-300:]))


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
    # ... also with Delaunay pairs when the final frame falls on a step whose update is due
    # (506 steps here): the update that frame does is not counted (until 2026-12-06
    # delaunay_updates was 49 with the frame and 48 without, and the fractions moved)
    due = {"n_particles": 300, "phi": 0.52, "stiffness": 1e4, "strain": 0.22, "snapshots": 2,
           "transient_strain": 0.1, "sample_strain": 0.02, "lubrication_pairs": "delaunay"}
    sd = [json.load(open(os.path.join(run(lubdem, work, "due_" + nw, dict(due, pair_network=nw)),
                                      "summary.json"))) for nw in ("none", "final")]
    check(sd[0]["results"] == sd[1]["results"] and sd[0]["steps"] == sd[1]["steps"],
          "delaunay: the final frame does not change the results (updates %s / %s, %s steps)"
          % (sd[0]["results"]["delaunay_updates"]["value"],
             sd[1]["results"]["delaunay_updates"]["value"], sd[1]["steps"]))

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
    out, code = stop_midway(lubdem, work, "stopped", dict(base, scene="simple_shear",
                                                          strain=10 * strain, pair_network=True),
                            0.3, 1.0)
    snet, ssnap = network(out)
    st = json.load(open(os.path.join(out, "summary.json")))
    check(code == 5 and st["status"] == "partial" and snet is not None and
          int(snet["step"][0]) == int(ssnap["position/step"][-1]) == st["steps"],
          "stopped: exit %s, %s, network at step %s (last snapshot %s, steps %s)"
          % (code, st["status"], snet["step"][0] if snet else None,
             ssnap["position/step"][-1] if ssnap else None, st["steps"]))
    if snet is not None:
        check_records("stopped", snet, ssnap, 0.02, 0.5)

    # 7. a frame at every snapshot
    every = dict(base, strain=3 * strain, snapshots=5)
    out_all = run(lubdem, work, "snapshots", dict(every, pair_network="snapshots"))
    anet, asnap = network(out_all)
    out_final = run(lubdem, work, "final", dict(every, pair_network="final"))
    fnet, _ = network(out_final)
    sa = json.load(open(os.path.join(out_all, "summary.json")))
    sf = json.load(open(os.path.join(out_final, "summary.json")))
    check(anet is not None and fnet is not None, "snapshots, final: /pair_network written")
    if anet is not None and fnet is not None:
        check_frames("snapshots", anet, asnap)
        check_example(out_all, frame(anet, 2), asnap, k=2)
        check_series(out_all, anet, len(asnap["radius"]))
        # the time series' coordination and contact numbers (2 x pairs / N) against the frames'
        # pairs and contacts at the sample nearest each frame after the first (a coordination
        # number without its factor 2 went unnoticed by the fast suite); Z moves by < 1 % and
        # Z_contact by < 15 % between a frame and its nearest sample in this run
        with h5py.File(os.path.join(out_all, "result.h5"), "r") as f:
            obs = {k: f["observables/" + k][()] for k in
                   ("Z/step", "Z/value", "Z_contact/value")}
        n = len(asnap["radius"])
        near = []
        for k in range(1, len(anet["step"])):
            at = int(np.argmin(np.abs(obs["Z/step"] - int(anet["step"][k]))))
            fk = frame(anet, k)
            near.append((round(float(obs["Z/value"][at]), 3), round(2.0 * len(fk["i"]) / n, 3),
                         round(float(obs["Z_contact/value"][at]), 3),
                         round(2.0 * int(fk["contact"].sum()) / n, 3)))
        print("coordination against frames:", near)
        check(len(near) >= 3 and all(abs(z - zf) < 0.03 * zf and abs(zc - zcf) < 0.25 * zcf
                                     for z, zf, zc, zcf in near),
              "snapshots: Z and Z_contact of the samples nearest the frames are the frames' "
              "2 x pairs / N and 2 x contacts / N ((Z, frame, Z_contact, frame): %s)" % near)
        check(int(anet["step"][0]) == 0 and int(anet["step"][-1]) == sa["steps"] and
              len(anet["step"]) == 6,
              "snapshots: 6 frames (5 snapshots and the initial state) from step 0 to the last "
              "(%s)" % anet["step"].tolist())
        last = frame(anet, len(anet["step"]) - 1)
        check(len(fnet["step"]) == 1 and int(fnet["row_start"][0]) == 0 and
              all(np.array_equal(last[k], fnet[k]) for k in fnet if k != "row_start"),
              "final: one frame, equal bit for bit to the last of \"snapshots\"")
        check(sa["results"] == sf["results"] and sa["steps"] == sf["steps"] and
              same_observables(out_all, out_final),
              "snapshots: the frames do not change the run (results, steps, time series)")
    with h5py.File(os.path.join(out, "result.h5"), "r") as f:
        resolved = json.loads(f["parameters/spec_resolved"][()])
    check(resolved.get("pair_network") == "final", "true is read as \"final\" (%s)"
          % resolved.get("pair_network"))
    bad = os.path.join(work, "bad.json")
    with open(bad, "w") as f:
        json.dump(dict(base, scene="simple_shear", pair_network="sometimes"), f)
    p = subprocess.run([lubdem, "run", bad, "--out", os.path.join(work, "bad")],
                       capture_output=True, text=True, timeout=60)
    check(p.returncode == 2 and "/pair_network" in p.stderr and "snapshots" in p.stderr,
          "bad value refused naming /pair_network (exit %s: %s)" % (p.returncode,
                                                                   p.stderr.strip()[-200:]))

    # 8. stopped and continued
    out, code = stop_midway(lubdem, work, "resumed",
                            dict(every, scene="simple_shear", pair_network="snapshots"), 0.45, 1.0)
    path = os.path.join(work, "resumed.json")
    tnet, tsnap = network(out)
    st = json.load(open(os.path.join(out, "summary.json")))
    check(code == 5 and tnet is not None and
          int(tnet["step"][-1]) == st["steps"] == int(tsnap["position/step"][-1]) and
          0 < st["steps"] < sa["steps"],
          "resumed: stopped (exit %s) at step %s with the network of its stop (%s)"
          % (code, st["steps"], tnet["step"].tolist() if tnet else None))
    if tnet is not None:
        check_frames("stopped with frames", tnet, tsnap)
    p = subprocess.run([lubdem, "run", path, "--out", out, "--quiet", "--resume"],
                       capture_output=True, text=True, timeout=600)
    rnet, rsnap = network(out)
    check(p.returncode == 0 and rnet is not None and anet is not None and
          sorted(rnet) == sorted(anet) and all(np.array_equal(rnet[k], anet[k]) for k in anet),
          "resumed: the continuation's frames equal the uninterrupted run's bit for bit "
          "(exit %s; steps %s against %s)"
          % (p.returncode, rnet["step"].tolist() if rnet else None,
             anet["step"].tolist() if anet else None))
    print("pair_network_frames=%d" % (len(anet["step"]) if anet is not None else 0))

    # 9. room: frames of about 0.5 MB under a limit 1.2 MB above the 64 MiB reserve
    out = os.path.join(work, "limited")
    shutil.rmtree(out, ignore_errors=True)
    limit = (64 << 20) + 1200000
    p = subprocess.run([lubdem, "run", path, "--out", out, "--quiet"], capture_output=True,
                       text=True, timeout=600,
                       preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_FSIZE,
                                                             (limit, limit)))
    lnet, lsnap = network(out)
    ls = json.load(open(os.path.join(out, "summary.json"))) if p.returncode == 0 else {}
    warned = [w for w in ls.get("warnings", []) if "of /pair_network from step" in w]
    written = len(lnet["step"]) if lnet is not None else 0
    check(p.returncode == 0 and ls.get("status") == "complete" and 0 < written < 6 and
          len(lsnap["position/step"]) == 6 and ls.get("results") == sa["results"] and
          len(warned) == 1 and ("%d frames" % (6 - written)) in warned[0] and
          anet is not None and ("from step %d" % anet["step"][written]) in warned[0],
          "limited: %d frames written, the rest skipped and reported (exit %s: %s; %s)"
          % (written, p.returncode, p.stderr.strip()[-200:], warned))
    return 1 if FAIL else 0


if __name__ == "__main__":
    sys.exit(main())
