#!/usr/bin/env python3
"""Benchmark of the resuspension scene (label "bench"): standard error of the steady profile
versus simulated (averaged) strain, and wall time.

Runs the scene (vorticity orientation by default: no artificial shear drag, which in the
gradient orientation also slows the settling transient; N = 300) for several total strains with
the same start of averaging; for each prints one line of name=value figures:
  strain=..  averaged_strain=..  wall_s=..  steps=..  steps_per_s=..  particle_steps_per_s=..
  mean_phi_err=.. (mean standard error of phi over the bulk bins)  max_phi_err=..
  height=.. height_err=..  cpu_s=.. (CPU seconds of the engine: not inflated by other load)
  eta_at_<phi>=.. eta_err_at_<phi>=.. for the two --eta-phi values (eta_22 in the gradient
  orientation, eta_33 in the vorticity one; local ln-linear fit of the bulk bins of
  /profiles/eta_vs_phi, helper eta_at of tests/resuspension/resuspension_consistency.py)
and finally the fitted exponent of mean_phi_err ~ averaged_strain^p (p = -1/2 expected once
the averaging window is longer than the correlation strain). The runs share the seed, so each
is a prefix of the longest trajectory. With --table DIR it writes DIR/resuspension_error.md and
DIR/resuspension_error.png.
usage: resuspension_bench.py --lubdem PATH --out DIR [--strains 6 12 24] [--n 300]
                             [--orientation gradient|vorticity] [--eta-phi 0.40 0.45] [--reuse]
                             [--stiffness K] [--table DIR]
"""
import argparse
import json
import os
import resource
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..",
                                "resuspension"))
from resuspension_consistency import eta_at  # noqa: E402  (ln-linear local fit of eta(phi))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lubdem", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--strains", type=float, nargs="+", default=[20.0, 30.0, 50.0])
    ap.add_argument("--average-from", type=float, default=15.0)
    ap.add_argument("--n", type=int, default=300)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--orientation", default="vorticity")
    ap.add_argument("--eta-phi", type=float, nargs=2, default=[0.40, 0.45])
    ap.add_argument("--stiffness", type=float, default=None,
                    help="contact stiffness in eta gd a (default: the scene's)")
    ap.add_argument("--table", default="", help="folder for the md table and the png plot")
    ap.add_argument("--reuse", action="store_true", help="analyse finished runs found in --out")
    args = ap.parse_args()
    rows = []
    print(f"config_n={args.n} config_orientation={args.orientation} "
          f"config_average_from={args.average_from} config_stiffness={args.stiffness}")
    for strain in args.strains:
        d = os.path.join(args.out, f"strain{strain:g}")
        os.makedirs(d, exist_ok=True)
        spec = {"scene": "resuspension", "n": args.n, "width": 12, "strain": strain,
                "average_from": args.average_from, "shields": 0.5, "inertial_number": 0.05,
                "density_ratio": 10, "shear_drag_viscosity": 3, "sample_strain": 0.05,
                "orientation": args.orientation,
                "snapshots": 0}
        if args.stiffness is not None:
            spec["stiffness"] = args.stiffness
        with open(os.path.join(d, "spec.json"), "w") as fh:
            json.dump(spec, fh)
        cpu_file = os.path.join(d, "cpu_seconds.txt")
        if args.reuse and os.path.exists(os.path.join(d, "run", "summary.json")):
            cpu = float(open(cpu_file).read()) if os.path.exists(cpu_file) else float("nan")
        else:
            r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
            p = subprocess.run([args.lubdem, "run", os.path.join(d, "spec.json"), "--out",
                                os.path.join(d, "run"), "--threads", str(args.threads),
                                "--quiet"], capture_output=True, text=True)
            r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
            if p.returncode != 0:
                print(f"run failed: {p.stderr}", file=sys.stderr)
                return 1
            with open(cpu_file, "w") as fh:
                fh.write(f"{cpu:.3f}\n")
        s = json.load(open(os.path.join(d, "run", "summary.json")))
        with h5py.File(os.path.join(d, "run", "result.h5"), "r") as f:
            err = f["profiles/phi_err"][:]
            keep = f["profiles/bulk_mask"][:] > 0.5
            evp = f["profiles/eta_vs_phi"][:] if "profiles/eta_vs_phi" in f else np.zeros((0, 4))
        r = s["results"]
        crushed = (r.get("crushed_contact_fraction") or {}).get("value", float("nan"))
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
              f"phi_err_method=\"{s['phi_err_method']}\" cpu_s={cpu:.1f} "
              f"crushed_contact_fraction={crushed:.3f}", end="")
        row = {"strain": strain, "avg": avg, "cpu_s": cpu, "mean_phi_err": me,
               "height": r["suspension_height"]["value"],
               "height_err": r["suspension_height"]["stderr"]}
        for ph in args.eta_phi:
            eta, eerr, nb = eta_at(evp, ph)
            row[f"eta_{ph:g}"], row[f"eta_err_{ph:g}"], row[f"bins_{ph:g}"] = eta, eerr, nb
            print(f" eta_at_{ph:g}={eta:.4g} eta_err_at_{ph:g}={eerr:.3g} bins_at_{ph:g}={nb}",
                  end="")
        print()
        rows.append(row)
        sys.stdout.flush()
    fit = [(r["avg"], r["mean_phi_err"]) for r in rows
           if np.isfinite(r["mean_phi_err"]) and r["mean_phi_err"] > 0]
    if len(fit) >= 2:
        xs, ys = zip(*fit)
        slope = np.polyfit(np.log(xs), np.log(ys), 1)[0]
        print(f"phi_err_strain_exponent={slope:.3f}")
    if args.table and rows:
        write_table(args, rows)
    return 0


def write_table(args, rows):
    os.makedirs(args.table, exist_ok=True)
    comp = "eta_22" if args.orientation == "gradient" else "eta_33"
    e1, e2 = args.eta_phi
    with open(os.path.join(args.table, "resuspension_error.md"), "w") as fh:
        fh.write(f"resuspension, {args.orientation} orientation, N = {args.n}, Sh = 0.5, "
                 f"averaging from strain {args.average_from:g}, 1 thread; errors: standard error (engine/stats.h) "
                 f"of the bins (phi), the summary's error of the half-maximum height (delta method over the "
                 f"averaging window), local fit for {comp}\n\n")
        fh.write(f"| strain | averaged strain | CPU s | mean SEM(phi) bulk bins | height (a) | "
                 f"{comp}({e1:g}) | {comp}({e2:g}) |\n|---|---|---|---|---|---|---|\n")
        for r in rows:
            fh.write(f"| {r['strain']:g} | {r['avg']:g} | {r['cpu_s']:.0f} | "
                     f"{r['mean_phi_err']:.4f} | {r['height']:.2f} ± {r['height_err'] or 0:.2f} | "
                     f"{r[f'eta_{e1:g}']:.3g} ± {r[f'eta_err_{e1:g}']:.2g} | "
                     f"{r[f'eta_{e2:g}']:.3g} ± {r[f'eta_err_{e2:g}']:.2g} |\n")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    avg = [r["avg"] for r in rows]
    cpu = [r["cpu_s"] for r in rows]
    ax[0].loglog(avg, [r["mean_phi_err"] for r in rows], "o-", label="mean SEM(phi), bulk bins")
    a0, y0 = avg[0], rows[0]["mean_phi_err"]
    ax[0].loglog(avg, [y0 * (a / a0) ** -0.5 for a in avg], "k--", lw=0.8, label="strain^-1/2")
    ax[0].set_xlabel("averaged strain")
    ax[0].set_ylabel("SEM(phi)")
    ax[0].legend(fontsize=8)
    for ph in args.eta_phi:
        rel = [r[f"eta_err_{ph:g}"] / r[f"eta_{ph:g}"] for r in rows]
        ax[1].loglog(cpu, rel, "o-", label=f"rel. error of {comp}({ph:g})")
    ax[1].set_xlabel("run time [CPU s, 1 thread]")
    ax[1].set_ylabel("relative error")
    ax[1].legend(fontsize=8)
    fig.suptitle(f"resuspension error vs strain and run time ({args.orientation}, N = {args.n})")
    fig.tight_layout()
    fig.savefig(os.path.join(args.table, "resuspension_error.png"), dpi=110)
    print(f"plot={os.path.join(args.table, 'resuspension_error.png')}")


if __name__ == "__main__":
    sys.exit(main())
