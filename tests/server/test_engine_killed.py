"""A simple_shear job whose engine is killed with SIGKILL from outside the service (the OOM
killer picks the engine, not the worker), on a service with periodic checkpoints
(--checkpoint-s 1) and two attempts per job (--max-attempts 2), with the real engine:

1. the service is stopped (SIGTERM) mid-run and started again: attempt 1 continues from the
   checkpoint of its stopped run, and its log keeps what the first run printed (the "attempt 1
   on worker" line, the progress lines, the stop) and goes on after it (until 2026-12-06 the
   log was replaced and began at the continuation);
2. its engine is killed (kill -9): the job runs again as attempt 2, from the last periodic
   checkpoint, and attempt 1's log says why (until 2026-12-06 the job failed at once);
3. attempt 2's engine is killed too: the job fails, its message says the checkpoint is kept
   and how to continue, the files kept are the checkpoint and the rows it goes with (no
   temporary file);
4. `lubdem_client.py extend JOB '{}' --wait` continues it (the inputs come with the results
   document, as the engine wrote no summary) to the results of the engine's own uninterrupted
   run of the same inputs."""
import json
import os
import re
import shutil
import signal
import sqlite3
import subprocess
import sys
import time

import lubd_testlib as T


def poll(srv, tok, jid, cond, what, timeout=120):
    """Polls job jid until cond(doc) holds; returns the last status document."""
    deadline = time.time() + timeout
    while True:
        st, _, doc = srv.request("GET", "/jobs/" + jid, tok)
        T.check(st == 200, "GET /jobs/%s -> %s" % (jid, st))
        if cond(doc):
            return doc
        T.check(doc["status"] in ("accepted", "running") and time.time() < deadline,
                "%s: %s" % (what, doc))
        time.sleep(0.1)


def fresh_checkpoint(out, since):
    """A checkpoint.h5 in out written after `since` (s since the epoch)."""
    path = os.path.join(out, "checkpoint.h5")
    try:
        return os.path.getmtime(path) > since
    except OSError:
        return False


def kill_engine(attempt_dir):
    pids = T.engine_processes(attempt_dir)
    T.check(pids, "no engine running in %s" % attempt_dir)
    for pid in pids:
        os.kill(pid, signal.SIGKILL)
    return time.time()


def run():
    a = T.args()
    srv = T.Server(a, "engine_killed", workers=1,
                   extra=["--checkpoint-s", "1", "--max-attempts", "2"]).fresh()
    tok = srv.token("oom")
    # about 24 s here on the engine's single thread (the sanitized engine ~4 times slower:
    # 5 strain there), long enough for a stop and two kills, each after a checkpoint
    inputs = {"n_particles": 300, "phi": 0.45, "strain": 5 if a.sanitized else 16,
              "transient_strain": 1, "stiffness": 1e5, "snapshots": 3}
    srv.start()
    jobs = os.path.join(srv.run, "jobs")
    try:
        st, _, doc = srv.request("POST", "/processes/simple_shear/execution", tok,
                                 {"inputs": inputs})
        T.check(st == 201, "submit: %s %s" % (st, doc))
        jid = doc["jobID"]
        att1, att2 = os.path.join(jobs, jid, "attempt-1"), os.path.join(jobs, jid, "attempt-2")
        poll(srv, tok, jid, lambda d: d["status"] == "running" and d["progress"] >= 3 and
             fresh_checkpoint(os.path.join(att1, "out"), 0), "running with a checkpoint")
    finally:
        T.check(srv.stop() == 0, "clean stop")
    # 1. the log of the stopped run stays, and the continuation is appended to it
    before = open(os.path.join(att1, "log")).read()
    T.check(before.startswith("lubdemd: job %s attempt 1 on worker" % jid) and
            "progress fraction=" in before, "log before the stop:\n%s" % before)
    t_restart = time.time()
    srv.start()
    try:
        poll(srv, tok, jid, lambda d: d["status"] == "running" and d["attempt"] == 1 and
             fresh_checkpoint(os.path.join(att1, "out"), t_restart), "attempt 1 continued")
        st, _, log = srv.request("GET", "/jobs/%s/log" % jid, tok, raw=True)
        log = log.decode()
        after = log[len(before):]
        T.check(st == 200 and log.startswith(before) and
                "attempt 1 on worker" in after and
                "continuing from the checkpoint of its stopped run" in after,
                "the log of attempt 1 after the restart (%d bytes before the stop):\n%s"
                % (len(before), log))
        # 2. kill -9 of the engine: attempt 2 continues from the periodic checkpoint
        t_kill = kill_engine(att1)
        doc = poll(srv, tok, jid, lambda d: d["attempt"] == 2 and d["status"] == "running",
                   "attempt 2 after the kill", timeout=60)
        log1 = open(os.path.join(att1, "log")).read()
        T.check("requeued: the engine was killed by signal 9 (SIGKILL) on attempt 1 of 2, not by "
                "this service" in log1 and
                re.search(r"attempt 2 continues from the checkpoint of step [1-9][0-9]* \(the "
                          r"last periodic one its engine wrote", log1),
                "attempt 1's log:\n%s" % log1[-2000:])
        poll(srv, tok, jid, lambda d: d["status"] == "running" and
             fresh_checkpoint(os.path.join(att2, "out"), t_kill + 0.5),
             "attempt 2 with a checkpoint of its own")
        log2 = open(os.path.join(att2, "log")).read()
        T.check(re.search(r"continuing from the checkpoint of attempt 1 \(step [1-9]", log2),
                "attempt 2's log:\n%s" % log2)
        # 3. killed again on its last attempt: failed, checkpoint kept, how to continue
        kill_engine(att2)
        doc = T.wait_final(srv, tok, jid, timeout=60)
        T.check(doc["status"] == "failed" and doc["attempt"] == 2 and
                "killed by signal 9 (SIGKILL) on attempt 2, the last of 2" in doc["message"] and
                "is kept" in doc["message"] and "extend %s" % jid in doc["message"],
                "after the second kill: %s" % doc)
        st, _, res = srv.request("GET", "/jobs/%s/results" % jid, tok)
        kept = sorted(os.listdir(os.path.join(jobs, jid, "result")))
        T.check(st == 422 and sorted(res["outputs"]) == ["checkpoint-result.h5", "checkpoint.h5"]
                and kept == sorted(res["outputs"]) and res.get("inputs") == inputs,
                "files of the killed job: %s, on disk %s, inputs %s"
                % (sorted(res.get("outputs") or {}), kept, res.get("inputs")))
        db = sqlite3.connect(os.path.join(srv.run, "queue.db"))
        events = [e for (e,) in db.execute(
            "SELECT event FROM job_events WHERE job_id = ? ORDER BY rowid", (jid,))]
        db.close()
        T.check(events == ["submitted", "claimed", "released", "claimed", "requeued", "claimed",
                           "failed"], "events: %s" % events)
        # 4. the client continues it with the job's own inputs
        client = os.path.join(a.clients, "lubdem_client.py")
        env = dict(os.environ, LUBDEM_URL="http://127.0.0.1:%d" % srv.port, LUBDEM_TOKEN=tok)
        r = subprocess.run([sys.executable, client, "extend", jid, "{}", "--wait", "--timeout",
                            "600"], env=env, capture_output=True, text=True, timeout=700)
        ids = re.findall(r"\b[0-9a-f]{32}\b", r.stdout)
        T.check(r.returncode == 0 and len(ids) == 1,
                "lubdem_client.py extend of the killed job: exit %s\n%s%s"
                % (r.returncode, r.stdout, r.stderr))
        st, _, res = srv.request("GET", "/jobs/%s/results" % ids[0], tok)
        summ = res["summary"]
        spec = os.path.join(a.work, "engine_killed_direct.json")
        with open(spec, "w") as f:
            json.dump(dict(inputs, scene="simple_shear"), f)
        out = os.path.join(a.work, "engine_killed_direct")
        shutil.rmtree(out, ignore_errors=True)
        subprocess.run([a.engine, "run", spec, "--out", out, "--quiet"], check=True,
                       timeout=600, stderr=subprocess.DEVNULL)
        with open(os.path.join(out, "summary.json")) as f:
            ref = json.load(f)
        T.check(summ.get("resumed_from_step", 0) > 0 and summ["results"] == ref["results"] and
                summ["steps"] == ref["steps"],
                "the continued run's results equal the uninterrupted run's (mu %s / %s, from "
                "step %s)" % (summ["results"]["mu"]["value"], ref["results"]["mu"]["value"],
                              summ.get("resumed_from_step")))
    finally:
        srv.stop()


T.main(run)
