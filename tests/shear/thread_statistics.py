#!/usr/bin/env python3
"""Do 1 and T threads give the same rheology? (issue 3 item 7: "same results within round-off
statistics as one thread").

The pair sums are added in a different order on T threads, so a T-thread trajectory differs from
the 1-thread one at round-off level from the first step, and the dynamics amplifies the
difference exponentially until the two runs are different samples of the same steady state.
The script runs one simple_shear spec (the physics suite's group-A spec, N = 300, with St 0.01
also at Iv = 0.01 where the suite uses 0.1; default: the ref set, cut-off 1a, at imposed
pressure, Iv = 0.01, 20 strain averaged from strain 8, where the runs separate fastest) for K
packing seeds, once on 1 thread and once on T
threads, and prints:
  - the separation of the two runs' time series against strain: max |mu_T - mu_1| and
    |L_y,T - L_y,1| over each unit of strain, relative to the standard deviation of the series,
    and its growth rate (a least-squares slope of ln(separation) against strain over the
    strains where it lies between 1e-13 and 1e-3, the mean over seeds): a Lyapunov-like rate
    that says after how much strain the two runs decorrelate;
  - the largest relative difference between the two summaries (every results value);
  - for each observable (phi, mu, Z_contact, sigma_xy_tangential_contact/P), the means over
    seeds and the pooled difference
    z = sum_k (x_T,k - x_1,k) / sqrt(sum_k (se_1,k^2 + se_T,k^2)),
    and chi2/dof = mean_k (x_T,k - x_1,k)^2/(se_1,k^2 + se_T,k^2). When the averaging window
    starts after the runs have decorrelated (--transient beyond the decorrelation strain), z is
    N(0, 1) and chi2/dof about 1 if the thread count changes nothing and the engine's error bars
    are right; before that, both are near 0 (the runs are one trajectory).
--check exits 1 if |z| > 3 for any observable (a false alarm in 1 of 370 observables).
Whatever the options, it exits 1 at the first seed whose comparison says nothing: the T-thread
run ran on fewer threads (its summary's "threads"; fewer processors than T, taskset, a 1-CPU
allocation, OMP_THREAD_LIMIT), or the two runs agree bit for bit over the first unit of strain
(until 2026-12-07 such runs, identical, gave every difference 0 and --check passed).
Prints name=value lines; writes OUT/thread_statistics.json.
usage: thread_statistics.py --lubdem PATH --out DIR [--seeds K] [--threads T] [--iv IV]
       [--pairs cutoff|delaunay] [--strain S] [--transient S0] [--n N] [--reuse] [--check]
"""
import argparse
import json
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "resuspension"))
from resuspension_consistency import run, summary  # noqa: E402

import run_physics  # noqa: E402  (same folder: the suite's configurations and specs)

OBSERVABLES = ["phi", "mu", "Z_contact", "friction_share"]


def spec_for(seed, args):
    """the physics suite's group-A spec of the configuration (run_physics.spec_for), with St
    0.01 at every Iv (the suite uses 0.1 at Iv = 0.01), the start phi on the §2 law and this
    script's strain, averaging start and seed"""
    case = {"config": "delaunay" if args.pairs == "delaunay" else "ref", "control": "pressure",
            "Iv": args.iv, "St": 0.01, "strain": args.strain}
    s = run_physics.spec_for(case, args.n, True)
    s.update({"transient_strain": args.transient, "seed": seed,
              "phi": round(0.574 / (1 + math.sqrt(args.iv)), 4)})  # start near the §2 law
    return s


def values(res):
    """observable -> (value, stderr); the friction share is sigma_xy of the tangential contact
    forces over P (its error from the two relative errors, an upper bound: they are correlated)"""
    r = res["results"]
    out = {}
    for k in ("phi", "mu", "Z_contact"):
        e = r[k].get("stderr")
        out[k] = (r[k]["value"], e if e is not None else float("nan"))
    f, p = r["sigma_xy_tangential_contact"], r["pressure"]
    v = f["value"] / p["value"]
    fe = (f.get("stderr") or float("nan")) / abs(f["value"])
    pe = (p.get("stderr") or float("nan")) / abs(p["value"])
    out["friction_share"] = (v, abs(v) * math.hypot(fe, pe))
    return out


def series(out, name):
    import h5py  # only here: the rest of the script needs the standard library only
    with h5py.File(os.path.join(out, "result.h5"), "r") as f:
        return (f["observables/strain/value"][:], f[f"observables/{name}/value"][:])


def separation(out1, outt, name, strain_max):
    """max |x_T - x_1| over each unit of strain, over the standard deviation of x_1 after strain
    2 (lists: unit strain end, separation)"""
    import numpy as np
    g, x1 = series(out1, name)
    gt, xt = series(outt, name)
    n = min(len(x1), len(xt))
    g, d = g[:n], np.abs(xt[:n] - x1[:n])
    sd = float(np.std(x1[g >= 2.0])) or 1.0
    ends, seps = [], []
    for e in range(1, int(math.floor(strain_max)) + 1):
        w = (g > e - 1) & (g <= e)
        if w.any():
            ends.append(e)
            seps.append(float(d[w].max()) / sd)
    return ends, seps


def growth_rate(ends, seps):
    """least-squares slope of ln(sep) against strain where 1e-13 < sep < 1e-3 (None if < 3)"""
    pts = [(e, math.log(s)) for e, s in zip(ends, seps) if 1e-13 < s < 1e-3]
    if len(pts) < 3:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx


def first_strain_separation(out1, outt, name):
    """max |x_T - x_1| over strain <= 1 (the whole run when it is shorter)"""
    import numpy as np
    g, x1 = series(out1, name)
    _, xt = series(outt, name)
    n = min(len(x1), len(xt))
    w = g[:n] <= 1.0
    return float(np.max(np.abs(xt[:n][w] - x1[:n][w]))) if w.any() else 0.0


def void_comparison(s1, st, threads, first_seps):
    """why the 1- and T-thread runs cannot be compared (a list of messages; empty: they can):
    either run's summary "threads" is not 1 / T, or the two runs did not separate in the first
    unit of strain (first_seps: name -> first_strain_separation)"""
    why = []
    if s1.get("threads") != 1:
        why.append(f"the 1-thread run ran on {s1.get('threads')} threads (summary threads)")
    if st.get("threads") != threads:
        why.append(f"the {threads}-thread run ran on {st.get('threads')} thread(s) (summary "
                   f"threads; threads_requested {st.get('threads_requested')}): the process may "
                   f"run on fewer than {threads} processors (taskset, a 1-CPU allocation) or "
                   f"OMP_THREAD_LIMIT is set; give it {threads} processors")
    if not any(s > 0.0 for s in first_seps.values()):
        why.append("the 1- and " + str(threads) + "-thread runs are identical over the first "
                   "unit of strain (separation 0 in " + ", ".join(sorted(first_seps)) +
                   "): the pair sums were not added in another order, and the comparison says "
                   "nothing")
    return why


def max_rel_diff(s1, st):
    worst, key = 0.0, None
    for k, v in s1["results"].items():
        a = v["value"] if isinstance(v, dict) else v
        b = st["results"][k]["value"] if isinstance(st["results"][k], dict) else st["results"][k]
        if not isinstance(a, (int, float)) or not isinstance(b, (int, float)) or a == b:
            continue
        r = abs(b - a) / max(abs(a), abs(b))
        if r > worst:
            worst, key = r, k
    return worst, key


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lubdem", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--iv", type=float, default=0.01)
    ap.add_argument("--pairs", choices=["cutoff", "delaunay"], default="cutoff")
    ap.add_argument("--strain", type=float, default=20.0)
    ap.add_argument("--transient", type=float, default=8.0)
    ap.add_argument("--n", type=int, default=300)
    ap.add_argument("--reuse", action="store_true")
    ap.add_argument("--check", action="store_true")
    a = ap.parse_args()

    rows = []
    rates = {"mu": [], "cell_ly": []}
    seps_all = {}
    worst = (0.0, None)
    for seed in range(1, a.seeds + 1):
        sp = spec_for(seed, a)
        o1 = run(a.lubdem, sp, os.path.join(a.out, f"seed{seed}_t1"), a.reuse)
        ot = run(a.lubdem, sp, os.path.join(a.out, f"seed{seed}_t{a.threads}"), a.reuse,
                 threads=a.threads)
        s1, st = summary(o1), summary(ot)
        why = void_comparison(s1, st, a.threads,
                              {name: first_strain_separation(o1, ot, name) for name in rates})
        if why:
            for w in why:
                print(f"FAIL seed {seed}: {w}", flush=True)
            return 1
        w = max_rel_diff(s1, st)
        if w[0] > worst[0]:
            worst = w
        r1, rt = values(s1), values(st)
        rows.append((seed, r1, rt))
        for name in rates:
            ends, seps = separation(o1, ot, name, a.strain)
            seps_all[f"seed{seed}_{name}"] = dict(zip(ends, seps))
            gr = growth_rate(ends, seps)
            if gr is not None:
                rates[name].append(gr)
            print(f"# seed {seed} separation of {name} (strain: max |diff|/std): " +
                  " ".join(f"{e}:{x:.1e}" for e, x in zip(ends, seps)), flush=True)
        print(f"# seed {seed}: " + ", ".join(
            f"{k} {r1[k][0]:.4f}+-{r1[k][1]:.4f} / {rt[k][0]:.4f}+-{rt[k][1]:.4f}"
            for k in OBSERVABLES), flush=True)

    print(f"threadstat_seeds={a.seeds}")
    print(f"threadstat_threads={a.threads}")
    print(f"threadstat_strain={a.strain:g}")
    print(f"threadstat_averaged_from_strain={a.transient:g}")
    print(f"threadstat_summary_max_rel_diff={worst[0]:.2e}")
    print(f"threadstat_summary_max_rel_diff_field={worst[1]}")
    for name, v in rates.items():
        if v:
            m = sum(v) / len(v)
            print(f"threadstat_separation_growth_per_strain_{name}={m:.3f}")
            print(f"threadstat_separation_growth_per_strain_{name}_range={min(v):.3f}-{max(v):.3f}")
    bad = []
    for k in OBSERVABLES:
        d = [rt[k][0] - r1[k][0] for _, r1, rt in rows]
        v = [r1[k][1] ** 2 + rt[k][1] ** 2 for _, r1, rt in rows]
        z = sum(d) / math.sqrt(sum(v))
        chi2 = sum(di * di / vi for di, vi in zip(d, v)) / len(d)
        m1 = sum(r1[k][0] for _, r1, _ in rows) / len(rows)
        mt = sum(rt[k][0] for _, _, rt in rows) / len(rows)
        print(f"threadstat_{k}_mean_t1={m1:.5g}")
        print(f"threadstat_{k}_mean_t{a.threads}={mt:.5g}")
        print(f"threadstat_{k}_diff={mt - m1:.3g}")
        print(f"threadstat_{k}_diff_stderr={math.sqrt(sum(v)) / len(rows):.3g}")
        print(f"threadstat_{k}_z={z:.2f}")
        print(f"threadstat_{k}_chi2_per_dof={chi2:.2f}")
        if abs(z) > 3:
            bad.append(k)
    with open(os.path.join(a.out, "thread_statistics.json"), "w") as fh:
        json.dump({"runs": [{"seed": s, "t1": r1, f"t{a.threads}": rt} for s, r1, rt in rows],
                   "separation": seps_all}, fh, indent=1)
    if a.check:
        print(f"threadstat_failures={len(bad)}")
        for k in bad:
            print(f"FAIL {k}: 1 and {a.threads} threads differ by more than 3 standard errors")
        return 1 if bad else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
