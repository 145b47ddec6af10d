#!/usr/bin/env python3
"""Time step against the pairs' summed stiffness (simple_shear; README, simple_shear, Method).

The automatic step is /dt_safety times the single-pair bound sqrt(min(m/g, I/(k_t r^2))), lowered
while dt exceeds /dt_stiffness_safety times the many-partner bound of engine/step_stiffness.h
(reported as dt_stiffness_ratio = the largest dt / bound met at a neighbour-list rebuild). For
light, soft spheres (small St * stiffness) the films within the cut-off are as stiff as g and
the single-pair step blows up. This study runs a grid of such specs twice:
  - "pair": /dt_stiffness_safety 0 (the single-pair step throughout), at /dt_safety 0.3, 0.25,
    0.2, 0.15: which runs blow up (exit 3), and at which dt_stiffness_ratio;
  - "auto": the default (/dt_safety 0.3, /dt_stiffness_safety 1): every run must complete.
Each run takes NSTEPS steps of the single-pair step at /dt_safety 0.3 (strain capped at 2).
Checks (--check): every "auto" run completes with dt_stiffness_ratio <= 1.01; every "pair" run
that blew up had a ratio above 1 (the bound sees what the single-pair bound misses); every
"pair" run at a ratio below 1 completed. Prints name=value lines and writes a markdown table.

usage: step_stability_study.py --lubdem PATH --out DIR [--jobs 2] [--nsteps 20000] [--check]
       [--table FILE]
"""
import argparse
import concurrent.futures as cf
import json
import os
import subprocess
import sys

# (n_particles, cutoff, St, stiffness, phi): imposed volume, mu 0.5
CONFIGS = [(300, 2.0, 0.01, 1e2, 0.3), (300, 2.0, 0.01, 1e2, 0.55), (300, 2.0, 0.01, 1e3, 0.55),
           (300, 2.0, 1e-4, 1e4, 0.55), (300, 2.0, 0.01, 1e4, 0.55), (300, 3.0, 0.01, 1e2, 0.3),
           (300, 3.0, 0.01, 1e3, 0.3), (300, 3.0, 1e-4, 1e4, 0.3), (300, 3.0, 0.01, 1e4, 0.3),
           (600, 3.0, 0.01, 1e3, 0.45), (600, 3.0, 1e-4, 1e4, 0.55)]
PAIR_SAFETIES = [0.3, 0.25, 0.2, 0.15]


def spec(cfg, dt_safety, stiffness_safety, nsteps):
    n, cut, st, k, phi = cfg
    # single-pair step at dt_safety 0.3: 0.3 sqrt(min(m/g, I/(k_t r^2))) = 0.3 sqrt(0.8 m/g)
    # with m = 4/3 pi St (a = 1, gd = 1), k_t = g/2
    dt = 0.3 * (0.8 * 4.18879 * st / k) ** 0.5
    s = {"scene": "simple_shear", "n_particles": n, "phi": phi, "cutoff": cut, "St": st,
         "stiffness": k, "strain": round(min(2.0, nsteps * dt), 6), "transient_strain": 0.0,
         "snapshots": 0, "dt_safety": dt_safety, "law": {"mu": 0.5}}
    if stiffness_safety is not None:
        s["dt_stiffness_safety"] = stiffness_safety
    return s


def run(lubdem, out, name, s):
    d = os.path.join(out, name)
    p = subprocess.run([lubdem, "run", "-", "--out", d, "--quiet"], input=json.dumps(s),
                       capture_output=True, text=True)
    res = {}
    try:
        with open(os.path.join(d, "summary.json")) as fh:
            res = {k: v["value"] for k, v in json.load(fh)["results"].items()}
    except (OSError, KeyError, ValueError):
        pass
    return name, p.returncode, res


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lubdem", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--nsteps", type=int, default=20000)
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--table")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    jobs = []
    for c in CONFIGS:
        key = "n%d_c%g_St%g_k%g_phi%g" % c
        for ds in PAIR_SAFETIES:
            jobs.append((f"pair{ds:g}_{key}", c, spec(c, ds, 0.0, a.nsteps)))
        jobs.append((f"auto_{key}", c, spec(c, 0.3, None, a.nsteps)))
    out = {}
    with cf.ThreadPoolExecutor(a.jobs) as ex:
        for name, rc, res in ex.map(lambda j: run(a.lubdem, a.out, j[0], j[2]), jobs):
            out[name] = (rc, res)
            ratio = res.get("dt_stiffness_ratio")
            print(f"case={name} rc={rc} dt_stiffness_ratio={ratio} "
                  f"dt_min_over_elastic={res.get('dt_min', float('nan')) / res.get('dt_elastic', 1):.4g}"
                  if res else f"case={name} rc={rc}", flush=True)
    fails = []
    rows = ["| N | cut-off | St | stiffness | φ | " +
            " | ".join(f"single-pair {ds:g}" for ds in PAIR_SAFETIES) +
            " | automatic: dt/dt_elastic, ratio |", "|---" * (6 + len(PAIR_SAFETIES)) + "|"]
    blown = []
    for c in CONFIGS:
        key = "n%d_c%g_St%g_k%g_phi%g" % c
        cells = []
        for ds in PAIR_SAFETIES:
            rc, res = out[f"pair{ds:g}_{key}"]
            ratio = res.get("dt_stiffness_ratio")
            cells.append(("**blew up** " if rc == 3 else ("ok " if rc == 0 else f"rc {rc} ")) +
                         (f"{ratio:.2f}" if ratio is not None else "–"))
            if rc == 3:
                blown.append(ratio)
                if not (ratio is not None and ratio > 1.0):
                    fails.append(f"pair{ds:g}_{key}: blew up at ratio {ratio}, within the bound")
            elif rc == 0 and ratio is not None and ratio > 1.0:
                pass  # stable beyond the bound: the bound is conservative
            elif rc != 0:
                fails.append(f"pair{ds:g}_{key}: exit {rc}")
        rc, res = out[f"auto_{key}"]
        if rc != 0 or not res.get("dt_stiffness_ratio", 9) <= 1.01:
            fails.append(f"auto_{key}: exit {rc}, ratio {res.get('dt_stiffness_ratio')}")
        auto = (f"{res['dt_min'] / res['dt_elastic']:.3f}, {res['dt_stiffness_ratio']:.2f}"
                if rc == 0 and res else f"exit {rc}")
        rows.append(f"| {c[0]} | {c[1]:g} a | {c[2]:g} | {c[3]:g} | {c[4]:g} | " +
                    " | ".join(cells) + f" | {auto} |")
    print(f"pair_blowups={len(blown)}")
    print(f"pair_smallest_ratio_blown={min(blown) if blown else float('nan'):.4g}")
    print(f"study_failures={len(fails)}")
    for f in fails:
        print("FAIL:", f, file=sys.stderr)
    if a.table:
        with open(a.table, "w") as fh:
            fh.write("\n".join(rows) + "\n")
    return 1 if (a.check and fails) else 0


if __name__ == "__main__":
    sys.exit(main())
