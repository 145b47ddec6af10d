#!/usr/bin/env python3
"""run_physics.py --check on altered copies of the committed table.csv: a known miss (a
criterion in KNOWN_MISSES, which the engine misses today) fails --check when it leaves its band.
Until 2026-12-07 a known miss passed at any value, so that mu three times the seed's law at
Iv = 1, or eta_r a tenth of it at phi = 0.35, passed the physics suite.

Each case scales one value of one row and expects run_physics.py to exit 1 and print
outside_band=1 for that criterion (a miss that grew: mu_ref_iv_1 x 3, eta_r_ref_phi_0.35 x 0.1,
eta_r_delaunay_phi_0.55 x 10, phi_ref_mu0_iv_0.1 x 1.2, mu_delaunay_mu1_iv_0.01 x 2; one that
overshot the reference: mu_ref_iv_1 x 1.4, +23 % against a tolerance of 10 %), or to exit 0
when the value moves inside the band (eta_r_ref_phi_0.55 x 1.1, still known_miss=1). The
unaltered table passes (shear.committed_table checks that too). Last, a table whose stored
seed reference differs from the formula's (phi_ref of ref_iv_0.1 + 0.02) fails as a table
that is not the plan's (until 2026-12-07 the criteria used the table's own references
unchecked). Prints band_cases=N.

usage: test_known_miss_bands.py --run-physics PATH --csv TABLE_CSV --out DIR
"""
import argparse
import csv
import os
import subprocess
import sys

CASES = [  # (row, column, factor, criterion, expected exit code)
    ("ref_iv_1", "mu", 3.0, "mu_ref_iv_1", 1),
    ("ref_phi_0.35", "eta_r", 0.1, "eta_r_ref_phi_0.35", 1),
    ("delaunay_phi_0.55", "eta_r", 10.0, "eta_r_delaunay_phi_0.55", 1),
    ("ref_mu0_iv_0.1", "phi", 1.2, "phi_ref_mu0_iv_0.1", 1),
    ("delaunay_mu1_iv_0.01", "mu", 2.0, "mu_delaunay_mu1_iv_0.01", 1),
    ("ref_iv_1", "mu", 1.4, "mu_ref_iv_1", 1),
    ("ref_phi_0.55", "eta_r", 1.1, "eta_r_ref_phi_0.55", 0),
]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--run-physics", required=True)
    ap.add_argument("--csv", required=True)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    with open(a.csv, newline="") as fh:
        reader = csv.DictReader(fh)
        fields, rows = reader.fieldnames, list(reader)
    bad = 0
    for k, (name, col, factor, crit, want) in enumerate(CASES):
        altered = [dict(r) for r in rows]
        hits = [r for r in altered if r["name"] == name]
        if len(hits) != 1:
            print(f"FAIL: row {name} not found once in {a.csv}")
            return 1
        hits[0][col] = repr(float(hits[0][col]) * factor)
        path = os.path.join(a.out, f"altered_{k}.csv")
        with open(path, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=fields)
            w.writeheader()
            w.writerows(altered)
        p = subprocess.run([sys.executable, a.run_physics, "--from-csv", path, "--out",
                            os.path.join(a.out, f"out_{k}"), "--check", "--quick"],
                           capture_output=True, text=True)
        line = next((l for l in p.stdout.splitlines()
                     if l.startswith(f"criterion={crit} ")), "")
        flagged = "outside_band=1" in line
        ok = p.returncode == want and flagged == (want == 1) and \
            (want == 1 or "known_miss=1" in line)
        print(f"case={name}:{col}x{factor:g} rc={p.returncode} want={want} {line}")
        if not ok:
            print(f"FAIL: {name} {col} x {factor:g}: exit {p.returncode}, expected {want}")
            bad += 1
    altered = [dict(r) for r in rows]
    for r in altered:
        if r["name"] == "ref_iv_0.1":
            r["phi_ref"] = repr(float(r["phi_ref"]) + 0.02)
    path = os.path.join(a.out, "altered_reference.csv")
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=fields)
        w.writeheader()
        w.writerows(altered)
    p = subprocess.run([sys.executable, a.run_physics, "--from-csv", path, "--out",
                        os.path.join(a.out, "out_reference"), "--check", "--quick"],
                       capture_output=True, text=True)
    seen = "table against plan: ref_iv_0.1: phi_ref is" in p.stderr
    print(f"case=ref_iv_0.1:phi_ref+0.02 rc={p.returncode} want=1 named={int(seen)}")
    if p.returncode != 1 or not seen:
        print("FAIL: a stored reference that is not the formula's passes")
        bad += 1
    print(f"band_cases={len(CASES)}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
