#!/usr/bin/env python3
"""Issue 4 item 1 ("N up to 10^4"): the vorticity-orientation resuspension at two particle
numbers, same bed height, everything else equal; is the N = 600 of the consistency study
(resuspension_consistency.py) large enough?

Both runs use the consistency study's vorticity spec (Sh, I = 0.04, density_ratio 10, the
scene's law, stiffness --stiffness); the cell width grows as sqrt(N) (12 a at N = 600) so
that the settled bed keeps the same height. Compared, per N:
  - the relative height increase (h - h0)/h0, as in the summary and floor-corrected (height
    from the bottom half-max crossing of the averaged profile, as in the Acrivos table);
  - eta_33 at phi = 0.40 and 0.45 from the run's own bulk bins (phi averaged over 2 a, ln eta
    fitted linearly within ±0.02: resuspension_consistency.bulk_pairs and eta_at);
  - the rms difference of the averaged profiles phi(y) over the bulk bins of both runs, against
    the rms of their combined error bars;
  - cost: wall time, particle-steps per second.
Prints name=value lines and a markdown table (--table). A long run (N = 1e4 at stiffness 1e6:
about an hour on 2 cores), therefore not a ctest.
usage: finite_size.py --lubdem PATH --out DIR [--n 600 10000] [--shields 1] [--strain 40]
                      [--average-from 20] [--stiffness 1e6] [--threads 2] [--reuse] [--table F] [--figure PNG]
"""
import argparse
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from resuspension_consistency import (bulk_pairs, check_bed_base, eta_at,  # noqa
                                      floor_plane_rel, half_max_crossings, law_spec, run,
                                      summary, val)


def spec_for(n, args):
    return {"scene": "resuspension", "orientation": "vorticity", "n": n,
            "width": round(12.0 * np.sqrt(n / 600.0), 1), "shields": args.shields,
            "inertial_number": 0.04, "density_ratio": 10.0, "stiffness": args.stiffness,
            "cutoff": 2.0, "radius_std": 0.05, "law": law_spec(), "sample_strain": 0.1,
            "seed": 1, "snapshots": 0, "strain": args.strain, "average_from": args.average_from}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lubdem", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--n", type=int, nargs="+", default=[600, 10000])
    ap.add_argument("--shields", type=float, default=1.0)
    ap.add_argument("--strain", type=float, default=40.0)
    ap.add_argument("--average-from", type=float, default=20.0)
    ap.add_argument("--stiffness", type=float, default=1e6)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--reuse", action="store_true")
    ap.add_argument("--table")
    ap.add_argument("--figure")
    ap.add_argument("--phi-window", type=float, default=2.0,
                    help="phi averaged over this width (a) before pairing with eta_33")
    args = ap.parse_args()
    rows = []
    for n in args.n:
        spec = spec_for(n, args)
        out = run(args.lubdem, spec, os.path.join(args.out, f"vorticity_sh{args.shields:g}_n{n}"),
                  args.reuse, threads=args.threads)
        s = summary(out)
        with h5py.File(os.path.join(out, "result.h5"), "r") as f:
            y, phi = f["profiles/y"][:], f["profiles/phi"][:]
            perr, mask = f["profiles/phi_err"][:], f["profiles/bulk_mask"][:].astype(bool)
            w_eng = s.get("spec", {}).get("analysis", {}).get("phi_window", 2.0)
            ev = bulk_pairs(f, args.phi_window, w_eng)
        h, herr = val(s, "suspension_height")
        h0 = val(s, "settled_height")[0]
        yb, _ = half_max_crossings(y, phi)
        check_bed_base(s, yb, h, h0)
        r = dict(n=n, width=spec["width"], rel=floor_plane_rel(s)[0], err=herr / h0,
                 rel_c=(h - yb - h0) / h0, h0=h0, wall=s["wall_time_s"],
                 steps=s.get("steps", float("nan")), steady=s.get("height_steady"),
                 crushed=val(s, "crushed_contact_fraction")[0], y=y, phi=phi, perr=perr,
                 mask=mask, bins=len(ev))
        r["rate"] = n * r["steps"] / r["wall"] if np.isfinite(r["steps"]) else float("nan")
        for pt in (0.40, 0.45):
            r[f"eta{pt:g}"] = eta_at(ev, pt, corr=(2.0 + args.phi_window) / 0.5)
        rows.append(r)
        print(f"finite_size_n{n}_width={r['width']:g} h0={h0:.3f} rel_height_increase="
              f"{r['rel']:.4f} err={r['err']:.4f} rel_floor_corrected={r['rel_c']:.4f} "
              f"eta33_0.40={r['eta0.4'][0]:.4g} err={r['eta0.4'][1]:.3g} "
              f"eta33_0.45={r['eta0.45'][0]:.4g} err={r['eta0.45'][1]:.3g} bulk_bins={r['bins']} "
              f"crushed={r['crushed']:.4f} steady={r['steady']} wall_s={r['wall']:.0f} "
              f"particle_steps_per_s={r['rate']:.3g}")
    # profile comparison of the first and last N on the common y grid (same bin width), raw bins
    a, b = rows[0], rows[-1]
    k = min(len(a["y"]), len(b["y"]))
    same_grid = np.allclose(a["y"][:k], b["y"][:k])
    both = a["mask"][:k] & b["mask"][:k]
    if same_grid and both.any():
        d = a["phi"][:k][both] - b["phi"][:k][both]
        e = np.hypot(a["perr"][:k][both], b["perr"][:k][both])
        print(f"profile_bins_compared={int(both.sum())} rms_phi_difference="
              f"{np.sqrt(np.mean(d ** 2)):.4f} rms_combined_error={np.sqrt(np.mean(e ** 2)):.4f} "
              f"mean_phi_difference={np.mean(d):+.4f}")
    else:
        print("profile_bins_compared=0")
    if args.figure:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 4.5))
        for r in rows:
            ax.errorbar(r["phi"], r["y"], xerr=r["perr"], fmt="-", lw=0.8, label=f"N = {r['n']}")
        ax.set_ylim(0, 1.2 * max(float(r["y"][r["phi"] > 0.01].max()) for r in rows))
        ax.set_xlabel("phi (0.5 a bins)"); ax.set_ylabel("y (a)")
        ax.set_title(f"vorticity resuspension, Sh = {args.shields:g}, stiffness {args.stiffness:g}")
        ax.legend()
        fig.tight_layout()
        fig.savefig(args.figure, dpi=100)
    if args.table:
        with open(args.table, "w") as fh:
            fh.write(f"Vorticity orientation, Sh = {args.shields:g}, I = 0.04, density_ratio 10, "
                     f"stiffness {args.stiffness:g}, strain {args.strain:g} averaged from "
                     f"{args.average_from:g}, cell width 12 a sqrt(N/600).\n\n")
            fh.write("| N | width (a) | h0 (a) | (h-h0)/h0 summary | floor-corr. | η_33(0.40) | "
                     "η_33(0.45) | bulk bins | crushed | steady | wall s | particle-steps/s |\n")
            fh.write("|---|---|---|---|---|---|---|---|---|---|---|---|\n")
            for r in rows:
                fh.write(f"| {r['n']} | {r['width']:g} | {r['h0']:.2f} | {r['rel']:.3f} ± "
                         f"{r['err']:.4f} | {r['rel_c']:.3f} | {r['eta0.4'][0]:.3g} ± "
                         f"{r['eta0.4'][1]:.2g} | {r['eta0.45'][0]:.3g} ± {r['eta0.45'][1]:.2g} | "
                         f"{r['bins']} | {r['crushed']:.4f} | {r['steady']} | {r['wall']:.0f} | "
                         f"{r['rate']:.3g} |\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
