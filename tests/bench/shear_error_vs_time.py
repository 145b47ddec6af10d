#!/usr/bin/env python3
"""Benchmark (label "bench"): standard error of mu and phi against simulated strain and run
time for the simple_shear scene at imposed pressure, for several particle numbers (issue 3,
"error against run time"), so that a user can choose N and the run length for a target accuracy.

For each N one run of `--strain` strain units is made (imposed pressure, default Iv = 0.01,
default law and cut-off unless overridden). The steady-state series of mu and phi (samples after
`transient_strain`) are then truncated at increasing end strains S and, for each S, the
standard error of the mean is computed with the engine's estimator (engine/stats.c: batch
means at the coarsest blocking level that keeps >= 32 of them, AR(1)-corrected; needs >= 32
samples). The run time to reach S is the run's measured CPU time (with 1 thread: the wall
time on an idle core, not inflated when the machine is shared) scaled by S / strain (the cost
per strain is constant once the pair lists are built). Prints one name=value line per figure:
  N=.. end_strain=.. averaged_strain=.. cpu_s=.. mu=.. mu_sem=.. mu_rel_err=.. phi=.. phi_sem=..
and per N the constants of the error model mu_rel_err = C_mu / sqrt(averaged_strain),
phi_sem = C_phi / sqrt(averaged_strain), taken from the whole steady series, with the apparent
exponents of the shorter windows as a diagnostic (1/2 if the estimator is unbiased at every
length); finally the pooled K = C sqrt(N) (error ~ K/sqrt(N strain)).
Writes OUT/error_vs_time.md, OUT/error_vs_time.csv and OUT/error_vs_time.png.

usage: shear_error_vs_time.py --lubdem PATH --out DIR [--n 500 1000 2000] [--strain 20]
                              [--iv 0.01] [--threads 1] [--reuse] [--extra JSON]
"""
import argparse
import csv
import json
import math
import os
import resource
import subprocess
import sys
import time

import h5py
import numpy as np


def stats_sem(x):
    """Standard error of the mean as engine/stats.c: halve (average neighbours) down to the
    coarsest level keeping >= 32 batch means, then the SEM of those means times
    sqrt((1 + r)/(1 - r)), r = their lag-1 autocorrelation clipped to [0, 0.95]."""
    x = np.asarray(x, dtype=float)
    if x.size < 32:
        return float("nan")
    while x.size // 2 >= 32:
        h = x.size // 2
        x = 0.5 * (x[0:2 * h:2] + x[1:2 * h:2])
    d = x - x.mean()
    den = float(d @ d)
    r = float(d[:-1] @ d[1:]) / den if den > 0 else 0.0
    r = min(max(r, 0.0), 0.95)
    return math.sqrt(np.var(x, ddof=1) / x.size) * math.sqrt((1 + r) / (1 - r))


def run(lubdem, out, name, spec, threads, reuse):
    d = os.path.join(out, name)
    summ_path = os.path.join(d, "summary.json")
    cpu_path = os.path.join(d, "cpu_seconds.txt")
    if not (reuse and os.path.exists(summ_path) and os.path.exists(cpu_path)):
        t0 = time.time()
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        p = subprocess.run([lubdem, "run", "-", "--out", d, "--threads", str(threads), "--quiet"],
                           input=json.dumps(spec), capture_output=True, text=True)
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        if p.returncode != 0:
            sys.exit(f"{name}: lubdem exit {p.returncode}: {p.stderr.strip()[:400]}")
        cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
        with open(cpu_path, "w") as fh:
            fh.write(f"{cpu:.3f}\n")
        print(f"run={name} wall_s={time.time() - t0:.1f} cpu_s={cpu:.1f}", flush=True)
    with open(summ_path) as fh:
        summ = json.load(fh)
    with open(cpu_path) as fh:
        summ["cpu_seconds"] = float(fh.read())
    with h5py.File(os.path.join(d, "result.h5"), "r") as h:
        o = h["observables"]
        series = {k: o[f"{k}/value"][:] for k in ("strain", "mu", "phi")}
    return summ, series


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lubdem", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--n", type=int, nargs="+", default=[500, 1000, 2000])
    ap.add_argument("--strain", type=float, default=20.0)
    ap.add_argument("--iv", type=float, default=0.01)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--reuse", action="store_true")
    ap.add_argument("--extra", default="{}", help="JSON object merged into every spec")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    transient = 2.0
    rows, fits = [], []
    for n in a.n:
        spec = {"scene": "simple_shear", "n_particles": n, "control": "pressure", "Iv": a.iv,
                "phi": 0.52, "St": 0.1, "stiffness": 1e4, "strain": a.strain,
                "transient_strain": transient, "snapshots": 0}
        spec.update(json.loads(a.extra))
        summ, s = run(a.lubdem, a.out, f"n{n}", spec, a.threads, a.reuse)
        # CPU seconds of the engine process: with --threads 1 this is the wall time on an idle
        # core, and it is not inflated when the machine is shared (the wall time is printed too)
        cpu = summ["cpu_seconds"]
        strain = s["strain"]
        keep = strain >= transient
        tol = 0.5 * (strain[1] - strain[0])
        # windows ending at round strains, and the whole run (the last window)
        ends = [e for e in (4, 6, 8, 10, 14, 20, 30, 40) if e < strain[-1] - 5 * tol]
        ends.append(round(float(strain[-1]), 2))
        xs, ys_mu, ys_phi = [], [], []
        for e in ends:
            m = keep & (strain <= e + tol)
            mu, phi = s["mu"][m], s["phi"][m]
            mu_sem, phi_sem = stats_sem(mu), stats_sem(phi)
            r = {"N": n, "end_strain": e, "averaged_strain": e - transient,
                 "cpu_s": cpu * e / strain[-1], "samples": int(m.sum()),
                 "mu": float(np.mean(mu)), "mu_sem": mu_sem,
                 "mu_rel_err": mu_sem / abs(float(np.mean(mu))), "phi": float(np.mean(phi)),
                 "phi_sem": phi_sem}
            rows.append(r)
            print(" ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                           for k, v in r.items()), flush=True)
            if math.isfinite(mu_sem) and mu_sem > 0 and math.isfinite(phi_sem) and phi_sem > 0:
                xs.append(e - transient)
                ys_mu.append(r["mu_rel_err"])
                ys_phi.append(phi_sem)
        if xs:
            # Error model: SEM(S) = SEM_full sqrt(S_full / S) (S = averaged strain), SEM_full from
            # the whole steady series (the longest window, the least noisy estimate). The fitted
            # exponents of the shorter windows show whether the estimate falls as S^-1/2.
            p_mu = -np.polyfit(np.log(xs), np.log(ys_mu), 1)[0] if len(xs) > 1 else float("nan")
            p_phi = -np.polyfit(np.log(xs), np.log(ys_phi), 1)[0] if len(xs) > 1 else float("nan")
            c_mu = ys_mu[-1] * math.sqrt(xs[-1])
            c_phi = ys_phi[-1] * math.sqrt(xs[-1])
            fits.append({"N": n, "cpu_s_per_strain": cpu / strain[-1], "p_mu": p_mu,
                         "p_phi": p_phi, "C_mu": c_mu, "C_phi": c_phi})
            print(f"N={n} cpu_s_per_strain={cpu / strain[-1]:.4g} window_exponent_mu={p_mu:.3f} "
                  f"window_exponent_phi={p_phi:.3f} C_mu={c_mu:.4g} C_phi={c_phi:.4g}", flush=True)
    if fits:
        k_mu = float(np.exp(np.mean([math.log(f["C_mu"] * math.sqrt(f["N"])) for f in fits])))
        k_phi = float(np.exp(np.mean([math.log(f["C_phi"] * math.sqrt(f["N"])) for f in fits])))
        print(f"K_mu={k_mu:.4g}\nK_phi={k_phi:.4g}")
    with open(os.path.join(a.out, "error_vs_time.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(a.out, "error_vs_time.md"), "w") as fh:
        fh.write(f"simple_shear, imposed pressure Iv = {a.iv:g}, extra spec {a.extra}, "
                 f"transient {transient:g} strain, threads {a.threads}\n\n")
        fh.write("| N | end strain | CPU s | mu | SEM(mu)/mu | phi | SEM(phi) |\n"
                 "|---|---|---|---|---|---|---|\n")
        for r in rows:
            fh.write(f"| {r['N']} | {r['end_strain']:g} | {r['cpu_s']:.0f} | {r['mu']:.4f} | "
                     f"{r['mu_rel_err']:.2%} | {r['phi']:.4f} | {r['phi_sem']:.1e} |\n")
        fh.write("\n| N | CPU s per strain | apparent p, SEM(mu) ~ strain^-p over the windows | "
                 "same for SEM(phi) | C_mu (rel. err of mu for 1 averaged strain) | C_phi |\n"
                 "|---|---|---|---|---|---|\n")
        for f in fits:
            fh.write(f"| {f['N']} | {f['cpu_s_per_strain']:.1f} | {f['p_mu']:.2f} | "
                     f"{f['p_phi']:.2f} | {f['C_mu']:.3g} | {f['C_phi']:.2g} |\n")
        if fits:
            fh.write(f"\nPooled: SEM(mu)/mu ~ {k_mu:.3g}/sqrt(N*strain), SEM(phi) ~ "
                     f"{k_phi:.3g}/sqrt(N*strain) (strain = averaged strain).\n")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(11, 4))
        for n in a.n:
            rr = [r for r in rows if r["N"] == n and math.isfinite(r["mu_sem"])]
            ax[0].loglog([r["cpu_s"] for r in rr], [r["mu_rel_err"] for r in rr], "o-",
                         label=f"N={n}")
            ax[1].loglog([r["cpu_s"] for r in rr], [r["phi_sem"] for r in rr], "o-",
                         label=f"N={n}")
        ax[0].set_xlabel("run time [CPU s, 1 thread]")
        ax[0].set_ylabel("SEM(mu)/mu")
        ax[1].set_xlabel("run time [CPU s, 1 thread]")
        ax[1].set_ylabel("SEM(phi)")
        for x in ax:
            x.legend()
            x.grid(True, which="both", lw=0.3)
        fig.suptitle(f"simple_shear error vs run time, imposed pressure Iv={a.iv:g}")
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, "error_vs_time.png"), dpi=110)
        print(f"plot={os.path.join(a.out, 'error_vs_time.png')}")
    except ImportError as e:
        print(f"plot=skipped ({e})")


if __name__ == "__main__":
    main()
