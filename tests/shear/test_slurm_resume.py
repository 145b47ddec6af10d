#!/usr/bin/env python3
"""The README's Slurm recipe for long runs, on a real single-node Slurm (ctest label `slurm`).

README "Stopping and resuming": a batch script whose last line is
`exec lubdem run SPEC --out DIR --resume`, submitted with `--signal=B:TERM@S`, stops S seconds
(give or take Slurm's 60 s signal resolution) before its time limit with a checkpoint, and the
same script submitted again continues where it stopped. This test starts its own Slurm
controller and node daemon (Debian's slurm-wlm and munge, configuration and state under
WORKDIR, ports 16817/16818), submits a `simple_shear` run of about 3 minutes with a 2-minute
time limit again and again (`sbatch --wait`) until its summary says complete, and checks:
  * every job but the last ended by the signal before its limit (exit 5, status partial, a
    checkpoint), and each later one continued from the step the one before stopped at;
  * the chain's last summary and result.h5 equal, bit for bit, those of the same run made in
    one piece outside Slurm on the same thread count.
Then the README's second recipe, a job that requeues itself (`lubdem` in the background, the
batch shell passing TERM on, `scontrol requeue` on exit 5, `--requeue`), submitted once with a
shorter run (60 strain, about 85 s):
  * it ran again after its stop (Slurm's Restarts >= 1, "lubdem exit 5" then "lubdem exit 0"
    in its output), and its summary and result.h5 equal the run in one piece bit for bit;
  * the same job cancelled with scancel while it runs stops with a checkpoint and is not
    requeued (JobState CANCELLED, nothing pending 20 s later).
Needs root (the daemons), slurmctld, slurmd, sbatch, munged and mungekey; exits 77 (skipped)
without them. Usage: test_slurm_resume.py LUBDEM WORKDIR
"""
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time

from h5_datasets import differing  # the script's folder

LUBDEM, WORK = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
TOOLS = ("slurmctld", "slurmd", "sbatch", "sinfo", "squeue", "scontrol", "scancel", "munged",
         "mungekey")
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def skip(why):
    print("skipped: " + why)
    sys.exit(77)


def start_slurm():
    """Writes a one-node configuration under WORK/slurm and starts munged, slurmctld and
    slurmd on it. Returns the environment for the Slurm clients."""
    d = os.path.join(WORK, "slurm")
    shutil.rmtree(d, ignore_errors=True)
    for sub in ("state", "spool"):
        os.makedirs(os.path.join(d, sub))
    os.chmod(WORK, 0o755)
    os.chmod(d, 0o755)  # munged wants its socket's folder reachable by all
    sock = os.path.join(d, "munge.sock")
    subprocess.run(["mungekey", "-c", "-f", "-k", os.path.join(d, "munge.key")], check=True)
    subprocess.run(["munged", "-f", "--socket=" + sock, "--key-file=" + d + "/munge.key",
                    "--log-file=" + d + "/munged.log", "--pid-file=" + d + "/munged.pid",
                    "--seed-file=" + d + "/munged.seed"], check=True)
    host = socket.gethostname().split(".")[0]
    conf = os.path.join(d, "slurm.conf")
    with open(conf, "w") as f:
        f.write(f"""ClusterName=lubdemtest
SlurmctldHost={host}
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={sock}
StateSaveLocation={d}/state
SlurmdSpoolDir={d}/spool
SlurmctldPidFile={d}/slurmctld.pid
SlurmdPidFile={d}/slurmd.pid
SlurmctldLogFile={d}/slurmctld.log
SlurmdLogFile={d}/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
KillWait=30
NodeName={host} CPUs={os.cpu_count()} State=UNKNOWN
PartitionName=test Nodes={host} Default=YES MaxTime=INFINITE State=UP
""")
    env = dict(os.environ, SLURM_CONF=conf)
    subprocess.run(["slurmctld", "-f", conf], check=True, env=env)
    subprocess.run(["slurmd", "-f", conf], check=True, env=env)
    for _ in range(60):
        state = subprocess.run(["sinfo", "-h", "-o", "%T"], env=env, capture_output=True,
                               text=True).stdout.strip()
        if state == "idle":
            return env, d
        time.sleep(1)
    stop_slurm(d)
    skip("the Slurm node did not come up (sinfo: %r; see %s)" % (state, d))


def stop_slurm(d):
    for name in ("slurmd", "slurmctld", "munged"):
        try:
            with open(os.path.join(d, name + ".pid")) as f:
                os.kill(int(f.read().split()[0]), 15)
        except (OSError, ValueError):
            pass


def requeue_script(path, spec, out):
    """The README's self-requeuing batch script for spec into out."""
    with open(path, "w") as f:
        f.write(f"""#!/bin/sh
#SBATCH --time=2
#SBATCH --signal=B:TERM@60
#SBATCH --cpus-per-task=2
#SBATCH --requeue
#SBATCH --open-mode=append
#SBATCH --output={out}.slurm.out
trap 'kill -TERM "$pid" 2>/dev/null' TERM
{LUBDEM} run {spec} --out {out} --threads 2 --resume &
pid=$!
wait "$pid"; rc=$?
while kill -0 "$pid" 2>/dev/null; do wait "$pid"; rc=$?; done
echo "lubdem exit $rc"
if [ "$rc" -eq 5 ] && scontrol show job "$SLURM_JOB_ID" | grep -q JobState=RUNNING; then
  scontrol requeue "$SLURM_JOB_ID"
fi
exit "$rc"
""")


def job_field(env, jid, field):
    """A field of `scontrol show job` ("" when the job is unknown)."""
    text = subprocess.run(["scontrol", "show", "job", jid], env=env, capture_output=True,
                          text=True).stdout
    for word in text.split():
        if word.startswith(field + "="):
            return word.split("=", 1)[1]
    return ""


def in_queue(env, jid):
    return subprocess.run(["squeue", "-h", "-j", jid, "-o", "%T"], env=env, capture_output=True,
                          text=True).stdout.strip()


def self_requeue(env):
    """The README's second recipe: one sbatch, the job requeues itself until the run is
    complete; and a scancel is not undone by it."""
    spec = os.path.join(WORK, "spec60.json")
    with open(spec, "w") as f:  # about 85 s on 2 threads here
        json.dump({"scene": "simple_shear", "n_particles": 1000, "phi": 0.5, "stiffness": 1e4,
                   "strain": 60, "sample_strain": 0.01, "transient_strain": 0.5}, f)
    out, ref = os.path.join(WORK, "requeued"), os.path.join(WORK, "ref60")
    for p in (out, ref):
        shutil.rmtree(p, ignore_errors=True)
    if os.path.exists(out + ".slurm.out"):
        os.unlink(out + ".slurm.out")
    script = os.path.join(WORK, "requeue.sh")
    requeue_script(script, spec, out)
    jid = subprocess.run(["sbatch", "--parsable", script], env=env, capture_output=True,
                         text=True).stdout.strip()
    t0 = time.time()
    # Slurm holds a requeued job until about 2 minutes after its requeue (BeginTime)
    while time.time() - t0 < 900 and in_queue(env, jid):
        time.sleep(2)
    wall = time.time() - t0
    log = open(out + ".slurm.out").read() if os.path.exists(out + ".slurm.out") else ""
    s = json.load(open(os.path.join(out, "summary.json")))
    restarts = job_field(env, jid, "Restarts")
    print(f"self-requeuing job {jid}: {wall:.0f} s, restarts {restarts}, status {s['status']}, "
          f"resumed from {s.get('resumed_from_step')}; its output: "
          f"{[l for l in log.splitlines() if l.startswith('lubdem exit')]}", flush=True)
    check(s["status"] == "complete" and restarts not in ("", "0") and
          log.count("lubdem exit 5") >= 1 and "lubdem exit 0" in log and
          s.get("resumed_from_step", 0) > 0,
          f"the self-requeuing job stopped, ran again (Restarts={restarts}) and completed the "
          f"run (from step {s.get('resumed_from_step')})")
    subprocess.run([LUBDEM, "run", spec, "--out", ref, "--threads", "2", "--quiet"],
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=1800)
    r = json.load(open(os.path.join(ref, "summary.json")))
    n, bad = differing(os.path.join(ref, "result.h5"), os.path.join(out, "result.h5"))
    check(r["results"] == s["results"] and r["steps"] == s["steps"] and not bad,
          f"the self-requeued run's summary and result.h5 ({n} datasets) equal the run in one "
          f"piece" + (f"; differ: {bad[:4]}" if bad else ""))

    # scancel: the job stops (with a checkpoint) and stays cancelled
    shutil.rmtree(out, ignore_errors=True)
    jid = subprocess.run(["sbatch", "--parsable", script], env=env, capture_output=True,
                         text=True).stdout.strip()
    t0 = time.time()
    while time.time() - t0 < 120 and in_queue(env, jid) != "RUNNING":
        time.sleep(1)
    time.sleep(10)
    subprocess.run(["scancel", jid], env=env, check=True)
    t0 = time.time()
    while time.time() - t0 < 60 and in_queue(env, jid):
        time.sleep(1)
    time.sleep(20)
    state, left = job_field(env, jid, "JobState"), in_queue(env, jid)
    s = json.load(open(os.path.join(out, "summary.json")))
    check(state == "CANCELLED" and not left and s["status"] == "partial" and
          os.path.exists(os.path.join(out, "checkpoint.h5")),
          f"a scancel of the self-requeuing job stops the run with a checkpoint (status "
          f"{s['status']}) and is not undone (JobState={state}, queue {left!r} 20 s later)")


def main():
    # stopped from outside (a ctest timeout, Ctrl-C): still stop the daemons (finally below)
    signal.signal(signal.SIGTERM, lambda *_: sys.exit("stopped by SIGTERM"))
    if os.geteuid() != 0:
        skip("needs root to start the Slurm daemons")
    missing = [t for t in TOOLS if not shutil.which(t)]
    if missing:
        skip("not installed: " + ", ".join(missing) + " (apt-get install slurm-wlm munge)")
    os.makedirs(WORK, exist_ok=True)
    spec = os.path.join(WORK, "spec.json")
    with open(spec, "w") as f:  # about 3 min on 2 threads here (2.3 s per strain)
        json.dump({"scene": "simple_shear", "n_particles": 1000, "phi": 0.5, "stiffness": 1e4,
                   "strain": 80, "sample_strain": 0.01, "transient_strain": 0.5}, f)
    chain, ref = os.path.join(WORK, "chain"), os.path.join(WORK, "ref")
    for p in (chain, ref):
        shutil.rmtree(p, ignore_errors=True)
    script = os.path.join(WORK, "job.sh")
    with open(script, "w") as f:  # the README's recipe
        f.write(f"""#!/bin/sh
#SBATCH --time=2
#SBATCH --signal=B:TERM@60
#SBATCH --cpus-per-task=2
#SBATCH --output={WORK}/slurm-%j.out
exec {LUBDEM} run {spec} --out {chain} --threads 2 --resume
""")
    env, d = start_slurm()
    try:
        stopped_at = []
        for round_ in range(1, 9):
            t0 = time.time()
            p = subprocess.run(["sbatch", "--wait", "--parsable", script], env=env,
                               capture_output=True, text=True)
            wall = time.time() - t0
            s = json.load(open(os.path.join(chain, "summary.json")))
            print(f"job {round_} ({p.stdout.strip()}): sbatch exit {p.returncode} after "
                  f"{wall:.0f} s, status {s['status']}, steps {s['steps']}, resumed from "
                  f"{s.get('resumed_from_step')}", flush=True)
            if round_ > 1:
                check(s.get("resumed_from_step") == stopped_at[-1],
                      f"job {round_} continued from step {stopped_at[-1]} where job "
                      f"{round_ - 1} stopped (resumed_from_step {s.get('resumed_from_step')})")
            if s["status"] == "complete":
                check(p.returncode == 0, f"job {round_} completed the run (exit {p.returncode})")
                break
            check(p.returncode == 5 and s["status"] == "partial" and
                  os.path.exists(os.path.join(chain, "checkpoint.h5")) and wall < 120 + 30,
                  f"job {round_} stopped by the signal before its 2-minute limit with a "
                  f"checkpoint (exit {p.returncode}, {wall:.0f} s)")
            stopped_at.append(s["steps"])
        check(len(stopped_at) >= 1 and s["status"] == "complete",
              f"the run completed in a chain of {len(stopped_at) + 1} jobs")
        # the reference, in one piece on the same thread count (after the chain: two 2-thread
        # runs on 2 cores would slow each other many times over)
        subprocess.run([LUBDEM, "run", spec, "--out", ref, "--threads", "2", "--quiet"],
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=1800)
        r = json.load(open(os.path.join(ref, "summary.json")))
        check(r["results"] == s["results"] and r["steps"] == s["steps"],
              f"the chain's results equal the run in one piece (mu {s['results']['mu']['value']}"
              f" / {r['results']['mu']['value']}, {s['steps']} steps)")
        n, bad = differing(os.path.join(ref, "result.h5"), os.path.join(chain, "result.h5"))
        check(not bad, f"the chain's result.h5 equals the run in one piece bit for bit ({n} "
              f"datasets)" + (f"; differ: {bad[:4]}" if bad else ""))
        self_requeue(env)
    finally:
        subprocess.run(["scancel", "--user", "root"], env=env, capture_output=True)
        stop_slurm(d)
    print(f"slurm_resume_jobs={len(stopped_at) + 1}")
    print(f"slurm_resume_failures={len(failures)}")
    sys.exit(1 if failures else 0)


main()
