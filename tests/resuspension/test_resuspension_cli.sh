#!/usr/bin/env bash
# CLI-level checks of the resuspension scene: a short complete run (summary schema, H5MD
# structure, profiles and time series present and consistent), SIGTERM during a long run
# (exit code 5, status "partial", valid H5MD with the profiles averaged so far), fixed and
# adapted time steps, specs refused for their length, sample count, step count, a cell too
# narrow for the cut-off or a bed too heavy for its contacts (exit 2), a bed sinking through
# the floor blamed on its weight (exit 3), a
# step count only the bed decides (exit 2 from the run, status failed), and an
# address-space limit too small for the system (exit 1, "out of memory", the limit, /n).
# usage: test_resuspension_cli.sh LUBDEM PYTHON CHECK_H5MD SCHEMA_DIR
set -u
LUBDEM=$1 PY=$2 CHECK=$3 SCHEMA_DIR=$4
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }

cat > "$work/short.json" <<'JEOF'
{"scene": "resuspension", "n": 150, "width": 12, "strain": 0.6, "average_from": 0.2,
 "sample_strain": 0.05, "inertial_number": 0.05, "density_ratio": 10,
 "shear_drag_viscosity": 3, "snapshots": 3}
JEOF
"$LUBDEM" run "$work/short.json" --out "$work/run1" --threads 1 > /dev/null 2> "$work/run1.err"
rc=$?
[ $rc -eq 0 ] && ok || bad "short run exit code $rc: $(cat "$work/run1.err")"
$PY "$CHECK" "$work/run1/result.h5" --status complete > /dev/null && ok || bad "H5MD structure"
$PY - "$work/run1" "$SCHEMA_DIR/summary.schema.json" <<'PYEOF' && ok || bad "summary/profiles"
import json, sys
import h5py, jsonschema, numpy as np
d = sys.argv[1]
s = json.load(open(d + "/summary.json"))
jsonschema.validate(s, json.load(open(sys.argv[2])))
assert s["status"] == "complete" and "gravity" in s["active_terms"] and "shear_drag" in s["active_terms"]
assert s["units"]["length"].startswith("a")
with h5py.File(d + "/result.h5", "r") as f:
    y = f["profiles/y"][:]; phi = f["profiles/phi"][:]; err = f["profiles/phi_err"][:]
    eta = f["profiles/eta_normal"][:]; mask = f["profiles/bulk_mask"][:]
    assert len(y) == len(phi) == len(err) == len(eta) == len(mask) > 10
    assert np.all(np.isfinite(phi)) and phi.max() > 0.3 and np.all(phi >= 0)
    dy = y[1] - y[0]
    inv = phi.sum() * dy
    assert abs(inv - s["results"]["inventory"]["value"]) < 1e-9 * inv
    assert np.all(np.diff(eta) <= 1e-12)          # eta_ii(y) decreases with height
    h = f["observables/suspension_height/value"][:]
    assert len(h) >= 10 and np.all(np.isfinite(h))
    assert f["particles/all/position/value"].shape[0] == 3
PYEOF

cat > "$work/long.json" <<'JEOF'
{"scene": "resuspension", "n": 150, "width": 12, "strain": 500, "average_from": 0.05,
 "sample_strain": 0.05, "inertial_number": 0.05, "density_ratio": 10}
JEOF
"$LUBDEM" run "$work/long.json" --out "$work/run2" --threads 1 > /dev/null 2> "$work/run2.err" &
pid=$!
sleep 4
kill -TERM $pid
for _ in $(seq 1 100); do kill -0 $pid 2>/dev/null || break; sleep 0.1; done
if kill -0 $pid 2>/dev/null; then bad "did not stop within 10 s of SIGTERM"; kill -9 $pid; fi
wait $pid
rc=$?
[ $rc -eq 5 ] && ok || bad "SIGTERM exit code $rc (expected 5): $(cat "$work/run2.err")"
$PY -c "import json; s=json.load(open('$work/run2/summary.json')); assert s['status']=='partial'" \
  && ok || bad "partial summary status"
# why it stopped, and --resume rather than a longer /strain (until 2026-12-06: no diagnostic,
# "increase /strain" with /strain 500)
$PY -c "
import json; s = json.load(open('$work/run2/summary.json')); w = s.get('warnings', [])
assert s['diagnostic'].startswith('stopped by a signal (SIGTERM)') and '--resume' in s['diagnostic'], s
assert not any('increase /strain' in x for x in w), w
assert s['height_steady'] or any('stopped by a signal' in x and '--resume' in x for x in w), w" \
  && ok || bad "stopped run's diagnostic and warnings: $(cat "$work/run2/summary.json")"
$PY "$CHECK" "$work/run2/result.h5" --status partial > /dev/null && ok || bad "partial H5MD"
$PY -c "
import h5py, numpy as np
f = h5py.File('$work/run2/result.h5', 'r')
assert np.all(np.isfinite(f['profiles/phi'][:]))" && ok || bad "partial profiles"

# stopped before /average_from (no profile averaged): what the averaging window measures is null,
# not 0 (until 2026-12-06 max_phi, bulk_bins and crushed_contact_fraction were 0, the last hiding
# the crushed-asperity warning of a heavy bed), and a warning says so
cat > "$work/early.json" <<'JEOF'
{"scene": "resuspension", "n": 150, "width": 12, "strain": 500, "average_from": 400,
 "sample_strain": 0.05, "inertial_number": 0.05, "density_ratio": 10}
JEOF
"$LUBDEM" run "$work/early.json" --out "$work/run2e" --threads 1 > /dev/null 2> "$work/run2e.err" &
pid=$!
sleep 2
kill -TERM $pid
wait $pid
rc=$?
[ $rc -eq 5 ] && ok || bad "early SIGTERM exit code $rc (expected 5): $(cat "$work/run2e.err")"
$PY - "$work/run2e" "$SCHEMA_DIR/summary.schema.json" <<'PYEOF' && ok || bad "stopped before averaging: nulls/warning"
import json, sys
import jsonschema
s = json.load(open(sys.argv[1] + "/summary.json"))
jsonschema.validate(s, json.load(open(sys.argv[2])))
r = s["results"]
assert s["status"] == "partial" and r["averaged_samples"]["value"] == 0, r["averaged_samples"]
nulls = ("max_phi", "crushed_contact_fraction", "bulk_bins", "suspension_height", "inventory",
         "settled_height", "relative_height_increase", "acrivos", "eta_vs_law_log_rms",
         "bulk_velocity_slope", "bed_base_height", "relative_height_increase_floor_plane")
for k in nulls:
    assert r[k]["value"] is None, (k, r[k])
# the warning names exactly the null members (2026-12-07: it named 5 of them)
w = [x for x in s["warnings"] if "no profile was averaged" in x]
assert len(w) == 1, s["warnings"]
named = set(w[0].split("measures (")[1].split(")")[0].split(", "))
null = {k for k, v in r.items() if v["value"] is None}
assert named == null == set(nulls) | ({"shear_drag_weight_share"} & set(r)), (named, null)
import h5py
with h5py.File(sys.argv[1] + "/result.h5", "r") as f:   # the floor plane even without profiles
    assert f["profiles/y_floor"].attrs["unit"] in (b"a", "a") and f["profiles/y_floor"][0] > 1
PYEOF

# a time step fixed far above the elastic bound: numerical failure (exit 3, status failed) whose
# diagnostic names the particle flung across the cell in one step, says that /dt caused it and
# how to fix it
cat > "$work/bigdt.json" <<'JEOF'
{"scene": "resuspension", "n": 100, "dt": 0.5, "strain": 1, "average_from": 0.5,
 "snapshots": 0}
JEOF
"$LUBDEM" run "$work/bigdt.json" --out "$work/run3" --threads 1 > /dev/null 2> "$work/run3.err"
rc=$?
[ $rc -eq 3 ] && ok || bad "fixed dt 0.5: exit code $rc (expected 3)"
grep -q "^error: .*the spec fixes /dt = 0.5, .* times the stability bound dt_critical" \
  "$work/run3.err" && ok || bad "fixed dt 0.5: diagnostic lacks the /dt hint: $(cat "$work/run3.err")"
grep -q "^error: particle [0-9]* moved .* a in one step" "$work/run3.err" && ok \
  || bad "fixed dt 0.5: the runaway particle is not named: $(cat "$work/run3.err")"
$PY -c "
import json; s = json.load(open('$work/run3/summary.json'))
assert s['status'] == 'failed' and '/dt_safety' in s['diagnostic'], s" \
  && ok || bad "fixed dt 0.5: summary"

# a fixed /dt 1.5x the bound that still completes: a warning naming /dt
cat > "$work/dt15.json" <<'JEOF'
{"scene": "resuspension", "n": 100, "dt": 1e-4, "strain": 0.3, "average_from": 0.1,
 "snapshots": 0}
JEOF
"$LUBDEM" run "$work/dt15.json" --out "$work/run4" --threads 1 > /dev/null 2> "$work/run4.err"
rc=$?
[ $rc -eq 0 ] && ok || bad "fixed dt 1e-4: exit code $rc"
$PY -c "
import json; s = json.load(open('$work/run4/summary.json'))
assert any('fixes /dt at 1.5' in w and 'lower /dt' in w for w in s['warnings']), s['warnings']" \
  && ok || bad "fixed dt 1e-4: no /dt warning"

# light, soft spheres with a 3 a cut-off (I = 0.01, stiffness 1e4): the single-pair step
# (/dt_stiffness_safety 0) blows up within 100 steps at a stiffness ratio of 1.35; the default
# lowers the step at the first neighbour-list rebuild and completes, its height series evenly
# spaced in strain
SOFT='"scene": "resuspension", "n": 150, "strain": 0.3, "average_from": 0.1, "snapshots": 0,
 "sample_strain": 0.01, "stiffness": 1e4, "inertial_number": 0.01, "cutoff": 3.0'
echo "{$SOFT, \"dt_stiffness_safety\": 0}" \
  | "$LUBDEM" run - --out "$work/run5" --threads 1 > /dev/null 2> "$work/run5.err"
rc=$?
[ $rc -eq 3 ] && grep -q "in one step.*lower /dt_safety" "$work/run5.err" && ok \
  || bad "single-pair step, soft spheres: exit $rc: $(cat "$work/run5.err")"
echo "{$SOFT}" | "$LUBDEM" run - --out "$work/run6" --threads 1 > /dev/null 2> "$work/run6.err"
rc=$?
[ $rc -eq 0 ] && ok || bad "adapted step, soft spheres: exit $rc: $(cat "$work/run6.err")"
$PY - "$work/run6" <<'PYEOF' && ok || bad "adapted step, soft spheres: summary/series"
import json, sys
import h5py, numpy as np
d = sys.argv[1]
r = {k: v["value"] for k, v in json.load(open(d + "/summary.json"))["results"].items()}
assert r["dt_changes"] >= 1 and r["dt_min"] < 0.3 * r["dt_critical"], r
assert r["dt_stiffness_ratio"] <= 1.01, r["dt_stiffness_ratio"]
t = h5py.File(d + "/result.h5")["observables/suspension_height/time"][:]
# every sample period is a whole number of steps: 0.01 apart within half a step, and one across
# a change at most one new step longer per change (the schedule rounds the next occurrence up, so
# that no interval is shorter than the sample buffers allow for); the last sample is the end of
# the run
dt1 = 0.3 * r["dt_critical"]
gaps = np.diff(t[:-1]) - 0.01
assert len(t) >= 30 and np.max(np.abs(gaps)) <= (0.5 + r["dt_changes"]) * dt1, t
assert np.min(gaps) >= -0.5 * dt1, t
assert abs(t[-1] - 0.3) <= 0.3 * r["dt_critical"], t[-1]
PYEOF
# the same bed at a fixed /dt 0.25 of the single-pair bound, 1.12 times the step its pairs'
# summed stiffness allows: completes (0.1 strain), with a warning naming /dt
echo '{"scene": "resuspension", "n": 150, "strain": 0.1, "average_from": 0.05, "snapshots": 0,
 "sample_strain": 0.01, "stiffness": 1e4, "inertial_number": 0.01, "cutoff": 3.0, "dt": 5.5e-5}' \
  | "$LUBDEM" run - --out "$work/run7" --threads 1 > /dev/null 2> "$work/run7.err"
rc=$?
[ $rc -eq 0 ] && grep -q "fixes /dt at 1.1.* summed stiffness .*lower /dt" "$work/run7.err" && ok \
  || bad "fixed dt above the stiffness bound: exit $rc, no warning: $(cat "$work/run7.err")"

# runs too long or sampled too finely for memory are refused up front (exit 2, nothing written,
# the member named); strain 1e12 used to fail after the set-up with "out of memory (188 bins x
# 9999764702598 samples)" and exit 1
echo '{"scene": "resuspension", "strain": 1e12}' \
  | "$LUBDEM" run - --out "$work/bad1" > /dev/null 2> "$work/bad1.err"
rc=$?
[ $rc -eq 2 ] && [ ! -e "$work/bad1" ] && grep -q "^error: /strain: must be <= 1000000" \
  "$work/bad1.err" && ok || bad "strain 1e12: exit $rc: $(cat "$work/bad1.err")"
echo '{"scene": "resuspension", "strain": 1000, "sample_strain": 1e-4}' \
  | "$LUBDEM" validate - > /dev/null 2> "$work/bad2.err"
rc=$?
[ $rc -eq 2 ] && grep -q "^error: /sample_strain: .* 1e+07 samples.*at least 0.001 " \
  "$work/bad2.err" && ok || bad "1e7 samples: exit $rc: $(cat "$work/bad2.err")"

# one averaged sample: no error bar, and phi_err_method says so (it named batch means)
echo '{"scene":"resuspension","n":150,"width":12,"strain":0.3,"average_from":0.295,"sample_strain":0.007,"snapshots":0}' \
  | "$LUBDEM" run - --out "$work/one" --quiet 2> "$work/one.err"
rc=$?
[ $rc -eq 0 ] && $PY -c '
import json, sys
s = json.load(open(sys.argv[1]))
assert s["results"]["averaged_samples"]["value"] == 1, s["results"]["averaged_samples"]
assert s["phi_err_method"] == "none (fewer than 2 samples)", s["phi_err_method"]' \
  "$work/one/summary.json" && ok || bad "one averaged sample: exit $rc $(cat "$work/one.err")"

# the step-count rule (README, CLI contract, "Step count"): from 1 to 1e12 steps, or exit 2
# naming the member, nothing created. These ran 0 steps with status complete (a step longer
# than the run) or took ~1e18 steps.
step_refused() { # name, spec, pointer, text in the message
  echo "$2" | "$LUBDEM" run - --out "$work/$1" --quiet 2> "$work/$1.err"
  local rc=$?
  echo "$2" | "$LUBDEM" validate - > /dev/null 2>&1
  local vrc=$?
  [ $rc -eq 2 ] && [ $vrc -eq 2 ] && [ ! -e "$work/$1" ] \
    && grep -q "^error: $3: the run would take .*$4" "$work/$1.err" && ok \
    || bad "step count $1: run $rc, validate $vrc: $(cat "$work/$1.err")"
}
small='"scene": "resuspension", "n": 20, "strain": 0.05, "average_from": 0, "sample_strain": 0.01'
step_refused light "{$small, \"shields\": 1e-300}" /shields "at least one whole step"
step_refused heavy "{$small, \"shields\": 1e300}" /shields "more than the 1e+12"
step_refused stiff "{$small, \"stiffness\": 1e300}" /stiffness "more than the 1e+12"
step_refused dt "{$small, \"dt\": 1e-300}" /dt "5e+298 steps"
step_refused dt_denormal "{$small, \"dt\": 5e-324}" /dt "at a step of 4.94e-324 " # was "of 0"
step_refused kt "{$small, \"law\": {\"kt_ratio\": 1e300}}" /law/kt_ratio "more than the 1e+12"
# a cell narrower than twice the neighbour listing distance (the schema's smallest /width with
# the default cut-off, the largest /cutoff at the default width): refused at /width before the
# packing (exit 2, nothing created); these ran and failed at step 0 with exit 3 and no member
# named. Just above the bound (9.8 for these 20 spheres, the largest 1.118 a) passes.
width_refused() { # name, spec, text in the message (after "at least")
  echo "$2" | "$LUBDEM" run - --out "$work/$1" --quiet 2> "$work/$1.err"
  local rc=$?
  echo "$2" | "$LUBDEM" validate - > /dev/null 2>&1
  local vrc=$?
  [ $rc -eq 2 ] && [ $vrc -eq 2 ] && [ ! -e "$work/$1" ] \
    && grep -q "^error: /width: the cell must be at least .*the neighbour listing .*$3" \
      "$work/$1.err" && ok || bad "cell width $1: run $rc, validate $vrc: $(cat "$work/$1.err")"
}
width_refused narrow "{$small, \"width\": 8}" "is 4.774 a .*raise /width to about 9.7 "
width_refused far '{"scene": "resuspension", "cutoff": 4, "strain": 0.05, "average_from": 0}' \
  "is 7.139 a .*raise /width to about 14.5 "
echo "{$small, \"width\": 9.8}" | "$LUBDEM" validate - > /dev/null 2> "$work/w98.err" && ok \
  || bad "width 9.8 refused: $(cat "$work/w98.err")"
# the vorticity orientation's x-z cell tilts by up to one half before a flip: sqrt(1.25) more
# (width 9.8 validated, then stopped at strain 0.24 with the cell too narrow); 10.8 runs past
# the first flip
vort='"scene": "resuspension", "n": 20, "strain": 0.6, "average_from": 0, "sample_strain": 0.01, "orientation": "vorticity"'
width_refused vort "{$vort, \"width\": 9.8}" "is 4.774 a .*raise /width to about 10.8 "
echo "{$vort, \"width\": 10.8}" | "$LUBDEM" run - --out "$work/vort" --quiet 2> "$work/vort.err"
rc=$?
[ $rc -eq 0 ] && ok || bad "vorticity width 10.8: exit $rc: $(cat "$work/vort.err")"
# the snapshots' unwrapped positions are continuous through the flip at strain 0.5 (until
# 2026-12-06 the images were not carried into the flipped cell: two of these 60 spheres jumped
# by the cell width, 12 a, between the snapshots at strain 0.514 and 0.524)
echo '{"scene":"resuspension","n":60,"strain":0.8,"average_from":0.4,"width":12,"orientation":"vorticity","snapshots":80}' \
  | "$LUBDEM" run - --out "$work/vortflip" --quiet 2>/dev/null
rc=$?
[ $rc -eq 0 ] && $PY - "$work/vortflip/result.h5" <<'PYEOF' && ok || bad "vorticity positions through the flip: exit $rc"
import sys
import h5py, numpy as np
with h5py.File(sys.argv[1], "r") as f:
    x = f["particles/all/position/value"][()]
    e = f["particles/all/box/edges/value"][()]
tilt = e[:, 2, 0] / e[:, 0, 0]  # the z edge's x component over the width
assert tilt.max() > 0.45 and tilt.min() < -0.4, "no flip between the snapshots"
jump = np.abs(np.diff(x, axis=0)).max()
print("vorticity flip: largest move between snapshots %.3f a" % jump)
assert jump < 1.0, jump
PYEOF
# a bed heavier than its contacts can hold: a sphere's own weight over the stiffness, (4/3) pi /
# (Sh stiffness) a, at 0.05 a or more is refused at /stiffness (Sh = 1e-6: 4.19 a); below that a
# bed whose spheres sink through the floor (400 spheres, 0.042 a) is blamed on the weight, not
# the step (both used to fail with "escaped the cell" and the advice to lower
# /dt_stiffness_safety, which did not help)
echo '{"scene": "resuspension", "n": 20, "width": 10, "cutoff": 1, "strain": 0.3, "average_from": 0.1, "sample_strain": 0.01, "shields": 1e-6}' \
  | "$LUBDEM" run - --out "$work/heavy" --quiet 2> "$work/heavy.err"
rc=$?
[ $rc -eq 2 ] && [ ! -e "$work/heavy" ] && grep -q "^error: /stiffness: a sphere's own weight would compress its contact by 4.19 a .*raise /stiffness above 8.38e+07" \
  "$work/heavy.err" && ok || bad "heavy bed: exit $rc: $(cat "$work/heavy.err")"
echo '{"scene": "resuspension", "cutoff": 1, "strain": 0.3, "average_from": 0.1, "sample_strain": 0.01, "shields": 1e-4}' \
  | "$LUBDEM" run - --out "$work/sinks" --quiet 2> "$work/sinks.err"
rc=$?
[ $rc -eq 3 ] && grep -q "^error: particle .* escaped the cell .*: the contacts give way under the bed's weight (a sphere's own weight compresses a contact by 0.0419 a.*raise /stiffness$" \
  "$work/sinks.err" && ! grep -q dt_stiffness_safety "$work/sinks.err" && ok \
  || bad "bed sinking through the floor: exit $rc: $(cat "$work/sinks.err")"
# a roughness at or beyond the cut-off is refused at /law/eps (as in simple_shear)
echo '{"scene": "resuspension", "cutoff": 1, "law": {"eps": 1}}' | "$LUBDEM" validate - \
  > /dev/null 2> "$work/eps.err"
rc=$?
[ $rc -eq 2 ] && grep -q '^error: /law/eps: must be below /cutoff (1)' "$work/eps.err" && ok \
  || bad "eps at the cut-off: exit $rc: $(cat "$work/eps.err")"
# the analysis's jamming fraction is one of spheres (0.2 to pi/sqrt(18)); 1e-300 used to give
# null results with exit 0
echo '{"scene": "resuspension", "analysis": {"phi_m": 1e-300}}' | "$LUBDEM" validate - \
  > /dev/null 2> "$work/phim.err"
rc=$?
[ $rc -eq 2 ] && grep -q '^error: /analysis/phi_m: must be >= 0.2 (got 1e-300)' "$work/phim.err" \
  && ok || bad "analysis phi_m 1e-300: exit $rc: $(cat "$work/phim.err")"
# a count only the bed's lightest particle puts above 1e12: validation bounds it, the run
# refuses it before the first step (exit 2, status failed, the diagnostic in summary.json)
echo '{"scene":"resuspension","n":20,"stiffness":1e9,"strain":1e6,"sample_strain":1,"average_from":1}' > "$work/late.json"
"$LUBDEM" validate "$work/late.json" > /dev/null 2>&1
vrc=$?
"$LUBDEM" run "$work/late.json" --out "$work/late" --quiet 2> "$work/late.err"
rc=$?
[ $vrc -eq 0 ] && [ $rc -eq 2 ] && grep -q '^error: /stiffness: the run would take 1.61e+12 steps' "$work/late.err" \
  && $PY -c "import json,sys; s=json.load(open('$work/late/summary.json')); sys.exit(0 if s['status']=='failed' and s['exit_code']==2 and s['diagnostic'].startswith('/stiffness: the run would take') else 1)" \
  && ok || bad "step count known after the bed: validate $vrc, run $rc: $(cat "$work/late.err")"

# 20 000 particles under 60 000 KiB of address space (lubdemd --mem-mb sets such a limit): the
# pair lists do not fit; the diagnostic says so, with the limit and /n (it was " (code -1)").
# Skipped for a binary that cannot start under the limit (ASan).
if (ulimit -v 60000; "$LUBDEM" version >/dev/null 2>&1); then
  echo '{"scene":"resuspension","n":20000,"strain":0.001,"average_from":0.0005}' >"$work/oom.json"
  (ulimit -v 60000; "$LUBDEM" run "$work/oom.json" --out "$work/oom" --quiet) 2>"$work/oom.err"
  rc=$?
  [ $rc -eq 1 ] && grep -q '^error: out of memory (.*20000 particles.*RLIMIT_AS.*lower /n$' \
    "$work/oom.err" && ok || bad "address-space limit: exit $rc: $(cat "$work/oom.err")"
  # profiles of 5183 bins over 1e6 samples (39 GiB): refused before they are allocated, with
  # what they need, the ceiling and the members (a cgroup would have killed the run as the
  # samples filled them, without a word)
  echo '{"scene":"resuspension","n":200,"bin_width":0.01,"strain":1000,"sample_strain":0.001,"average_from":1}' >"$work/profiles.json"
  (ulimit -v 60000; "$LUBDEM" run "$work/profiles.json" --out "$work/profiles" --quiet) 2>"$work/profiles.err"
  rc=$?
  [ $rc -eq 1 ] && grep -q '^error: not enough memory: the profiles of [0-9]* bins over [0-9]* samples from /average_from on and the height series of [0-9]* samples need at least [0-9.]* GiB, but this process may use .*RLIMIT_AS.*; lower /strain - /average_from (or raise /bin_width or /sample_strain) (nothing was run)$' \
    "$work/profiles.err" && grep -q '"status": "failed"' "$work/profiles/summary.json" \
    && ok || bad "profiles beyond the address-space limit: exit $rc: $(cat "$work/profiles.err")"
  # a long run averaged at its very end: 101 profiles, but a height series (and the
  # statistics' scratch) of 1e6 samples, 30.6 MiB. Until 2026-12-06 only the profiles were
  # counted; the run passed the check and failed on the series with "out of memory for the
  # profiles (101 bins x 101 samples)", which named the wrong members.
  if (ulimit -v 40000; "$LUBDEM" version >/dev/null 2>&1); then
    echo '{"scene":"resuspension","n":20,"strain":100000,"sample_strain":0.1,"average_from":99990}' >"$work/series.json"
    (ulimit -v 40000; timeout 120 "$LUBDEM" run "$work/series.json" --out "$work/series" --quiet) 2>"$work/series.err"
    rc=$?
    [ $rc -eq 1 ] && grep -q '^error: not enough memory: the profiles of [0-9]* bins over [0-9]* samples from /average_from on and the height series of [0-9]* samples need at least 3[0-9.]* MiB, but this process may use .*RLIMIT_AS.*; lower /strain (or raise /sample_strain) (nothing was run)$' \
      "$work/series.err" && ok || bad "height series beyond the address-space limit: exit $rc: $(cat "$work/series.err")"
  else
    echo "height series under 40 000 KiB: skipped (this binary does not start under the limit)"
  fi
else
  echo "address-space limit: skipped (this binary does not start under ulimit -v 60000)"
fi

# A run extended from its own summary's spec (what lubdem_client.py extend sends): the summary
# states the spec exactly (until 2026-12-06 it rounded it to 10 digits, and --resume refused the
# default /shear_drag_viscosity 1/30 as 0.03333333333 "in the stopped run's spec")
echo '{"scene":"resuspension","n":40,"strain":0.3,"average_from":0.1}' >"$work/ext.json"
"$LUBDEM" run "$work/ext.json" --out "$work/ext" --keep-checkpoint --threads 1 --quiet 2>/dev/null
rc1=$?
$PY - "$work/ext/summary.json" "$work/ext2.json" <<'PYEOF'
import json, sys
summary = json.load(open(sys.argv[1]))
# fewer than 32 averaged samples: the height's error bar is the naive SEM, like phi_err's
# (until 2026-12-06 it was null)
h = summary["results"]["suspension_height"]
assert summary["phi_err_method"] == "naive (fewer than 32 samples)", summary["phi_err_method"]
assert h["stderr"] is not None and 0 < h["stderr"] < h["value"], h
spec = summary["spec"]
assert spec["shear_drag_viscosity"] == 1.0 / 30.0, spec["shear_drag_viscosity"]
# the results stay at 10 significant digits (only the spec is exact)
for name, r in summary["results"].items():
    v = r.get("value") if isinstance(r, dict) else None
    if isinstance(v, float):
        digits = repr(v).lower().split("e")[0].replace("-", "").replace(".", "").strip("0")
        assert len(digits) <= 10, (name, v)
spec["strain"] = 0.4
json.dump(spec, open(sys.argv[2], "w"))
PYEOF
prc=$?
"$LUBDEM" run "$work/ext2.json" --out "$work/ext" --resume --threads 1 --quiet 2>"$work/ext2.err"
rc2=$?
[ $rc1 -eq 0 ] && [ $prc -eq 0 ] && [ $rc2 -eq 0 ] \
  && grep -q '"resumed_from_step"' "$work/ext/summary.json" \
  && ok || bad "extension from the summary's spec: exits $rc1 / $prc / $rc2: $(cat "$work/ext2.err")"

# 51 averaged samples of which 26 follow the height's MSER cut: the height's error bar is the
# batch-means one over the averaging window, as phi_err's, and phi_err_method says so (the
# fallback first added on 2026-12-06 gave a naive SEM and labelled phi_err naive too)
echo '{"scene":"resuspension","n":40,"strain":1.2,"average_from":0.2,"sample_strain":0.02}' \
  | "$LUBDEM" run - --out "$work/cut" --threads 1 --quiet 2>/dev/null
rc=$?
[ $rc -eq 0 ] && $PY - "$work/cut/summary.json" <<'PYEOF' && ok || bad "height error after a short MSER window: exit $rc"
import json, sys
s = json.load(open(sys.argv[1]))
h = s["results"]["suspension_height"]
assert s["results"]["averaged_samples"]["value"] >= 32, s["results"]["averaged_samples"]
assert s["phi_err_method"] == "batch_means_ar1", s["phi_err_method"]
assert h["stderr"] is not None and 0 < h["stderr"] < h["value"], h
# the height's transient (MSER-5 of the whole series, 0.6 here) ends after /average_from: a
# warning says so (until 2026-12-06 none); the verdict is over the averaging window
w = s["warnings"]
late = s["height_transient_end_strain"] > s["spec"]["average_from"] + 1e-9
assert late == any("transient" in x and "/average_from" in x for x in w), (late, w)
assert late, s["height_transient_end_strain"]
assert s["height_steady"] or any("not steady over the averaging window" in x for x in w), w
PYEOF

# the transient's end is the strain of a height sample, also where /sample_strain is below the
# step (a sample every step of 1.94e-5 here; until 2026-12-07 the sample's index times
# /sample_strain: 0.154 where that sample was at strain 0.300)
echo '{"scene":"resuspension","n":40,"strain":0.6,"average_from":0.1,"sample_strain":1e-5,"snapshots":0}' \
  | "$LUBDEM" run - --out "$work/dense" --threads 1 --quiet 2>/dev/null
rc=$?
[ $rc -eq 0 ] && $PY - "$work/dense" <<'PYEOF' && ok || bad "transient end at a sample's strain: exit $rc"
import json, sys
import h5py
import numpy as np
s = json.load(open(sys.argv[1] + "/summary.json"))
with h5py.File(sys.argv[1] + "/result.h5", "r") as f:
    strains = f["observables/center_of_mass_height/time"][()]
end = s["height_transient_end_strain"]
assert np.min(np.abs(strains - end)) < 1e-8 and end > 0.01, (end, strains[:3])  # 10 digits
late = [x for x in s["warnings"] if "transient" in x and "/average_from" in x]
assert not late or ("ends at strain %.4g," % end) in late[0], (end, late)
PYEOF

# snapshots 1: the initial and the final state (as simple_shear's snapshots 1; README), which
# the schema now says (it read "first and last included when >= 2")
echo '{"scene":"resuspension","n":40,"strain":0.2,"average_from":0.1,"snapshots":1}' \
  | "$LUBDEM" run - --out "$work/snap1" --threads 1 --quiet 2>/dev/null
$PY -c "
import h5py; f = h5py.File('$work/snap1/result.h5', 'r')
st = f['particles/all/position/step'][:]
assert len(st) == 2 and st[0] == 0 and st[1] == f['observables/suspension_height/step'][-1], st" \
  && ok || bad "snapshots 1: not the initial and the final state"

echo "resuspension_cli_checks=$((pass + fail))"
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
