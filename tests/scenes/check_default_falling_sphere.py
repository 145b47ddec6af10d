#!/usr/bin/env python3
"""Regression: the falling_sphere defaults (what a first job through the service runs) are the
viscous rigid limit, so the summary must report the exponential rate 8/9 (physics-reference
§1a; tolerance 1e-3 relative, the issue's bound) and the regime "damped". This failed when
elastic ringing after the release ended the fit window and the monotone exponential approach
was counted as an oscillation.  usage: check_default_falling_sphere.py LUBDEM"""
import json
import subprocess
import sys
import tempfile

lubdem = sys.argv[1]
with tempfile.TemporaryDirectory() as out:
    subprocess.run([lubdem, "run", "-", "--out", out, "--quiet"], input='{"scene": "falling_sphere"}',
                   text=True, check=True)
    s = json.load(open(f"{out}/summary.json"))
r = s["results"]
rate = r["exp_rate"]["value"]
print(f"default_exp_rate={rate}")
print(f"default_regime={s.get('regime')}")
ok = rate is not None and abs(rate / (8 / 9) - 1) < 1e-3 and s.get("regime") == "damped"
print(f"{int(ok)} passed, {int(not ok)} failed")
sys.exit(0 if ok else 1)
