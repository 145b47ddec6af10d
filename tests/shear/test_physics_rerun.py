#!/usr/bin/env python3
"""run_physics.py --from-csv ... --rerun: the named cases and the cases missing from the CSV are
run again and replace their rows; every other row is kept as the CSV has it.

Takes the committed table.csv, drops the row of ref_iv_1 (so that it must be run because it is
missing), puts sentinel values into the row of ref_nlonly_iv_1 and asks for that case by
--rerun (the two cheapest cases of the sweep, ~4 s each at N = 300). Checks that:
  * the output has the plan's rows in the committed order;
  * the two rerun rows hold the values of the summaries just written (phi, mu, eta_r);
  * every other row equals the committed one, cell for cell;
  * an unknown case name is refused with exit 2 and names the case;
  * the quick table read without --quick is refused with exit 2 (it would mix 10- and
    20-strain rows and run the whole full plan).
Prints rerun_rows=2 kept_rows=N on success.

usage: test_physics_rerun.py --run-physics PATH --lubdem PATH --csv TABLE_CSV --out DIR
"""
import argparse
import csv
import json
import os
import subprocess
import sys

MISSING, EXPLICIT = "ref_iv_1", "ref_nlonly_iv_1"


def read_rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--run-physics", required=True)
    ap.add_argument("--lubdem", required=True)
    ap.add_argument("--csv", required=True)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    committed = read_rows(a.csv)
    names = [r["name"] for r in committed]
    for n in (MISSING, EXPLICIT):
        if n not in names:
            sys.exit(f"FAIL the committed table has no row {n}")
    partial = os.path.join(a.out, "partial.csv")
    with open(partial, "w", newline="") as out:
        w = csv.DictWriter(out, fieldnames=list(committed[0]))
        w.writeheader()
        for r in committed:
            if r["name"] == EXPLICIT:  # a row the rerun must replace, not keep
                r = dict(r, phi="0.123", mu="9.87", eta_r="6.54")
            if r["name"] != MISSING:
                w.writerow(r)
    run_dir = os.path.join(a.out, "rerun")
    base = [sys.executable, a.run_physics, "--from-csv", partial, "--lubdem", a.lubdem,
            "--quick", "--jobs", "2"]
    p = subprocess.run(base + ["--rerun", EXPLICIT, "--out", run_dir],
                       capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"FAIL run_physics exited {p.returncode}: {p.stderr.strip()[-500:]}")
    fails = []
    got = read_rows(os.path.join(run_dir, "table.csv"))
    if [r["name"] for r in got] != names:
        fails.append("row order or set differs from the committed table")
    by = {r["name"]: r for r in got}
    kept = 0
    for r in committed:
        n = r["name"]
        g = by.get(n)
        if g is None:
            continue
        if n in (MISSING, EXPLICIT):
            with open(os.path.join(run_dir, n, "summary.json")) as fh:
                res = json.load(fh)["results"]
            for k in ("phi", "mu", "eta_r"):
                if abs(float(g[k]) - res[k]["value"]) > 1e-9 * abs(res[k]["value"]):
                    fails.append(f"{n}: {k} {g[k]} is not the summary's {res[k]['value']}")
            continue
        # the committed CSV may lack columns added since (empty cells in the output)
        diff = [k for k in r if r[k] != g.get(k, "")]
        if diff:
            fails.append(f"{n}: kept row changed in {diff[:5]}")
        kept += 1
    q = subprocess.run(base + ["--rerun", "no_such_case", "--out", os.path.join(a.out, "bad")],
                       capture_output=True, text=True)
    if q.returncode != 2 or "no_such_case" not in q.stderr:
        fails.append(f"unknown case: exit {q.returncode}, stderr {q.stderr.strip()[-200:]!r}")
    no_quick = [x for x in base if x != "--quick"]
    q = subprocess.run(no_quick + ["--rerun", EXPLICIT, "--out", os.path.join(a.out, "full")],
                       capture_output=True, text=True)
    if q.returncode != 2 or "strain differs" not in q.stderr:
        fails.append(f"quick table without --quick: exit {q.returncode}, "
                     f"stderr {q.stderr.strip()[-200:]!r}")
    for f in fails:
        print("FAIL", f, file=sys.stderr)
    print(f"rerun_rows=2 kept_rows={kept}")
    sys.exit(1 if fails else 0)


if __name__ == "__main__":
    main()
