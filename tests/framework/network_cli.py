"""network_cli.py - what the CLI tests of /pair_network (tests/shear/test_pair_network_cli.py,
tests/resuspension/test_pair_network_cli.py) share: failure bookkeeping, running lubdem on a
spec, reading a network with the particle snapshots and time series, one frame of a network,
and a run stopped by SIGTERM part-way."""
import json
import os
import shutil
import signal
import subprocess

import h5py

FAIL = []
INDEX = ("step", "time", "row_start", "row_count")  # one entry per frame


def check(cond, what):
    if not cond:
        FAIL.append(what)
        print("FAIL:", what)


def run(lubdem, work, name, spec, *extra, fresh=True):
    """lubdem run of spec (with its "scene") into work/name; the folder."""
    out = os.path.join(work, name)
    if fresh:
        shutil.rmtree(out, ignore_errors=True)
    path = os.path.join(work, name + ".json")
    with open(path, "w") as f:
        json.dump(spec, f)
    p = subprocess.run([lubdem, "run", path, "--out", out, "--quiet", *extra],
                       capture_output=True, text=True, timeout=600)
    check(p.returncode == 0, "%s: exit %s: %s" % (name, p.returncode, p.stderr[-500:]))
    return out


def frame(net, k):
    """Frame k of a network (columns as stored): its rows of every column, its index entries."""
    a, n = int(net["row_start"][k]), int(net["row_count"][k])
    return {key: (v[k:k + 1] if key in INDEX else v[a:a + n]) for key, v in net.items()}


def stop_midway(lubdem, work, name, spec, lo, hi, *extra):
    """Runs spec into work/name and sends SIGTERM at the first progress line with a fraction
    in [lo, hi); the folder and the exit code (5 when stopped)."""
    out = os.path.join(work, name)
    shutil.rmtree(out, ignore_errors=True)
    path = os.path.join(work, name + ".json")
    with open(path, "w") as f:
        json.dump(spec, f)
    proc = subprocess.Popen([lubdem, "run", path, "--out", out, *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    for line in proc.stdout:
        if line.startswith("progress ") and \
                lo <= float(line.split("fraction=")[1].split()[0]) < hi:
            proc.send_signal(signal.SIGTERM)
            break
    proc.communicate(timeout=600)
    return out, proc.returncode


def observables(out):
    """Every dataset under /observables of out/result.h5, by its path."""
    with h5py.File(os.path.join(out, "result.h5"), "r") as f:
        obs = {}
        f["observables"].visititems(
            lambda k, v: obs.__setitem__(k, v[()]) if isinstance(v, h5py.Dataset) else None)
    return obs


def load(out):
    """(all frames of /pair_network of out/result.h5, columns as stored; its particle
    snapshots with "units" of the network's columns and the resolved "spec"), or (None, None)
    without the group."""
    with h5py.File(os.path.join(out, "result.h5"), "r") as f:
        if "pair_network" not in f:
            return None, None
        g = f["pair_network"]
        net = {k: g[k][()] for k in g}
        units = {k: g[k].attrs["unit"] for k in g}
        snap = {k: f["particles/all/" + k][()] for k in
                ("position/value", "position/step", "box/edges/value", "radius")}
        spec = json.loads(f["parameters/spec_resolved"][()])
    units = {k: (u.decode() if isinstance(u, bytes) else u) for k, u in units.items()}
    return net, dict(snap, units=units, spec=spec)
