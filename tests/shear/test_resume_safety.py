#!/usr/bin/env python3
"""What happens to a stopped run's files (README "Stopping and resuming", "Output"; fast suite,
about 30 s). On a small simple_shear run (250 particles, 3 strain):
 1. durability: under an LD_PRELOAD library that logs fsync (with the path synced) and rename,
    a run taking periodic checkpoints (--checkpoint-every) stopped by SIGTERM, and its
    continuation: every file renamed into the run's folder (.checkpoint.h5.tmp,
    .checkpoint-result.h5.tmp, .result.h5.tmp, .summary.json.tmp) was fsync'd under its
    temporary name before its rename, and the folder was fsync'd after the rename (until
    2026-12-07 the periodic checkpoint.h5 was never synced, nor its folder);
 2. a continuation that cannot write its summary.json (a non-empty folder of that name),
    stopped by SIGTERM: exit 4, and checkpoint.h5 and the result.h5 it needs stay (they used to
    be deleted, leaving nothing to continue from); once the folder is removed, --resume
    completes with the results of the run that never stopped;
 3. damaged checkpoint data: one byte flipped inside system/x, or system/v[0] multiplied by
    1.01 in place, is refused with exit 2 naming the dataset, the folder unchanged (both used
    to be continued silently); the CRC-32 stored with each dataset is zlib's of its bytes;
 4. provenance: a checkpoint written by another build (its git_commit note edited) is
    continued with a warning naming both builds (summary and stderr), and the summary's builds
    lists both with the step each began at; the same build adds none; the same build on 2
    threads adds a part of 2 threads (no warning), and a checkpoint without the threads note
    (written before 2026-12-07) gives its part no threads (until then only the last part's
    threads were reported);
 5. a leftover .checkpoint-result.h5.tmp (of a kill during a periodic checkpoint) is removed by
    a continuation without --checkpoint-every (it stayed); --checkpoint-every on a scene that
    takes no checkpoints warns on stderr and in the summary (it was ignored without a word).
Usage: test_resume_safety.py LUBDEM WORKDIR SHIM [--sanitized] (the sanitizer build skips 1:
the LD_PRELOAD library cannot come before its runtime)
"""
import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
import zlib

import h5py
import numpy as np

LUBDEM, WORK, SHIM = sys.argv[1], os.path.realpath(sys.argv[2]), sys.argv[3]
SANITIZED = "--sanitized" in sys.argv[4:]
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def run(spec_path, out, *extra, stop_at=None, env=None):
    """lubdem run; with stop_at, SIGTERM once a progress line passes that fraction (below 1)."""
    proc = subprocess.Popen([LUBDEM, "run", spec_path, "--out", out, *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=dict(os.environ, **(env or {})))
    if stop_at is not None:
        for line in proc.stdout:
            if line.startswith("progress "):
                frac = float(line.split("fraction=")[1].split()[0])
                if stop_at <= frac < 1.0:
                    proc.send_signal(signal.SIGTERM)
                    break
    _, err = proc.communicate(timeout=300)
    return proc.returncode, err


def summary(out):
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def digest(folder):
    h = {}
    for name in sorted(os.listdir(folder)):
        p = os.path.join(folder, name)
        if os.path.isfile(p):
            with open(p, "rb") as f:
                h[name] = hashlib.sha256(f.read()).hexdigest()
        else:
            h[name] = "folder"
    return h


def fresh(name):
    d = os.path.join(WORK, name)
    shutil.rmtree(d, ignore_errors=True)
    return d


def copy_of(src, name):
    d = fresh(name)
    shutil.copytree(src, d)
    return d


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
base = {"scene": "simple_shear", "n_particles": 250, "phi": 0.5, "stiffness": 1e4, "strain": 3.0,
        "sample_strain": 0.01, "transient_strain": 0.5, "snapshots": 3,
        "pair_network": "snapshots"}
spec = os.path.join(WORK, "spec.json")
with open(spec, "w") as f:
    json.dump(base, f)

ref = fresh("ref")
rc, err = run(spec, ref)
check(rc == 0, f"uninterrupted run exit 0 (got {rc}) {err[-300:]}")
stopped = fresh("stopped")
rc, err = run(spec, stopped, stop_at=0.3)
check(rc == 5 and os.path.exists(os.path.join(stopped, "checkpoint.h5")),
      f"run stopped with a checkpoint (exit {rc}) {err[-300:]}")


def same_results(a, b):
    return summary(a)["results"] == summary(b)["results"] and summary(a)["steps"] == summary(b)["steps"]


# ---- 1. fsync before every rename into the folder, the folder after ----
def check_sync_log(log, folder, label):
    """Every rename into folder: its source fsync'd since it was last renamed, and folder
    fsync'd after the rename."""
    with open(log) as f:
        lines = [ln.rstrip("\n").split(" ") for ln in f]
    synced = set()  # paths fsync'd since their last rename
    pending = []    # renames into folder not yet followed by an fsync of it
    renames = 0
    problems = []
    for words in lines:
        if words[0] == "fsync":
            synced.add(words[1])
            if words[1] == folder:
                pending = []
        elif words[0] == "rename":
            src, dst = os.path.realpath(words[1]), os.path.realpath(words[2])
            if os.path.dirname(dst) != folder:
                continue
            renames += 1
            if os.path.basename(dst) in pending:
                problems.append(f"folder not fsync'd between two renames to {os.path.basename(dst)}")
            if src not in synced:
                problems.append(f"{os.path.basename(src)} renamed without fsync")
            synced.discard(src)
            pending.append(os.path.basename(dst))
    if pending:
        problems.append(f"folder not fsync'd after renaming {pending}")
    names = sorted({os.path.basename(w[1]) for w in lines if w[0] == "rename"})
    check(renames > 0 and not problems,
          f"1 {label}: {renames} renames into the folder ({', '.join(names)}), each fsync'd "
          f"before, the folder after" + (f"; {sorted(set(problems))}" if problems else ""))
    return names


if SANITIZED:
    print("skip 1: the sanitizer build (LD_PRELOAD cannot come before its runtime)")
else:
    per = fresh("periodic")
    log = os.path.join(WORK, "sync.log")
    env = {"LD_PRELOAD": os.path.realpath(SHIM), "LUBDEM_SYNC_LOG": log}
    rc, err = run(spec, per, "--checkpoint-every", "0.1", stop_at=0.5, env=env)
    check(rc == 5, f"1: periodic run stopped (exit {rc}) {err[-200:]}")
    names = check_sync_log(log, per, "stopped run")
    check(".checkpoint-result.h5.tmp" in names and ".checkpoint.h5.tmp" in names,
          f"1: periodic checkpoints were taken ({names})")
    os.remove(log)
    rc, err = run(spec, per, "--resume", "--checkpoint-every", "0.1", env=env)
    check(rc == 0, f"1: its continuation completed (exit {rc}) {err[-200:]}")
    check_sync_log(log, per, "continuation")

# ---- 2. a continuation whose summary cannot be written keeps its checkpoint ----
blocked = copy_of(stopped, "blocked")
os.remove(os.path.join(blocked, "summary.json"))
os.makedirs(os.path.join(blocked, "summary.json", "inside"))
rc, err = run(spec, blocked, "--resume", stop_at=0.7)
check(rc == 4 and "cannot write the results" in err,
      f"2: continuation without a summary: exit 4 (got {rc}) {err.strip()[-300:]}")
left = sorted(os.listdir(blocked))
check("checkpoint.h5" in left and "result.h5" in left,
      f"2: checkpoint.h5 and result.h5 kept ({left})")
shutil.rmtree(os.path.join(blocked, "summary.json"))
rc, err = run(spec, blocked, "--resume")
check(rc == 0 and same_results(ref, blocked) and summary(blocked).get("resumed_from_step", 0) > 0,
      f"2: --resume then completes, with the uninterrupted run's results (exit {rc}) "
      f"{err.strip()[-300:]}")

# ---- 3. damaged checkpoint data refused ----
with h5py.File(os.path.join(stopped, "checkpoint.h5"), "r") as f:
    x = f["system/x"]
    xs = x[()]
    check("crc32" in x.attrs and int(x.attrs["crc32"]) == zlib.crc32(xs.astype("<f8").tobytes()),
          "3: system/x carries the CRC-32 of its bytes (zlib's)")
    spec_text = f["spec_resolved"][()]
    spec_text = spec_text.encode() if isinstance(spec_text, str) else spec_text
    check(int(f["spec_resolved"].attrs.get("crc32", -1)) == zlib.crc32(spec_text),
          "3: spec_resolved carries the CRC-32 of its text")
    x_offset = x.id.get_offset()
flipped = copy_of(stopped, "flipped")
with open(os.path.join(flipped, "checkpoint.h5"), "r+b") as f:
    f.seek(x_offset + 3)
    b = f.read(1)
    f.seek(x_offset + 3)
    f.write(bytes([b[0] ^ 0x10]))
before = digest(flipped)
rc, err = run(spec, flipped, "--resume")
check(rc == 2 and "/system/x" in err and "damaged" in err,
      f"3: a flipped byte in system/x refused, exit 2 naming it (got {rc}: {err.strip()[-300:]})")
check(digest(flipped) == before, "3: folder unchanged")
scaled = copy_of(stopped, "scaled")
with h5py.File(os.path.join(scaled, "checkpoint.h5"), "r+") as f:
    v = f["system/v"]
    v[0] = v[0] * 1.01
before = digest(scaled)
rc, err = run(spec, scaled, "--resume")
check(rc == 2 and "/system/v" in err and "damaged" in err,
      f"3: system/v[0] x 1.01 refused, exit 2 naming it (got {rc}: {err.strip()[-300:]})")
check(digest(scaled) == before, "3: folder unchanged")

# ---- 3b. a result.h5 that is not the one the checkpoint was taken with ----
# (another seed's complete run: enough rows, other values). The checkpoint's copy of the strain
# series is compared with the file's first rows bit for bit; until 2026-12-07 only the row count
# was checked, and the continuation carried the other run's rows into its result.h5.
other_spec = os.path.join(WORK, "other_seed.json")
with open(other_spec, "w") as f:
    json.dump(dict(base, seed=99), f)
other_run = fresh("other_seed")
rc, err = run(other_spec, other_run)
swapped = copy_of(stopped, "swapped")
shutil.copyfile(os.path.join(other_run, "result.h5"), os.path.join(swapped, "result.h5"))
before = digest(swapped)
rc, err = run(spec, swapped, "--resume")
check(rc == 2 and "not the file the checkpoint was taken with" in err and "row 0 of strain" in err,
      f"3b: another run's result.h5 refused, exit 2 naming the row (got {rc}: "
      f"{err.strip()[-300:]})")
check(digest(swapped) == before, "3b: folder unchanged")

# ---- 4. the builds that ran the run ----
with h5py.File(os.path.join(stopped, "checkpoint.h5"), "r") as f:
    commit = f.attrs.get("git_commit")
    commit = commit.decode() if isinstance(commit, bytes) else commit
    stop_step = int(f["step"][0])
this = summary(stopped)
check(commit == this["git_commit"] and this.get("builds") == [
    {"lubdem_version": this["lubdem_version"], "git_commit": this["git_commit"], "threads": 1,
     "from_step": 0}],
      f"4: the checkpoint notes the build that wrote it ({commit}); the summary one build")
other = copy_of(stopped, "other_build")
with h5py.File(os.path.join(other, "checkpoint.h5"), "r+") as f:
    f.attrs["git_commit"] = "0123abc-other"
rc, err = run(spec, other, "--resume")
s = summary(other)
warned = [w for w in s.get("warnings", []) if "0123abc-other" in w and this["git_commit"] in w]
check(rc == 0 and warned and "0123abc-other" in err,
      f"4: a checkpoint of another build continued with a warning naming both (exit {rc}; "
      f"{warned[:1]})")
check(s.get("builds") == [
    {"lubdem_version": this["lubdem_version"], "git_commit": "0123abc-other", "threads": 1,
     "from_step": 0},
    {"lubdem_version": this["lubdem_version"], "git_commit": this["git_commit"], "threads": 1,
     "from_step": stop_step}], f"4: summary builds lists both ({s.get('builds')})")
same = copy_of(stopped, "same_build")
rc, err = run(spec, same, "--resume", "--keep-checkpoint")
s = summary(same)
check(rc == 0 and len(s.get("builds", [])) == 1 and "another build" not in err,
      f"4: the same build continues without a warning, one build ({s.get('builds')})")
with h5py.File(os.path.join(same, "checkpoint.h5"), "r") as f:
    notes = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f.attrs.items()}
check(notes.get("git_commit") == this["git_commit"] and notes.get("build_from_step") == "0"
      and notes.get("earlier_builds") == "[]" and notes.get("threads") == "1",
      f"4: its kept checkpoint's notes ({notes})")
# the same build on another thread count: a part of its own, no warning (the summary's threads
# alone said 2 for a run whose first part ran on 1). Needs 2 usable processors.
if len(os.sched_getaffinity(0)) >= 2:
    two = copy_of(stopped, "two_threads")
    rc, err = run(spec, two, "--resume", "--threads", "2", "--keep-checkpoint")
    s = summary(two)
    check(rc == 0 and s.get("threads") == 2 and s.get("builds") == [
        {"lubdem_version": this["lubdem_version"], "git_commit": this["git_commit"], "threads": 1,
         "from_step": 0},
        {"lubdem_version": this["lubdem_version"], "git_commit": this["git_commit"], "threads": 2,
         "from_step": stop_step}] and "another build" not in err,
          f"4: continued on 2 threads, two parts (exit {rc}; {s.get('builds')})")
    with h5py.File(os.path.join(two, "checkpoint.h5"), "r") as f:
        notes = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f.attrs.items()}
    check(notes.get("threads") == "2" and notes.get("build_from_step") == str(stop_step)
          and json.loads(notes.get("earlier_builds", "[]")) == s.get("builds", [])[:1],
          f"4: its kept checkpoint notes the 2-thread part and the 1-thread one before ({notes})")
else:
    print("4: one processor: the 2-thread continuation is skipped")
# a checkpoint without the threads note: its part's thread count is not known
unnoted = copy_of(stopped, "no_threads_note")
with h5py.File(os.path.join(unnoted, "checkpoint.h5"), "r+") as f:
    del f.attrs["threads"]
rc, err = run(spec, unnoted, "--resume")
s = summary(unnoted)
check(rc == 0 and s.get("builds") == [
    {"lubdem_version": this["lubdem_version"], "git_commit": this["git_commit"], "from_step": 0},
    {"lubdem_version": this["lubdem_version"], "git_commit": this["git_commit"], "threads": 1,
     "from_step": stop_step}] and "another build" not in err,
      f"4: a checkpoint without the threads note: its part has no threads ({s.get('builds')})")

# ---- 4b. a checkpoint of a build before a spec member existed ----
# its saved spec lacks the member (/initial_gap, 2026-12-07); this build resolves that spec
# again, so the member takes its default (the behaviour before it), and the run continues to
# the uninterrupted run's results. Until 2026-12-07 such a continuation was refused with
# "/initial_gap: 0.01 here, absent in the stopped run's spec".
older = copy_of(stopped, "older_spec")
with h5py.File(os.path.join(older, "checkpoint.h5"), "r+") as f:
    d = f["spec_resolved"]
    text = d[()]
    text = text.decode() if isinstance(text, bytes) else text
    saved = json.loads(text)
    check("initial_gap" in saved, "4b: the resolved spec holds /initial_gap")
    saved.pop("initial_gap", None)
    new_text = json.dumps(saved).encode()
    dtype, attrs = d.dtype, dict(d.attrs)
    del f["spec_resolved"]
    nd = f.create_dataset("spec_resolved", data=new_text, dtype=h5py.string_dtype(
        "utf-8" if h5py.check_string_dtype(dtype) and h5py.check_string_dtype(dtype).encoding
        == "utf-8" else "ascii", None if h5py.check_string_dtype(dtype) and
        h5py.check_string_dtype(dtype).length is None else len(new_text)))
    for k, v in attrs.items():
        nd.attrs[k] = v
    nd.attrs["crc32"] = np.uint32(zlib.crc32(new_text))
rc, err = run(spec, older, "--resume")
check(rc == 0 and same_results(ref, older),
      f"4b: a checkpoint whose spec lacks /initial_gap continued to the uninterrupted run's "
      f"results (exit {rc}: {err.strip()[-300:]})")

# ---- 5. leftovers of a kill; --checkpoint-every where it does nothing ----
leftover = copy_of(stopped, "leftover")
with open(os.path.join(leftover, ".checkpoint-result.h5.tmp"), "wb") as f:
    f.write(b"part of a copy")
rc, err = run(spec, leftover, "--resume")
check(rc == 0 and not [n for n in os.listdir(leftover) if n.startswith(".")],
      f"5: a leftover .checkpoint-result.h5.tmp removed by the continuation (exit {rc}; "
      f"{sorted(os.listdir(leftover))})")
two = os.path.join(WORK, "two.json")
with open(two, "w") as f:
    json.dump({"scene": "two_spheres_shear"}, f)
two_out = fresh("two")
rc, err = run(two, two_out, "--checkpoint-every", "1")
check(rc == 0 and "--checkpoint-every was ignored" in err
      and any("--checkpoint-every" in w for w in summary(two_out).get("warnings", [])),
      f"5: --checkpoint-every on two_spheres_shear warns (exit {rc}: {err.strip()[-200:]})")

if failures:
    print(f"{len(failures)} FAILED")
    sys.exit(1)
print("all passed")
