#!/usr/bin/env python3
"""The microstructure of simple_shear (/profiles/pdf_*, spec member /microstructure;
engine/microstructure.h) through the CLI, against an independent recomputation (fast suite):
 1. imposed volume, one microstructure snapshot at the step of a /pair_network frame and of a
    particle snapshot: every map (densities, pair counts, mean gap, both mean relative
    velocities, the four stress densities) recomputed here from that frame's pairs and that
    snapshot's velocities, spins and box, with the README's angle convention, to 1e-9 of the
    map's scale; empty bins: densities 0, mean gap and velocities NaN; the densities integrate
    to Z/2 and Z_contact/2 and the stress densities to the stress parts of the time series at
    that step; the bin edges, their convention attribute, the units, pdf_snapshots and
    pdf_strain_range are written (and in the summary);
 2. turning the microstructure on does not change the run: the time series, the summary's
    results and the final positions of a run with a snapshot every 10 steps (most steps taken
    with the batched law) equal bit for bit those of the same run without it;
 3. the first snapshot is at /microstructure/start_strain in both control modes, also when the
    strain summed step by step falls short of it by round-off (imposed pressure, Iv 0.1, dt
    0.002: 0.04999999999999981 at the step of 0.05, whose snapshot was skipped);
 4. the averaging warning end to end: maps averaged from strain 0 while the steady state is
    detected later warn, naming /microstructure/start_strain, the first map's strain and the
    summary's steady_from_strain; the same run with start_strain in the second half (after any
    steady start the run can detect) does not (the check itself is unit-tested in
    shear.run_checks; nothing ran it through a run before 2026-12-07).
Usage: test_microstructure_cli.py LUBDEM WORKDIR"""
import json
import math
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

LUBDEM, WORK = sys.argv[1], sys.argv[2]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
bad = []


def run(name, spec):
    path = os.path.join(WORK, name + ".json")
    with open(path, "w") as f:
        json.dump(spec, f)
    out = os.path.join(WORK, name)
    p = subprocess.run([LUBDEM, "run", path, "--out", out, "--quiet"], capture_output=True,
                       text=True)
    if p.returncode != 0:
        print(f"FAIL {name}: exit {p.returncode}: {p.stderr}")
        sys.exit(1)
    return out


def summary(d):
    with open(os.path.join(d, "summary.json")) as f:
        return json.load(f)


BASE = {"scene": "simple_shear", "n_particles": 300, "phi": 0.55, "stiffness": 1e4,
        "transient_strain": 0.01}

# 1. one snapshot at step 150 (strain 0.03), where the second particle snapshot and network
# frame are (snapshots 2 over 300 steps: after step 149, i.e. the configuration step 150
# evaluates); every step sampled, so the time series has that step's Z and stress parts
spec1 = dict(BASE, dt=0.0002, strain=0.06, sample_strain=0.0002, snapshots=2,
             pair_network="snapshots",
             microstructure={"enabled": True, "start_strain": 0.01, "interval_strain": 0.03,
                             "n_theta": 31, "n_phi": 31})
d1 = run("network", spec1)
f = h5py.File(os.path.join(d1, "result.h5"), "r")
P = f["profiles"]
nt, npp = P["pdf_interaction_density"].shape
nb = nt * npp
K = 1
step_k = int(f["pair_network/step"][K])
if step_k != 150:
    bad.append(f"network frame {K} at step {step_k}, not 150")
rs, rc = int(f["pair_network/row_start"][K]), int(f["pair_network/row_count"][K])


def col(name):
    return f["pair_network/" + name][rs:rs + rc]


r = f["particles/all/radius"][:]
N = r.shape[0]
i, j, img, br = col("i"), col("j"), col("image"), col("branch")
un, con = col("centre_gap"), col("contact")
H = f["particles/all/box/edges/value"][K]
v = f["particles/all/velocity/value"][K]
w = f["particles/all/angular_velocity/value"][K]
V = abs(np.linalg.det(H))
L = np.zeros((3, 3))
L[0, 1] = 1.0  # imposed volume: gd = 1
n = br / np.linalg.norm(br, axis=1)[:, None]
vc = v[j] + (img @ H) @ L.T - v[i]  # centre-of-mass relative velocity, image flow included
h1, h2 = r[i] + 0.5 * un, r[j] + 0.5 * un
wp = vc - np.cross(w[j], n) * h2[:, None] - np.cross(w[i], n) * h1[:, None]  # contact point
# the README's convention: theta = arccos(n_y), phi = atan2(n_x, n_z); phi < 0 counted as -n
th = np.arccos(np.clip(n[:, 1], -1, 1))
ph = np.arctan2(n[:, 0], n[:, 2])
inv = ph < 0
th = np.where(inv, np.pi - th, th)
ph = np.where(inv, ph + np.pi, ph)
it = np.minimum((th / (np.pi / nt)).astype(int), nt - 1)
ip = np.minimum((ph / (np.pi / npp)).astype(int), npp - 1)
b = it * npp + ip
T = np.arange(nt + 1) * np.pi / nt
dS = np.repeat(np.cos(T[:-1]) - np.cos(T[1:]), npp) * np.pi / npp
cnt = np.bincount(b, minlength=nb).astype(float)
sg = np.where(inv, -1.0, 1.0)[:, None]
safe = np.where(cnt > 0, cnt, np.nan)
ref = {
    "pdf_interaction_density": cnt / (N * dS),
    "pdf_contact_density": np.bincount(b, weights=con.astype(float), minlength=nb) / (N * dS),
    "pdf_pair_count": cnt,
    "pdf_mean_gap": np.bincount(b, weights=un / (0.5 * (r[i] + r[j])), minlength=nb) / safe,
    "pdf_mean_relative_velocity": np.stack(
        [np.bincount(b, weights=(sg * wp)[:, c], minlength=nb) for c in range(3)], 1)
    / safe[:, None],
    "pdf_mean_centre_relative_velocity": np.stack(
        [np.bincount(b, weights=(sg * vc)[:, c], minlength=nb) for c in range(3)], 1)
    / safe[:, None],
}
for part, fn, ft in [("contact", "force_normal_contact", "force_tangential_contact"),
                     ("lubrication", "force_normal_lubrication", "force_tangential_lubrication")]:
    for kind, F in [("normal", n * col(fn)[:, None]), ("tangential", col(ft))]:
        t = np.einsum("pi,pj->pij", F, br).reshape(-1, 9)
        ref[f"pdf_stress_{kind}_{part}"] = np.stack(
            [np.bincount(b, weights=t[:, c], minlength=nb) for c in range(9)], 1) / (
            V * dS[:, None])
empty = cnt == 0
print(f"{rc} pairs, {int(empty.sum())} of {nb} bins empty")
if not empty.any():
    bad.append("no empty bin: the NaN check checks nothing")
for name, want in ref.items():
    got = P[name][:].reshape(want.shape)
    if not np.array_equal(np.isnan(got), np.isnan(want)):
        bad.append(f"{name}: NaN in other bins than the recomputation's")
        continue
    scale = np.nanmax(np.abs(want))
    diff = np.nanmax(np.abs(got - want))
    print(f"{name:40s} max diff {diff:.2e} of {scale:.2e}")
    if not diff <= 1e-9 * scale:
        bad.append(f"{name}: recomputed to {diff:.3g} of {scale:.3g}")
for name in ["pdf_interaction_density", "pdf_contact_density"]:
    if np.any(P[name][:].ravel()[empty] != 0):
        bad.append(f"{name} not 0 in an empty bin")
for name in ["pdf_mean_gap", "pdf_mean_relative_velocity", "pdf_mean_centre_relative_velocity"]:
    if not np.all(np.isnan(P[name][:].reshape(nb, -1)[empty])):
        bad.append(f"{name} not NaN in an empty bin")
# integrals against the time series at that step
steps = f["observables/Z/step"][:]
row = int(np.searchsorted(steps, step_k))
if steps[row] != step_k:
    bad.append(f"no sample at step {step_k}")
for name, obs in [("pdf_interaction_density", "Z"), ("pdf_contact_density", "Z_contact")]:
    integral = float((P[name][:].ravel() * dS).sum())
    half = 0.5 * float(f[f"observables/{obs}/value"][row])
    print(f"integral of {name} {integral:.12g}, {obs}/2 {half:.12g}")
    if abs(integral - half) > 1e-12 * half:
        bad.append(f"{name} integrates to {integral}, not {obs}/2 = {half}")
for kind in ["normal", "tangential"]:
    for part in ["contact", "lubrication"]:
        S = (P[f"pdf_stress_{kind}_{part}"][:] * dS[:, None]).sum(0).reshape(3, 3)
        want = f[f"observables/stress/{kind}_{part}/value"][row]
        d = np.abs(S - want).max()
        if not d <= 1e-9 * np.abs(want).max():
            bad.append(f"stress density {kind}_{part} integrates to {d:.3g} off the series")
# layout: edges, convention, units, snapshot count and strain range
if not np.allclose(P["pdf_theta_edges"][:], np.linspace(0, np.pi, nt + 1), rtol=0, atol=1e-15):
    bad.append("pdf_theta_edges")
if not np.allclose(P["pdf_phi_edges"][:], np.linspace(0, np.pi, npp + 1), rtol=0, atol=1e-15):
    bad.append("pdf_phi_edges")
conv = P["pdf_theta_edges"].attrs.get("convention", b"")
conv = conv.decode() if isinstance(conv, bytes) else conv
if "arccos(n_y)" not in conv or "atan2(n_x, n_z)" not in conv:
    bad.append(f"convention attribute: {conv!r}")


def unit(name):
    u = P[name].attrs["unit"]
    return u.decode() if isinstance(u, bytes) else u


for name, u in [("pdf_mean_gap", "1"), ("pdf_pair_count", "1"),
                ("pdf_mean_centre_relative_velocity", "a*gd"), ("pdf_theta_edges", "rad"),
                ("pdf_interaction_density", "1/sr")]:
    if unit(name) != u:
        bad.append(f"{name} unit {unit(name)!r}, not {u!r}")
strain_k = float(f["observables/strain/value"][row])
rng = P["pdf_strain_range"][:]
if P["pdf_snapshots"][0] != 1 or not (rng[0] == rng[1] == strain_k):
    bad.append(f"pdf_snapshots {P['pdf_snapshots'][:]}, strain range {rng} (step's {strain_k})")
res1 = summary(d1)["results"]
if abs(res1["pdf_first_strain"]["value"] - strain_k) > 1e-12 or res1["pdf_snapshots"]["value"] != 1:
    bad.append(f"summary: {res1['pdf_first_strain']}, {res1['pdf_snapshots']}")
f.close()

# 2. on and off: bit-identical runs (default sampling: 1 step in 50 samples stress, the others
# take the batched law; a microstructure snapshot every 10 steps)
spec2 = dict(BASE, strain=0.15, sample_strain=0.01, snapshots=1)
on = run("on", dict(spec2, microstructure={"enabled": True, "start_strain": 0.0,
                                            "interval_strain": 0.002}))
off = run("off", spec2)
fa, fb = h5py.File(os.path.join(on, "result.h5"), "r"), h5py.File(os.path.join(off, "result.h5"),
                                                                  "r")
print(f"on/off: {int(fa['profiles/pdf_snapshots'][0])} snapshots")
diffs = []


def compare(name, obj):
    if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f":
        other = fb[obj.name][()]
        if not np.array_equal(obj[()], other):
            diffs.append(f"{obj.name} ({np.nanmax(np.abs(obj[()] - other)):.2e})")


fa["observables"].visititems(compare)
fa["particles"].visititems(compare)
ra, rb = summary(on)["results"], summary(off)["results"]
for k, val in rb.items():
    if ra.get(k) != val:
        diffs.append(f"summary {k}: {ra.get(k)} vs {val}")
if diffs:
    bad.append("microstructure on changes the run: " + "; ".join(diffs[:6]))

# 3. the first snapshot at /microstructure/start_strain, both control modes
for name, spec in [
    ("start_pressure", dict(BASE, control="pressure", Iv=0.1, phi=0.52, dt=0.002, strain=0.07,
                            transient_strain=0.05, stiffness=1e4)),
    ("start_volume", dict(BASE, dt=0.0002, strain=0.07, transient_strain=0.05)),
]:
    spec["microstructure"] = {"enabled": True, "start_strain": 0.05, "interval_strain": 0.01}
    d = run(name, spec)
    with h5py.File(os.path.join(d, "result.h5"), "r") as g:
        first, last = g["profiles/pdf_strain_range"][:]
        snaps = g["profiles/pdf_snapshots"][0]
    print(f"{name}: {snaps:.0f} snapshots, strains {first!r} .. {last!r}")
    if not (abs(first - 0.05) < 1e-9 and abs(last - 0.06) < 1e-9 and snaps == 2):
        bad.append(f"{name}: snapshots {snaps}, first at {first!r}, last {last!r} "
                   "(want 2, from 0.05 to 0.06)")

# 4. the averaging warning, end to end (250 particles, soft contacts: about 1.3 s a run)
WARN = "the microstructure (/profiles) is averaged from strain"
for name, start, want in [("early_maps", 0.0, True), ("late_maps", 1.6, False)]:
    spec = {"scene": "simple_shear", "n_particles": 250, "phi": 0.40, "stiffness": 1e4,
            "strain": 2.0, "transient_strain": 0.3,
            "microstructure": {"enabled": True, "start_strain": start, "interval_strain": 0.1,
                               "n_theta": 9, "n_phi": 9}}
    s = summary(run(name, spec))
    steady = (s["results"].get("steady_from_strain") or {}).get("value")
    got = [w for w in s.get("warnings", []) if w.startswith(WARN)]
    print(f"{name}: steady from {steady}, averaging warning {bool(got)}")
    if steady is None or not 0.3 <= steady < 1.0:
        bad.append(f"{name}: steady state from {steady}, wanted one between 0.3 and 1 (test set-up)")
    elif want and not (len(got) == 1 and f"from strain {start:.4g}," in got[0]
                       and f"from strain {steady:.4g}:" in got[0]
                       and "/microstructure/start_strain" in got[0]):
        bad.append(f"{name}: no averaging warning naming /microstructure/start_strain, {start:.4g} "
                   f"and {steady:.4g} ({s.get('warnings')})")
    elif not want and got:
        bad.append(f"{name}: averaging warning although the maps start at {start} ({got})")

for m in bad:
    print("FAIL", m)
print("OK" if not bad else f"{len(bad)} failure(s)")
sys.exit(1 if bad else 0)
