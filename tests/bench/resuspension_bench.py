#!/usr/bin/env python3
"""Benchmark of the resuspension scene (label "bench"): standard error of the steady profile
versus simulated (averaged) strain, and wall time.

Runs the scene (vorticity orientation by default: no artificial shear drag, which in the
gradient orientation also slows the settling transient; N = 300) for several total strains with
the same start of averaging; for each prints one line of name=value figures:
  strain=..  averaged_strain=..  wall_s=..  steps=..  steps_per_s=..  particle_steps_per_s=..
  mean_phi_err=.. (mean blocking SEM of phi over the bulk bins)  max_phi_err=..
  height=.. height_err=..
and finally the fitted exponent of mean_phi_err ~ averaged_strain^p (p = -1/2 expected once
the averaging window is longer than the correlation strain).
usage: resuspension_bench.py --lubdem PATH --out DIR [--strains 6 12 24] [--n 300]
"""
import argparse
import json
import os
import subprocess
import sys

import h5py
import numpy as np


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lubdem", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--strains", type=float, nargs="+", default=[20.0, 30.0, 50.0])
    ap.add_argument("--average-from", type=float, default=15.0)
    ap.add_argument("--n", type=int, default=300)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--orientation", default="vorticity")
    args = ap.parse_args()
    xs, ys = [], []
    print(f"config_n={args.n} config_orientation={args.orientation} "
          f"config_average_from={args.average_from}")
    for strain in args.strains:
        d = os.path.join(args.out, f"strain{strain:g}")
        os.makedirs(d, exist_ok=True)
        spec = {"scene": "resuspension", "n": args.n, "width": 12, "strain": strain,
                "average_from": args.average_from, "shields": 0.5, "inertial_number": 0.05,
                "density_ratio": 10, "shear_drag_viscosity": 3, "sample_strain": 0.05,
                "orientation": args.orientation,
                "snapshots": 0}
        with open(os.path.join(d, "spec.json"), "w") as fh:
            json.dump(spec, fh)
        p = subprocess.run([args.lubdem, "run", os.path.join(d, "spec.json"), "--out",
                            os.path.join(d, "run"), "--threads", str(args.threads), "--quiet"],
                           capture_output=True, text=True)
        if p.returncode != 0:
            print(f"run failed: {p.stderr}", file=sys.stderr)
            return 1
        s = json.load(open(os.path.join(d, "run", "summary.json")))
        with h5py.File(os.path.join(d, "run", "result.h5"), "r") as f:
            err = f["profiles/phi_err"][:]
            keep = f["profiles/bulk_mask"][:] > 0.5
        r = s["results"]
        wall = s["wall_time_s"]
        steps = s["steps"]
        me = float(np.nanmean(err[keep])) if keep.any() else float("nan")
        mx = float(np.nanmax(err[keep])) if keep.any() else float("nan")
        avg = strain - args.average_from
        print(f"strain={strain:g} averaged_strain={avg:g} wall_s={wall:.2f} steps={steps} "
              f"steps_per_s={steps / wall:.1f} particle_steps_per_s={args.n * steps / wall:.3g} "
              f"mean_phi_err={me:.5f} max_phi_err={mx:.5f} "
              f"height={r['suspension_height']['value']:.3f} "
              f"height_err={r['suspension_height']['stderr']} "
              f"phi_err_method=\"{s['phi_err_method']}\"")
        sys.stdout.flush()
        if np.isfinite(me) and me > 0:
            xs.append(avg)
            ys.append(me)
    if len(xs) >= 2:
        slope = np.polyfit(np.log(xs), np.log(ys), 1)[0]
        print(f"phi_err_strain_exponent={slope:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
