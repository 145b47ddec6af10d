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
TOOLS = ("slurmctld", "slurmd", "sbatch", "sinfo", "munged", "mungekey")
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
    finally:
        subprocess.run(["scancel", "--user", "root"], env=env, capture_output=True)
        stop_slurm(d)
    print(f"slurm_resume_jobs={len(stopped_at) + 1}")
    print(f"slurm_resume_failures={len(failures)}")
    sys.exit(1 if failures else 0)


main()
