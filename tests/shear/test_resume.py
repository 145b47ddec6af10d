#!/usr/bin/env python3
"""Stopping and resuming simple_shear and resuspension runs (README "Stopping and resuming";
fast suite).

A run stopped by SIGTERM leaves DIR/checkpoint.h5 next to its partial result.h5; `lubdem run
SPEC --out DIR --resume` continues it. Checked:
 1. imposed volume, 1 thread, snapshots, microstructure and the interaction network at every
    snapshot on: stopped at about a third, resumed: exit 0, the checkpoint removed, and
    summary.json (every result with its error bar, steps, rebuilds, flips) and result.h5 (every
    time series, snapshot, distribution and network frame) equal, bit for bit, to those of the
    same spec run without a stop;
 2. imposed pressure (servo), the Delaunay interaction set, 2 threads, stopped twice: the same
    equality with the uninterrupted 2-thread run;
 3. refusals, each exit 2 with the stopped run's files left byte for byte: another /phi
    (the message names /phi and both values), result.h5 missing, a truncated checkpoint;
 4. a run without --resume in a folder with a checkpoint says so on stderr, starts afresh and
    removes the checkpoint at its end; --resume with no checkpoint starts afresh;
 5. extension: a completed 1.5-strain run kept its checkpoint (--keep-checkpoint), --resume with
    /strain 3 continues it; its time series and distributions equal, bit for bit, those of a
    run asked for 3 from the start, and so do its results; a /strain below the 1.5 already
    done is refused (exit 2, files unchanged);
 6. resuspension (2 threads, snapshots and network frames): stopped at about a third and
    resumed, the same equality with the uninterrupted run (its summary, every time series,
    snapshot, profile and network frame). Before it is resumed, on the stopped run: a
    continuation that fails before it takes the run up (the memory check, under an
    address-space limit; not in the sanitizer build) exits 1 and leaves the stopped run's files
    byte for byte (it used to delete the checkpoint and replace result.h5 by an empty failed
    file); one whose result.h5 cannot be written (a 52 KiB file-size limit) exits 4 and keeps
    the checkpoint and the stopped run's result.h5 (it used to delete the checkpoint); the
    resume itself spells /width 12.0 where the stopped run had 12 (it used to be refused). A
    fresh run that cannot write its result.h5 in a folder holding another run's removes that
    file (a stale result.h5 used to stay beside the summary that says it was removed); a
    SIGTERM sent after the last step (at the progress line of fraction 1) leaves the run
    complete, exit 0 (it used to be "partial" without a checkpoint, which --resume started
    afresh);
 7. the CPU-time limit (a soft RLIMIT_CPU of 3 s, as ulimit -S -t or lubdemd --cpu-s set it):
    the run stops at SIGXCPU like at SIGTERM (exit 5, partial, a checkpoint) and says why in
    its diagnostic and on stderr; it used to be killed by the signal with nothing written;
 8. kill -9 (no warning) of runs taking periodic checkpoints (--checkpoint-every 0.3 s), after
    60 % of the run: checkpoint.h5 and checkpoint-result.h5 are there, no summary; --resume
    continues from the last one to the numbers of the run that never stopped (simple_shear as
    in 1, resuspension as in 6), and leaves neither file;
 9. another thread count: the 1-thread run stopped in 1, continued on 2 threads. It is not the
    same run bit for bit (the pair sums add in another order), so: its rows up to the stop are
    the stopped run's, the first sample after it agrees with the 1-thread run to round-off
    (relative 1e-6, where a wrong state would differ at once), and every result with an error
    bar agrees with the 1-thread run's within 5 combined standard errors.
 10. extension of a completed resuspension run (--keep-checkpoint; its checkpoint is taken
    before the sample its end forces): --resume with twice the /strain equals, bit for bit, a
    run asked for it from the start (summary and result.h5); less /strain is refused (exit 2).
 11. extension of a run that stopped on its /target_rel_error: with the same target and a
    longer /strain it stops where it did (no step more), with a smaller one it goes on; both
    equal, bit for bit, a run asked for the new spec from the start.
 12. snapshots, network frames and target checks across a continuation (a fixed step): a run
    stopped on its target and continued with a smaller one, a run made without a target and
    extended with one, a continuation that takes no step (its stop on a snapshot step), and the
    extension of a completed run: each with the snapshot and frame steps and the results of
    the run asked for the second spec from the start (a-c: result.h5 bit for bit).
The stop is sent once the progress lines pass a fraction, so that it lands mid-run on any
machine. The sanitizer build (~5 times slower) runs every case on a shorter strain (the
equalities do not depend on it). Usage: test_resume.py LUBDEM WORKDIR [--sanitized]
"""
import hashlib
import json
import os
import resource
import shutil
import signal
import subprocess
import sys

import h5py
import numpy as np

from h5_datasets import differing_items, h5_items, same_bits  # the script's folder

LUBDEM, WORK = sys.argv[1], sys.argv[2]
SCALE = 0.4 if "--sanitized" in sys.argv[3:] else 1.0  # strains of every case
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def write_spec(name, spec):
    path = os.path.join(WORK, name + ".json")
    with open(path, "w") as f:
        json.dump(spec, f)
    return path


def run(spec_path, out, *extra, stop_at=None, cpu_s=None, sig=signal.SIGTERM, fsize=None,
        address_space=None):
    """Runs lubdem; with stop_at, sends sig once a progress line passes that fraction (for
    SIGKILL, once a periodic checkpoint is there too; stop_at 1: at the last progress line);
    with cpu_s, under that soft CPU-time limit (SIGXCPU; no hard limit); fsize and
    address_space: RLIMIT_FSIZE and RLIMIT_AS in bytes."""
    cmd = [LUBDEM, "run", spec_path, "--out", out, *extra]
    limits = [(resource.RLIMIT_CPU, (cpu_s, resource.RLIM_INFINITY)) if cpu_s else None,
              (resource.RLIMIT_FSIZE, (fsize, fsize)) if fsize else None,
              (resource.RLIMIT_AS, (address_space, address_space)) if address_space else None]
    limits = [x for x in limits if x]

    def limit():
        for what, value in limits:
            resource.setrlimit(what, value)
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=limit if limits else None)
    out_lines = []
    if stop_at is not None:
        for line in proc.stdout:
            out_lines.append(line)
            if line.startswith("progress "):
                frac = float(line.split("fraction=")[1].split()[0])
                ready = sig != signal.SIGKILL or os.path.exists(os.path.join(out, "checkpoint.h5"))
                if stop_at <= frac and (frac < 1.0 or stop_at >= 1.0) and ready:
                    proc.send_signal(sig)
                    break
    rest, err = proc.communicate(timeout=600)
    return proc.returncode, "".join(out_lines) + rest, err


def summary(out):
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def compare_runs(ref_dir, res_dir, label):
    ra, rb = summary(ref_dir), summary(res_dir)
    check(rb["status"] == "complete" and rb["exit_code"] == 0, f"{label}: resumed run complete")
    check(rb.get("resumed_from_step", 0) > 0, f"{label}: summary says where it resumed "
          f"(resumed_from_step {rb.get('resumed_from_step')})")
    diff = [k for k in ra["results"] if ra["results"][k] != rb["results"].get(k)]
    check(not diff and set(ra["results"]) == set(rb["results"]),
          f"{label}: all {len(ra['results'])} results and error bars equal"
          + (f"; differ: {diff[:5]}" if diff else ""))
    for key in ("steps", "simulated_time", "steady_state_detected", "warnings"):
        check(ra.get(key) == rb.get(key), f"{label}: {key} equal ({ra.get(key)!r:.60})")
    check(not os.path.exists(os.path.join(res_dir, "checkpoint.h5")),
          f"{label}: checkpoint removed at the end")
    ia, ib = h5_items(os.path.join(ref_dir, "result.h5")), h5_items(os.path.join(res_dir, "result.h5"))
    bad = differing_items(ia, ib)
    check(not bad,
          f"{label}: result.h5 equal bit for bit ({len(ia)} datasets, "
          f"{max((len(v) for k, v in ia.items() if k.startswith('observables/') and k.endswith('/value')), default=0)} rows)" + (f"; differ: {bad[:5]}" if bad else ""))


def digest(folder):
    h = {}
    for name in sorted(os.listdir(folder)):
        with open(os.path.join(folder, name), "rb") as f:
            h[name] = hashlib.sha256(f.read()).hexdigest()
    return h


os.makedirs(WORK, exist_ok=True)

# ---- 1. imposed volume, 1 thread ----
spec1 = write_spec("volume", {
    "scene": "simple_shear", "n_particles": 300, "phi": 0.5, "stiffness": 1e4, "strain": 3.0 * SCALE,
    "sample_strain": 0.01, "transient_strain": 0.5, "snapshots": 5, "pair_network": "snapshots",
    "microstructure": {"enabled": True, "start_strain": 0.5, "interval_strain": 0.05}})
ref1, res1 = os.path.join(WORK, "ref1"), os.path.join(WORK, "res1")
for d in (ref1, res1):
    shutil.rmtree(d, ignore_errors=True)
rc, _, err = run(spec1, ref1)
check(rc == 0, f"1: uninterrupted run exit 0 (got {rc}) {err[-300:]}")
rc, _, err = run(spec1, res1, stop_at=0.3)
s = summary(res1)
check(rc == 5 and s["status"] == "partial", f"1: stopped run exit 5, partial (got {rc})")
check(os.path.exists(os.path.join(res1, "checkpoint.h5")) and s.get("checkpoint") == "checkpoint.h5",
      "1: stopped run left checkpoint.h5, named in its summary")
check(not [n for n in os.listdir(res1) if n.startswith(".")], "1: no temporary file left")
stopped_steps = s["steps"]
check(0 < stopped_steps < summary(ref1)["steps"],
      f"1: stopped mid-run (step {stopped_steps} of {summary(ref1)['steps']})")

# ---- 3. refusals (on the stopped run of 1, before it is resumed) ----
before = digest(res1)
spec_other = write_spec("volume_other", dict(json.load(open(spec1)), phi=0.49))
rc, _, err = run(spec_other, res1, "--resume")
check(rc == 2 and "/phi" in err and "0.49" in err and "0.5" in err,
      f"3: another /phi refused with exit 2 naming it (got {rc}: {err.strip()[-200:]})")
check(digest(res1) == before, "3: the stopped run's files unchanged")
bad_dir = os.path.join(WORK, "bad")
shutil.rmtree(bad_dir, ignore_errors=True)
shutil.copytree(res1, bad_dir)
os.remove(os.path.join(bad_dir, "result.h5"))
before_bad = digest(bad_dir)
rc, _, err = run(spec1, bad_dir, "--resume")
check(rc == 2 and "result.h5" in err and "missing" in err,
      f"3: checkpoint without its result.h5 refused (got {rc}: {err.strip()[-200:]})")
check(digest(bad_dir) == before_bad, "3: folder unchanged")
shutil.rmtree(bad_dir)
shutil.copytree(res1, bad_dir)
ck = os.path.join(bad_dir, "checkpoint.h5")
with open(ck, "r+b") as f:
    f.truncate(os.path.getsize(ck) // 2)
before_bad = digest(bad_dir)
rc, _, err = run(spec1, bad_dir, "--resume")
check(rc == 2 and "checkpoint" in err, f"3: truncated checkpoint refused (got {rc}: "
      f"{err.strip()[-200:]})")
check(digest(bad_dir) == before_bad, "3: folder unchanged")

res9 = os.path.join(WORK, "res9")  # for 9: the same stopped run, continued on 2 threads
shutil.rmtree(res9, ignore_errors=True)
shutil.copytree(res1, res9)

# ---- 1 (cont.): resume ----
rc, out, err = run(spec1, res1, "--resume")
check(rc == 0, f"1: resumed run exit 0 (got {rc}) {err[-300:]}")
compare_runs(ref1, res1, "1")

# ---- 2. imposed pressure, Delaunay, 2 threads, two stops ----
spec2 = write_spec("pressure", {
    "scene": "simple_shear", "n_particles": 300, "control": "pressure", "Iv": 0.1,
    "strain": 2.0 * SCALE, "sample_strain": 0.01, "transient_strain": 0.5,
    "lubrication_pairs": "delaunay"})
ref2, res2 = os.path.join(WORK, "ref2"), os.path.join(WORK, "res2")
for d in (ref2, res2):
    shutil.rmtree(d, ignore_errors=True)
rc, _, err = run(spec2, ref2, "--threads", "2")
check(rc == 0, f"2: uninterrupted 2-thread run exit 0 (got {rc}) {err[-300:]}")
rc, _, _ = run(spec2, res2, "--threads", "2", stop_at=0.25)
first_stop = summary(res2)["steps"]
rc2, _, _ = run(spec2, res2, "--threads", "2", "--resume", stop_at=0.6)
s = summary(res2)
check(rc == 5 and rc2 == 5 and s.get("resumed_from_step") == first_stop and s["steps"] > first_stop,
      f"2: stopped twice (steps {first_stop}, then {s['steps']}; exit {rc}, {rc2})")
rc, _, err = run(spec2, res2, "--threads", "2", "--resume")
check(rc == 0, f"2: resumed run exit 0 (got {rc}) {err[-300:]}")
compare_runs(ref2, res2, "2")

# ---- 4. without --resume / without a checkpoint ----
fresh = os.path.join(WORK, "fresh")
shutil.rmtree(fresh, ignore_errors=True)
spec4 = write_spec("short", {"scene": "simple_shear", "n_particles": 300, "phi": 0.45,
                             "stiffness": 1e4, "strain": 1.5 * SCALE, "sample_strain": 0.01})
rc, _, _ = run(spec4, fresh, stop_at=0.3)
check(rc == 5 and os.path.exists(os.path.join(fresh, "checkpoint.h5")), "4: stopped with a checkpoint")
rc, _, err = run(spec4, fresh)
check(rc == 0 and "checkpoint" in err and "--resume" in err,
      f"4: a run without --resume notes the checkpoint it replaces (got {rc}: {err.strip()[:160]})")
check(not os.path.exists(os.path.join(fresh, "checkpoint.h5")) and
      "resumed_from_step" not in summary(fresh), "4: ... starts afresh and removes it")
rc, out, _ = run(spec4, fresh, "--resume")
check(rc == 0 and "starts from the beginning" in out and "resumed_from_step" not in summary(fresh),
      f"4: --resume without a checkpoint starts afresh (got {rc})")

# ---- 5. extending a completed run ----
ext, ref5 = os.path.join(WORK, "ext"), os.path.join(WORK, "ref5")
for d in (ext, ref5):
    shutil.rmtree(d, ignore_errors=True)
base5 = {"scene": "simple_shear", "n_particles": 300, "phi": 0.5, "stiffness": 1e4,
         "sample_strain": 0.01, "transient_strain": 0.5, "snapshots": 0,
         "microstructure": {"enabled": True, "start_strain": 0.5, "interval_strain": 0.05}}
short5 = write_spec("short5", dict(base5, strain=1.5 * SCALE))
long5 = write_spec("long5", dict(base5, strain=3.0 * SCALE))
rc, _, err = run(short5, ext, "--keep-checkpoint")
s = summary(ext)
check(rc == 0 and s["status"] == "complete" and s.get("checkpoint") == "checkpoint.h5" and
      os.path.exists(os.path.join(ext, "checkpoint.h5")),
      f"5: completed run kept its checkpoint with --keep-checkpoint (exit {rc})")
short_steps = s["steps"]
before = digest(ext)
rc, _, err = run(write_spec("less5", dict(base5, strain=1.0 * SCALE)), ext, "--resume")
check(rc == 2 and "/strain" in err and "already" in err and digest(ext) == before,
      f"5: /strain below the strain done refused, files unchanged (got {rc}: {err.strip()[-160:]})")
rc, _, err = run(long5, ext, "--resume")
check(rc == 0, f"5: extension to /strain 3 exit 0 (got {rc}) {err[-300:]}")
rc, _, err = run(long5, ref5)
check(rc == 0, f"5: run asked for /strain 3 from the start exit 0 (got {rc})")
s, r = summary(ext), summary(ref5)
check(s.get("resumed_from_step") == short_steps and s["steps"] == r["steps"],
      f"5: extended from step {s.get('resumed_from_step')} to {s['steps']} steps "
      f"(the long run: {r['steps']})")
check(s["results"] == r["results"], "5: results equal to the long run's (eta_r "
      f"{s['results']['eta_r']['value']} / {r['results']['eta_r']['value']})")
ia, ib = h5_items(os.path.join(ref5, "result.h5")), h5_items(os.path.join(ext, "result.h5"))
bad = differing_items(ia, ib)
check(not bad, f"5: result.h5 equal bit for bit to the long run's "
      f"({len(ia)} datasets)" + (f"; differ: {bad[:5]}" if bad else ""))

# ---- 6. resuspension ----
ref6, res6 = os.path.join(WORK, "ref6"), os.path.join(WORK, "res6")
for d in (ref6, res6):
    shutil.rmtree(d, ignore_errors=True)
spec6 = write_spec("resuspension", {
    "scene": "resuspension", "n": 150, "width": 12, "strain": 0.6 * SCALE, "average_from": 0.2 * SCALE,
    "sample_strain": 0.005, "snapshots": 4, "pair_network": "snapshots"})
rc, _, err = run(spec6, ref6, "--threads", "2")
check(rc == 0, f"6: uninterrupted resuspension run exit 0 (got {rc}) {err[-300:]}")
rc, _, _ = run(spec6, res6, "--threads", "2", stop_at=0.3)
s = summary(res6)
check(rc == 5 and s.get("checkpoint") == "checkpoint.h5" and 0 < s["steps"] < summary(ref6)["steps"],
      f"6: stopped with a checkpoint at step {s['steps']} of {summary(ref6)['steps']} (exit {rc})")
before = digest(res6)
if "--sanitized" not in sys.argv[3:]:  # ASan reserves terabytes of address space
    # /strain may change on --resume: 4999 needs 0.7 GiB of profiles, refused by the memory check
    big6 = write_spec("resuspension_big", dict(json.load(open(spec6)), strain=4999))
    rc, _, err = run(big6, res6, "--resume", address_space=300 << 20)
    check(rc == 1 and "not enough memory" in err and "left as they were" in err
          and digest(res6) == before,
          f"6: a continuation refused by the memory check leaves the stopped run's files "
          f"(exit {rc}: {err.strip()[-160:]})")
rc, _, err = run(spec6, res6, "--threads", "2", "--resume", fsize=52 << 10)
s, now = summary(res6), digest(res6)
check(rc == 4 and s["exit_code"] == 4 and s.get("checkpoint") == "checkpoint.h5"
      and "lubdem run --resume goes on from there" in s["diagnostic"]
      and sorted(now) == sorted(before)
      and all(now[k] == before[k] for k in ("checkpoint.h5", "result.h5")),
      f"6: a continuation that cannot write result.h5 keeps the checkpoint and the stopped run's "
      f"result.h5 (exit {rc}, {sorted(now)}: {s.get('diagnostic', '')[:160]})")
stale6 = os.path.join(WORK, "stale6")
shutil.rmtree(stale6, ignore_errors=True)
shutil.copytree(ref6, stale6)
rc, _, err = run(spec6, stale6, "--threads", "2", fsize=52 << 10)
check(rc == 4 and sorted(os.listdir(stale6)) == ["summary.json"],
      f"6: a run that cannot write result.h5 leaves no other run's result.h5 beside its summary "
      f"(exit {rc}, {sorted(os.listdir(stale6))})")
end6 = os.path.join(WORK, "end6")
shutil.rmtree(end6, ignore_errors=True)
rc, _, err = run(spec6, end6, "--threads", "2", stop_at=1.0)
s = summary(end6)
check(rc == 0 and s["status"] == "complete" and s["results"] == summary(ref6)["results"],
      f"6: SIGTERM after the last step: complete, exit 0 (exit {rc}, {s['status']})")
# the stopped run had "width": 12; 12.0 is the same spec
spec6f = write_spec("resuspension_float", json.load(open(spec6)))
with open(spec6f) as f:
    text = f.read()
with open(spec6f, "w") as f:
    f.write(text.replace('"width": 12,', '"width": 12.0,'))
rc, _, err = run(spec6f, res6, "--threads", "2", "--resume")
check(rc == 0 and '"width": 12.0' in text.replace('"width": 12,', '"width": 12.0,'),
      f"6: resumed run (/width 12.0) exit 0 (got {rc}) {err[-300:]}")
compare_runs(ref6, res6, "6")

# ---- 7. the CPU-time limit ----
cpu = os.path.join(WORK, "cpu")
shutil.rmtree(cpu, ignore_errors=True)
spec7 = write_spec("cpu", {"scene": "simple_shear", "n_particles": 300, "phi": 0.5,
                           "stiffness": 1e4, "strain": 1000, "sample_strain": 0.01})
rc, _, err = run(spec7, cpu, cpu_s=3)
s = summary(cpu) if os.path.exists(os.path.join(cpu, "summary.json")) else {}
check(rc == 5 and s.get("status") == "partial" and s.get("checkpoint") == "checkpoint.h5" and
      "SIGXCPU" in s.get("diagnostic", "") and "CPU time limit" in err,
      f"7: stopped at the CPU-time limit with a checkpoint (exit {rc}, step {s.get('steps')}, "
      f"{s.get('diagnostic', '')[:120]})")

# ---- 8. kill -9 with periodic checkpoints ----
for label, spec, ref, threads in (("8a", spec1, ref1, "1"), ("8b", spec6, ref6, "2")):
    killed = os.path.join(WORK, "killed" + label)
    shutil.rmtree(killed, ignore_errors=True)
    rc, _, _ = run(spec, killed, "--threads", threads, "--checkpoint-every", "0.3", stop_at=0.6,
                   sig=signal.SIGKILL)
    names = sorted(os.listdir(killed))
    check(rc == -9 and "checkpoint.h5" in names and "checkpoint-result.h5" in names and
          "summary.json" not in names, f"{label}: killed with periodic checkpoints left ({names})")
    rc, _, err = run(spec, killed, "--threads", threads, "--resume", "--checkpoint-every", "0.3")
    check(rc == 0, f"{label}: resumed after kill -9, exit 0 (got {rc}) {err[-300:]}")
    compare_runs(ref, killed, label)
    # a continuation of more than 1 s (over 3 intervals) takes at least one periodic
    # checkpoint; on a loaded host the kill can land late (it waits for the first checkpoint
    # file), leaving a continuation too short for one (seen once: 0 periodic checkpoints)
    wall = summary(killed).get("wall_time_s", 0.0)
    check(not os.path.exists(os.path.join(killed, "checkpoint-result.h5")) and
          (summary(killed).get("periodic_checkpoints", 0) >= 1 or wall <= 1.0),
          f"{label}: the copy removed at the end; {summary(killed).get('periodic_checkpoints')} "
          f"periodic checkpoints in the continuation of {wall:.2f} s")

# ---- 9. continued on another thread count ----
rc, _, err = run(spec1, res9, "--threads", "2", "--resume")
s9, r1 = summary(res9), summary(ref1)
check(rc == 0 and s9["threads"] == 2 and s9.get("resumed_from_step") == stopped_steps,
      f"9: the 1-thread run continued on {s9.get('threads')} threads from step "
      f"{s9.get('resumed_from_step')} (exit {rc}) {err[-200:]}")
series_a = {k: v for k, v in h5_items(os.path.join(ref1, "result.h5")).items()
            if k.startswith("observables/") and k.endswith("/value")}
series_b = {k: v for k, v in h5_items(os.path.join(res9, "result.h5")).items()
            if k.startswith("observables/") and k.endswith("/value")}
with h5py.File(os.path.join(ref1, "result.h5"), "r") as fa, \
        h5py.File(os.path.join(res9, "result.h5"), "r") as fb:
    steps_a, steps_b = fa["observables/mu/step"][()], fb["observables/mu/step"][()]
# rows are labelled with the step they sample (0-based): the stopped run did steps
# 0 .. stopped_steps - 1, so a row labelled stopped_steps is the continuation's own (with
# side="right" it was counted as the stopped run's, and the check failed whenever the stop
# fell just before a sampled step: about one run in 29)
before = int(np.searchsorted(steps_a, stopped_steps, side="left"))
check(set(series_a) == set(series_b) and same_bits(steps_a[:before], steps_b[:before]) and
      all(same_bits(series_a[k][:before], series_b[k][:before]) for k in series_a),
      f"9: the {before} rows of the {len(series_a)} time series up to the stop are the stopped "
      "run's")
worst = 0.0
for k in series_a:
    va = np.asarray(series_a[k][before], dtype=float)
    vb = np.asarray(series_b[k][before], dtype=float)
    worst = max(worst, float(np.max(np.abs(va - vb) / np.maximum(np.abs(va), 1e-300))))
check(steps_b[before] == steps_a[before] and worst < 1e-6,
      f"9: first sample after the stop (step {steps_b[before]}) within round-off of the "
      f"1-thread run's (largest relative difference {worst:.1e})")
later = sum(not same_bits(series_a[k], series_b[k]) for k in series_a)
print(f"9: {later} of {len(series_a)} time series differ from the 1-thread run's somewhere "
      "after the stop")
far = []
compared = 0
for k, a_ in r1["results"].items():
    b_ = s9["results"].get(k, {})
    if not isinstance(a_, dict) or a_.get("stderr") is None or b_.get("stderr") is None:
        continue
    compared += 1
    tol = 5.0 * (a_["stderr"] ** 2 + b_["stderr"] ** 2) ** 0.5
    if abs(a_["value"] - b_["value"]) > tol:
        far.append((k, a_["value"], b_["value"], tol))
check(compared > 0 and not far,
      f"9: {compared} results with error bars within 5 combined standard errors of the 1-thread "
      f"run's (mu {s9['results']['mu']['value']:.4g} / {r1['results']['mu']['value']:.4g})"
      + (f"; outside: {far[:3]}" if far else ""))

# ---- 10. extending a completed resuspension run ----
ext10, ref10 = os.path.join(WORK, "ext10"), os.path.join(WORK, "ref10")
for d in (ext10, ref10):
    shutil.rmtree(d, ignore_errors=True)
# sample_strain 0.007: the short run's end is off the sampling grid, so its last row is the
# one its end forces, which the longer run does not take
base10 = {"scene": "resuspension", "n": 150, "width": 12, "average_from": 0.1 * SCALE,
          "sample_strain": 0.007, "snapshots": 0}
rc, _, err = run(write_spec("short10", dict(base10, strain=0.3 * SCALE)), ext10, "--threads", "2",
                 "--keep-checkpoint")
s = summary(ext10)
check(rc == 0 and s["status"] == "complete" and s.get("checkpoint") == "checkpoint.h5",
      f"10: completed resuspension run kept its checkpoint (exit {rc}) {err[-200:]}")
with h5py.File(os.path.join(ext10, "result.h5"), "r") as h:
    short_last = int(h["observables/suspension_height/step"][-1])
before = digest(ext10)
rc, _, err = run(write_spec("less10", dict(base10, strain=0.2 * SCALE)), ext10, "--threads", "2",
                 "--resume")
check(rc == 2 and "/strain" in err and "already" in err and digest(ext10) == before,
      f"10: /strain below the strain done refused, files unchanged (got {rc}: "
      f"{err.strip()[-160:]})")
long10 = write_spec("long10", dict(base10, strain=0.6 * SCALE))
rc, _, err = run(long10, ext10, "--threads", "2", "--resume")
check(rc == 0, f"10: extension to twice the strain exit 0 (got {rc}) {err[-300:]}")
rc, _, err = run(long10, ref10, "--threads", "2")
s, r = summary(ext10), summary(ref10)
with h5py.File(os.path.join(ref10, "result.h5"), "r") as h:
    ref_steps = h["observables/suspension_height/step"][()]
check(rc == 0 and short_last not in ref_steps and s.get("resumed_from_step") == short_last and
      s["steps"] == r["steps"],
      f"10: extended from step {s.get('resumed_from_step')} (the short run's forced last sample, "
      f"not one of the long run's) to {s['steps']} steps (the long run: {r['steps']})")
check(s["results"] == r["results"],
      f"10: all {len(r['results'])} results equal to the long run's (suspension height "
      f"{s['results']['suspension_height']['value']:.6g})")
ia, ib = h5_items(os.path.join(ref10, "result.h5")), h5_items(os.path.join(ext10, "result.h5"))
bad = differing_items(ia, ib)
check(not bad, f"10: result.h5 equal bit for bit to the long run's ({len(ia)} datasets, "
      f"{len(ref_steps)} rows)" + (f"; differ: {bad[:5]}" if bad else ""))

# ---- 11. extending a run that stopped on its /target_rel_error ----
# A run asked for a longer /strain with the same target stops where the short one did; the
# extension repeats the check made at the stopped run's last step and stops there too, with no
# step more (until 2026-12-06 it went on to the next check, one strain later: 4.05 -> 5.07 in
# the reviewer's run). A smaller target goes on, to the steps of a run asked for it from the
# start. The tiny cell (40 spheres, cut-off 0.1 a) takes under a second per run. Targets 0.3
# and 0.15 since the stop tests the 90 % upper bound of the error (2026-12-07): with 0.2 the
# 8-strain run no longer stopped (eta_r's error 0.16, its bound 0.23); with 0.3 it stops at 4.5.
ext11, ref11 = os.path.join(WORK, "ext11"), os.path.join(WORK, "ref11")
base11 = {"scene": "simple_shear", "n_particles": 40, "cutoff": 0.1, "skin": 0.05, "phi": 0.45,
          "transient_strain": 0.5, "target_rel_error": 0.3, "target_min_strain": 1,
          "sample_strain": 0.01, "snapshots": 0}  # snapshots keep the first run's spacing
for label, target in (("same target", 0.3), ("smaller target", 0.15)):
    for d in (ext11, ref11):
        shutil.rmtree(d, ignore_errors=True)
    rc, _, err = run(write_spec("short11", dict(base11, strain=8)), ext11, "--keep-checkpoint")
    s = summary(ext11)
    check(rc == 0 and s["stopped_on_target_error"] and s["results"]["strain_reached"]["value"] < 8,
          f"11 ({label}): the 8-strain run stopped on /target_rel_error 0.3 at strain "
          f"{s['results']['strain_reached']['value']:.3f} (exit {rc}) {err[-200:]}")
    long11 = write_spec("long11", dict(base11, strain=16, target_rel_error=target))
    rc, _, err = run(long11, ext11, "--resume")
    check(rc == 0, f"11 ({label}): extension to /strain 16 exit 0 (got {rc}) {err[-300:]}")
    rc, _, err = run(long11, ref11)
    s, r = summary(ext11), summary(ref11)
    check(rc == 0 and s["steps"] == r["steps"] and
          s["stopped_on_target_error"] == r["stopped_on_target_error"] and
          s["results"] == r["results"],
          f"11 ({label}): extended to {s['steps']} steps, stopped on the target "
          f"{s['stopped_on_target_error']}; the run asked for /strain 16 from the start: "
          f"{r['steps']} steps, {r['stopped_on_target_error']}; results equal "
          f"{s['results'] == r['results']}")
    ia, ib = h5_items(os.path.join(ref11, "result.h5")), h5_items(os.path.join(ext11, "result.h5"))
    bad = differing_items(ia, ib)
    check(not bad, f"11 ({label}): result.h5 equal bit for bit ({len(ia)} datasets)"
          + (f"; differ: {bad[:5]}" if bad else ""))

# ---- 12. snapshots and target checks across a continuation ----
# The tiny cell of 11 with a fixed step (2^-11, so that strains are exact): until 2026-12-07
#  a. a run stopped on its target and continued with a smaller one wrote the snapshot and
#     network frame due at the stop one step late (steps 0 2048 4097 ... against 4096);
#  b. a run made without a target and extended with one checked at its first sample and every
#     strain from there (stopped at 1.516 against 2.0);
#  c. a continuation that took no step (the same target: the repeated check stops at once)
#     wrote its last snapshot, taken at the stop, a second time;
#  d. the extension of a completed run had no snapshot at the old end (0 1024 2048 3072 5120
#     against ... 3072 4096 5120).
base12 = {"scene": "simple_shear", "n_particles": 40, "cutoff": 0.1, "skin": 0.05, "phi": 0.45,
          "stiffness": 1e4, "dt": 2**-11, "sample_strain": 2**-6, "transient_strain": 0,
          "target_min_strain": 0.5, "strain": 4, "snapshots": 4, "pair_network": "snapshots"}


def steps_of(out):
    with h5py.File(os.path.join(out, "result.h5"), "r") as f:
        return (f["particles/all/position/step"][()].tolist() if "particles" in f else [],
                f["pair_network/step"][()].tolist() if "pair_network" in f else [])


def continued_equals_straight(label, first, then, straight=None, whole=True):
    ext, ref = os.path.join(WORK, "ext12"), os.path.join(WORK, "ref12")
    for d in (ext, ref):
        shutil.rmtree(d, ignore_errors=True)
    rc1, _, err1 = run(write_spec("first12", first), ext, "--keep-checkpoint")
    rc2, _, err2 = run(write_spec("then12", then), ext, "--resume")
    rc3, _, err3 = run(write_spec("straight12", straight or then), ref)
    s, r = summary(ext), summary(ref)
    check(rc1 == 0 and rc2 == 0 and rc3 == 0 and s["steps"] == r["steps"] and
          s["results"] == r["results"],
          f"12{label}: continued {s.get('steps')} steps (strain "
          f"{s['results']['strain_reached']['value']:.4f}), straight {r.get('steps')} (strain "
          f"{r['results']['strain_reached']['value']:.4f}); results equal "
          f"{s['results'] == r['results']} (exit {rc1} {rc2} {rc3}) {(err1 + err2 + err3)[-200:]}")
    got, want = steps_of(ext), steps_of(ref)
    check(got == want, f"12{label}: snapshot and network steps {str(got)[-90:]} against the "
          f"straight run's {str(want)[-90:]}")
    if whole:
        bad = differing_items(h5_items(os.path.join(ref, "result.h5")),
                              h5_items(os.path.join(ext, "result.h5")))
        check(not bad, f"12{label}: result.h5 equal bit for bit" +
              (f"; differ: {bad[:5]}" if bad else ""))


continued_equals_straight("a", dict(base12, target_rel_error=0.5),
                          dict(base12, target_rel_error=0.01))
continued_equals_straight("b", dict(base12, strain=1.5, snapshots=0),
                          dict(base12, target_rel_error=0.5, snapshots=0))
# c: the stop on the target at strain 2 (step 4096) falls on a snapshot step (every 2048)
continued_equals_straight("c", dict(base12, target_rel_error=0.5),
                          dict(base12, target_rel_error=0.5))
# d: the extension keeps the first run's spacing, that of 8 snapshots over the longer strain
continued_equals_straight("d", dict(base12, strain=2), base12, dict(base12, snapshots=8),
                          whole=False)

print(f"resume_failures={len(failures)}")
sys.exit(1 if failures else 0)
