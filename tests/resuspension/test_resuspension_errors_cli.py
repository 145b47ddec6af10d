#!/usr/bin/env python3
"""The error bars of /profiles/eta_normal_err and /profiles/phi_coarse_err recomputed from the
particle snapshots of short runs (a snapshot at every averaged sample): each snapshot's phi(y)
(exact sphere-slab volumes), its eta_ii(y) = (1/Sh) int_y phi and its phi averaged over
/analysis/phi_window give one series per bin; the engine's error must be the standard error of
that series' mean (AR(1)-corrected batch means, re-implemented here from the stats.h text, from
32 samples on; the naive SEM below, phi_err_method "naive (...)"). Tolerance 1e-6 relative + 1e-9
absolute (the snapshots' positions are the engine's, the arithmetic differs). The bottom bin's
eta_err must be ~0 (every sample holds the same inventory); the error model that assumed
independent bins gave it the largest error of the profile. Gradient orientation: the summary's
shear_drag_weight_share (the shear drag's vertical force over the buoyant weight, averaged over
the samples) and its error (the SEM of the per-sample shares, since 2026-12-08) from the
snapshots' velocities, and its warning above 2 % quoting that error; /profiles/velocity_x (the
window's volume-weighted v_x per bin), bulk_velocity_slope (least squares over the bulk bins)
and its error: the SEM of each sample's first-order change of the slope,
sum_i c_i (s_ik - v_i vol_ik) / (V_i / navg) (delta method; s_ik and vol_ik the sample's
velocity sum and volume in bin i, V_i and v_i the window's), whose mean must be 0.
A run stopped by SIGTERM and resumed gives the summary of the uninterrupted run, error bars
included; resumed from a checkpoint without the per-sample series (as one written before
2026-12-08: the datasets deleted here), the same values and null errors for those two.
Usage: test_resuspension_errors_cli.py LUBDEM WORKDIR"""
import json
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "framework"))
from network_cli import stop_midway  # noqa: E402


def sem_ar1(x):
    s = np.asarray(x, float)
    if len(s) < 32:
        return np.sqrt(s.var(ddof=1) / len(s))
    while len(s) // 2 >= 32:
        h = len(s) // 2
        s = 0.5 * (s[0 : 2 * h : 2] + s[1 : 2 * h : 2])
    d = s - s.mean()
    den = (d * d).sum()
    r = (d[:-1] * d[1:]).sum() / den if den > 0 else 0.0
    r = min(max(r, 0.0), 0.95)
    return np.sqrt(s.var(ddof=1) / len(s)) * np.sqrt((1 + r) / (1 - r))


def cap(h, r):
    h = np.clip(h, 0, 2 * r)
    return np.pi * h * h * (3 * r - h) / 3


def check(lubdem, work, name, spec):
    d = os.path.join(work, name)
    path = os.path.join(work, name + ".json")
    json.dump(spec, open(path, "w"))
    subprocess.run([lubdem, "run", path, "--out", d, "--threads", "1", "--quiet"], check=True)
    S = json.load(open(d + "/summary.json"))
    sp, R = S["spec"], S["results"]
    fails = []
    with h5py.File(d + "/result.h5", "r") as f:
        P = {k: f["profiles"][k][()] for k in f["profiles"]}
        y_floor = float(f["profiles/y_floor"][0])
        assert f["profiles/y_floor"].attrs["unit"] in (b"a", "a")
        # written since 2026-12-06: r_f (1 + jitter) + 1 (resuspension_bed.c)
        y_expect = R["floor_radius"]["value"] * (1 + sp["floor"]["jitter"]) + 1.0
        if not abs(y_floor - y_expect) < 1e-8:
            fails.append(f"{name}: /profiles/y_floor {y_floor} vs {y_expect}")
        rad = f["particles/all/radius"][()]
        X = f["particles/all/position/value"][()]
        V = f["particles/all/velocity/value"][()]
        H = np.array(f["particles/all/box/edges/value"][0]).T
        t = f["particles/all/position/time"][()]
    area = abs(np.linalg.det(H)) / H[1, 1]
    dy, Sh, nb = sp["bin_width"], sp["shields"], len(P["y"])
    lo = np.arange(nb) * dy
    hi = lo + dy
    rows = [k for k in range(len(t)) if t[k] >= sp["average_from"] - 1e-9]
    navg = int(R["averaged_samples"]["value"])
    if len(rows) != navg:
        return [f"{name}: {len(rows)} snapshots in the averaging window, {navg} samples"]
    A, VS = [], []  # per sample: phi(y), and the volume-weighted v_x per bin (gradient: v_x)
    for k in rows:
        b = (X[k][:, 1] - y_floor - rad)[:, None]
        r = rad[:, None]
        slab = cap(hi[None] - b, r) - cap(lo[None] - b, r)
        A.append(slab.sum(0) / (area * dy))
        VS.append((slab * V[k][:, 0:1]).sum(0))
    A, VS = np.array(A), np.array(VS)
    if not np.allclose(A.mean(0), P["phi"], rtol=1e-6, atol=1e-9):
        fails.append(f"{name}: phi(y) from the snapshots differs from /profiles/phi")
    above = np.concatenate([np.cumsum(A[:, ::-1], 1)[:, ::-1][:, 1:], np.zeros((len(A), 1))], 1)
    E = (above + 0.5 * A) * dy / Sh
    w = sp["analysis"]["phi_window"]
    C = np.empty_like(A)
    for i in range(nb):
        ov = np.clip(np.minimum(P["y"][i] + w / 2, hi) - np.maximum(P["y"][i] - w / 2, lo), 0, None)
        C[:, i] = (A * ov).sum(1) / ov.sum()
    es = np.array([sem_ar1(E[:, i]) for i in range(nb)])
    cs = np.array([sem_ar1(C[:, i]) for i in range(nb)])
    for what, got, want in (("eta_normal_err", P["eta_normal_err"], es),
                            ("phi_coarse_err", P["phi_coarse_err"], cs)):
        bad = np.abs(got - want) > 1e-6 * np.abs(want) + 1e-9
        if bad.any():
            i = int(np.argmax(bad))
            fails.append(f"{name}: {what} differs from the SEM of the per-sample series in "
                         f"{bad.sum()} of {nb} bins, e.g. y = {P['y'][i]}: {got[i]:.6g} vs {want[i]:.6g}")
    if not P["eta_normal_err"][0] <= 1e-9 * P["eta_normal"][0]:
        fails.append(f"{name}: eta_normal_err of the bottom bin {P['eta_normal_err'][0]:.3g}, "
                     f"expected ~0 (eta {P['eta_normal'][0]:.4g})")
    m = P["bulk_mask"] > 0
    ev = P["eta_vs_phi"]  # written with no rows too (since 2026-12-07), shape (0, 4)
    if ev.ndim != 2 or ev.shape != (int(m.sum()), 4):
        fails.append(f"{name}: eta_vs_phi shape {ev.shape}, {int(m.sum())} bulk bins")
        ev = np.zeros((0, 4)) if ev.size == 0 else ev
    if int(R["bulk_bins"]["value"]) < 3:
        # fewer than 3 bulk bins: the null members and the spec fields are named (2026-12-07)
        nulls = ["bulk_velocity_slope"] + (["eta_vs_law_log_rms"] if not m.any() else [])
        warn = [w for w in S["warnings"] if "bulk bin" in w]
        for k in nulls:
            if R[k]["value"] is not None:
                fails.append(f"{name}: {k} = {R[k]['value']} with {int(m.sum())} bulk bins")
        want = nulls + ["/analysis/interface_width", "/analysis/floor_skip",
                        "/analysis/phi_min", "/n", "/strain"]
        if not m.any():
            want.append("/profiles/eta_vs_phi")
        if len(warn) != 1 or not all(k in warn[0] for k in want):
            fails.append(f"{name}: no warning naming {want}: {S['warnings']}")
    if not (np.array_equal(ev[:, 1], P["phi_coarse_err"][m])
            and np.array_equal(ev[:, 3], P["eta_normal_err"][m])):
        fails.append(f"{name}: eta_vs_phi error columns are not the bulk bins' errors")
    # a top-level member: "batch_means_ar1" or "naive (fewer than 32 samples)" (until
    # 2026-12-07 this read results/phi_err_method, absent, and never checked anything)
    method = S.get("phi_err_method")
    want_method = "batch_means" if navg >= 32 else "naive"
    if not (isinstance(method, str) and method.startswith(want_method)):
        fails.append(f"{name}: phi_err_method {method!r}, expected {want_method}...")
    # gradient orientation: the share of the buoyant weight the shear drag carries over the
    # averaged samples, from the snapshots' velocities, and its warning above 2 %
    if sp["orientation"] == "gradient":
        W = (4 / 3 * np.pi * rad**3).sum() / Sh
        shares = [-(6 * np.pi * sp["shear_drag_viscosity"] * rad * V[k][:, 1]).sum() / W
                  for k in rows]
        share, share_err = np.mean(shares), sem_ar1(shares)
        got, got_err = R["shear_drag_weight_share"]["value"], R["shear_drag_weight_share"]["stderr"]
        if not abs(got - share) <= 1e-9 + 1e-6 * abs(share):
            fails.append(f"{name}: shear_drag_weight_share {got} vs {share} from the snapshots")
        if got_err is None or not abs(got_err - share_err) <= 1e-9 + 1e-6 * share_err:
            fails.append(f"{name}: shear_drag_weight_share error {got_err} vs {share_err}, the "
                         "SEM of the snapshots' shares")
        warn = [w for w in S["warnings"] if "shear drag carries" in w]
        if bool(warn) != (abs(share) > 0.02):
            fails.append(f"{name}: drag share {share:.4f}, warning {bool(warn)}")
        elif warn and not f"{100 * share:.3g} \u00b1 {100 * share_err:.2g} %" in warn[0]:
            fails.append(f"{name}: the drag share's warning does not quote "
                         f"{100 * share:.3g} \u00b1 {100 * share_err:.2g} %: {warn[0]}")
        print(f"{name}: shear drag carries {100 * share:.2f} +- {100 * share_err:.2f} % of the "
              f"weight, warning {bool(warn)}")
        # the velocity profile and the slope's error (the bulk bins a sphere crossed)
        vol = A * area * dy
        Sv, Vv = VS.sum(0), vol.sum(0)
        vx = np.where(Vv > 0, Sv / np.where(Vv > 0, Vv, 1), np.nan)
        if not np.allclose(vx, P["velocity_x"], rtol=1e-6, atol=1e-9, equal_nan=True):
            fails.append(f"{name}: velocity_x from the snapshots differs from /profiles/velocity_x")
        fit = m & (Vv > 0)
        n, yb = int(fit.sum()), P["y"][fit]
        slope = R["bulk_velocity_slope"]
        if n >= 3:
            c = (n * yb - yb.sum()) / (n * (yb * yb).sum() - yb.sum() ** 2)
            want = (c * vx[fit]).sum()
            d = ((VS[:, fit] - vx[fit] * vol[:, fit]) / (Vv[fit] / navg) * c).sum(1)
            want_err = sem_ar1(d)
            if not abs(slope["value"] - want) <= 1e-8 * abs(want) + 1e-9:
                fails.append(f"{name}: bulk_velocity_slope {slope['value']} vs {want}")
            if not abs(d.mean()) <= 1e-9 * np.abs(d).max():
                fails.append(f"{name}: the slope's per-sample changes have mean {d.mean():.3g}")
            if slope["stderr"] is None or not abs(slope["stderr"] - want_err) <= 1e-9 + 1e-6 * want_err:
                fails.append(f"{name}: bulk_velocity_slope error {slope['stderr']} vs {want_err}, "
                             "the SEM of the snapshots' first-order changes")
            warn = [w for w in S["warnings"] if "not sheared homogeneously" in w]
            if bool(warn) != (abs(want - 1) > 0.2):
                fails.append(f"{name}: slope {want:.4f}, warning {bool(warn)}")
            elif warn and not f"{want:.3g} \u00b1 {want_err:.2g} gd" in warn[0]:
                fails.append(f"{name}: the slope's warning does not quote {want:.3g} \u00b1 "
                             f"{want_err:.2g} gd: {warn[0]}")
            print(f"{name}: bulk velocity slope {want:.4f} +- {want_err:.4f} over {n} bins")
    elif "shear_drag_weight_share" in R:
        fails.append(f"{name}: shear_drag_weight_share in the vorticity orientation")
    ratio = np.median(P['eta_normal_err'][m] / es[m]) if m.any() else float("nan")
    print(f"{name}: {navg} samples, bottom eta_err {P['eta_normal_err'][0]:.3g}, "
          f"bulk eta_err / series SEM {ratio:.3f}, {int(m.sum())} bulk bins")
    return fails


def resumed(lubdem, work):
    """A gradient run stopped by SIGTERM midway and resumed, against the same run made straight;
    and resumed from its checkpoint without the per-sample series."""
    fails = []
    spec = {"scene": "resuspension", "n": 150, "width": 12, "strain": 2, "average_from": 0.2,
            "sample_strain": 0.05, "inertial_number": 0.05, "density_ratio": 10,
            "shear_drag_viscosity": 3, "snapshots": 0}
    straight = os.path.join(work, "straight")
    path = os.path.join(work, "straight.json")
    json.dump(spec, open(path, "w"))
    subprocess.run([lubdem, "run", path, "--out", straight, "--threads", "1", "--quiet"],
                   check=True)
    want = json.load(open(straight + "/summary.json"))["results"]
    out, code = stop_midway(lubdem, work, "stopped", spec, 0.3, 0.9, "--threads", "1")
    if code != 5:
        return [f"resumed: the stop gave exit {code}, not 5"]
    old = os.path.join(work, "stopped_old")
    shutil.rmtree(old, ignore_errors=True)
    shutil.copytree(out, old)
    with h5py.File(os.path.join(old, "checkpoint.h5"), "r+") as f:
        for k in ("profiles/vx_samples", "series/drag_share"):
            if k not in f:
                fails.append(f"resumed: the checkpoint has no {k}")
            else:
                del f[k]
    for d, errors in ((out, True), (old, False)):
        p = subprocess.run([lubdem, "run", os.path.join(work, "stopped.json"), "--out", d,
                            "--threads", "1", "--quiet", "--resume"],
                           capture_output=True, text=True, timeout=600)
        if p.returncode != 0:
            fails.append(f"resumed {d}: exit {p.returncode}: {p.stderr[-300:]}")
            continue
        got = json.load(open(d + "/summary.json"))["results"]
        for k in want:
            w = dict(want[k])
            if not errors and k in ("bulk_velocity_slope", "shear_drag_weight_share"):
                w["stderr"] = None
            if got.get(k) != w:
                fails.append(f"resumed {d}: {k} {got.get(k)}, expected {w}")
    for k in ("bulk_velocity_slope", "shear_drag_weight_share"):
        if want[k]["stderr"] is None:
            fails.append(f"straight: {k} has no error")
    print(f"resumed: {want['averaged_samples']['value']} samples, slope "
          f"{want['bulk_velocity_slope']}, drag share {want['shear_drag_weight_share']}")
    return fails


def main():
    lubdem, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    base = {"scene": "resuspension", "n": 150, "width": 12, "inertial_number": 0.05,
            "density_ratio": 10, "shear_drag_viscosity": 3}
    fails = check(lubdem, work, "batch", dict(base, strain=0.5, average_from=0.1,
                                              sample_strain=0.01, snapshots=51))
    fails += check(lubdem, work, "naive", dict(base, strain=0.5, average_from=0.3,
                                               sample_strain=0.01, snapshots=51))
    # the seed's drag (eta/30) barely shears the bed: the slope's warning, with its error bar
    fails += check(lubdem, work, "weakdrag", dict(base, strain=0.5, average_from=0.1,
                                                  sample_strain=0.01, snapshots=51,
                                                  shear_drag_viscosity=1.0 / 30.0))
    fails += check(lubdem, work, "vorticity", dict(base, orientation="vorticity", strain=0.5,
                                                   average_from=0.1, sample_strain=0.01,
                                                   snapshots=51, shear_drag_viscosity=0))
    # the audit's bed too thin for a bulk bin (N 40, Sh 0.05): bulk_bins 0, eta_vs_phi (0, 4)
    fails += check(lubdem, work, "nobulk", dict(base, orientation="vorticity", n=40, strain=0.6,
                                                average_from=0.1, sample_strain=0.01,
                                                shields=0.05, snapshots=61,
                                                shear_drag_viscosity=0))
    fails += resumed(lubdem, work)
    # 9 averaged samples, fewer than the 10 MSER-5 needs: "too few samples to judge", not
    # "not steady (MSER-5, drift test)" (2026-12-07)
    d, path = os.path.join(work, "few"), os.path.join(work, "few.json")
    json.dump(dict(base, orientation="vorticity", n=40, strain=0.6, average_from=0.2,
                   sample_strain=0.05, shields=0.05, snapshots=0, shear_drag_viscosity=0),
              open(path, "w"))
    subprocess.run([lubdem, "run", path, "--out", d, "--threads", "1", "--quiet"], check=True)
    S = json.load(open(d + "/summary.json"))
    w = S["warnings"]
    if not (S["results"]["averaged_samples"]["value"] < 10 and not S["height_steady"]
            and any("too few samples to judge" in x for x in w)
            and not any("not steady" in x for x in w)):
        fails.append(f"few: {S['results']['averaged_samples']['value']} samples, warnings {w}")
    for x in fails:
        print("FAIL:", x, file=sys.stderr)
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
