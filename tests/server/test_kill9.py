""""Nothing lost": kill -9 the server (with its workers) or single workers while jobs run,
REPS times, restarting the server after each server kill. Afterwards every accepted job
reaches a final state exactly once (job_events audit), attempts of a job never overlap
(between two claims there is always a requeue), no engine outlives its killed worker, and
every successful job serves a complete result.h5 whose sha256 matches."""
import hashlib
import os
import random
import signal
import sqlite3
import time

import lubd_testlib as T


def extra(p):
    p.add_argument("--reps", type=int, default=20)


def run():
    a = T.args(extra)
    rnd = random.Random(1234)
    srv = T.Server(a, "kill9", workers=2,
                   extra=["--lease-s", "2", "--grace-s", "1", "--max-attempts", "20"]).fresh()
    tok = srv.token("chaos")
    accepted = []
    server_kills = worker_kills = 0
    srv.start()
    try:
        for rep in range(a.reps):
            if srv.proc is None:
                srv.start()
            for _ in range(3):
                longest = 8.0 if a.sanitized else 30.0  # ASan engines run ~4x slower
                if rnd.random() < 0.7:
                    pid, inputs = "falling_sphere", {"duration": rnd.uniform(1.0, longest)}
                else:
                    pid, inputs = "two_spheres_shear", {"duration": rnd.uniform(1.0, 8.0)}
                st, _, doc = srv.request("POST", "/processes/%s/execution" % pid, tok,
                                         {"inputs": inputs},
                                         {"Idempotency-Key": "rep%d-%d" % (rep, len(accepted))})
                T.check(st == 201, "submit -> %s %s" % (st, doc))
                accepted.append(doc["jobID"])
            time.sleep(rnd.uniform(0.2, 1.2))
            workers = srv.worker_pids()
            if rep % 2 == 0:
                # The server and its workers, all with SIGKILL (every other time only the
                # server: its workers and their engines must die with it).
                if rep % 4 == 0:
                    for w in workers:
                        os.kill(w, signal.SIGKILL)
                srv.proc.send_signal(signal.SIGKILL)
                srv.proc.wait(10)
                srv.proc = None
                server_kills += 1
                deadline = time.time() + 5
                while T.engine_processes(srv.run) and time.time() < deadline:
                    time.sleep(0.05)
                left = T.engine_processes(srv.run)
                T.check(not left, "rep %d: engines %s outlived the killed service" % (rep, left))
                def alive(pid):
                    try:
                        with open("/proc/%d/stat" % pid) as f:
                            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
                    except OSError:
                        return False
                deadline = time.time() + 5
                while any(alive(w) for w in workers) and time.time() < deadline:
                    time.sleep(0.05)
                orphans = [w for w in workers if alive(w)]
                T.check(not orphans, "rep %d: workers %s outlived the server" % (rep, orphans))
            elif workers:
                os.kill(rnd.choice(workers), signal.SIGKILL)
                worker_kills += 1
        if srv.proc is None:
            srv.start()
        # Everything accepted reaches a final state.
        deadline = time.time() + 240
        pending = set(accepted)
        final = {}
        while pending and time.time() < deadline:
            for jid in list(pending):
                st, _, doc = srv.request("GET", "/jobs/" + jid, tok)
                T.check(st == 200, "job %s lost: %s" % (jid, st))
                if doc["status"] in T.FINAL:
                    final[jid] = doc
                    pending.discard(jid)
            time.sleep(0.2)
        T.check(not pending, "%d jobs never finished" % len(pending))
        ok = [j for j, d in final.items() if d["status"] == "successful"]
        T.check(len(ok) >= len(accepted) * 0.9,
                "only %d/%d successful: %s" % (len(ok), len(accepted),
                                               [d["message"] for d in final.values()
                                                if d["status"] != "successful"][:3]))
        for jid in ok:
            st, _, res = srv.request("GET", "/jobs/%s/results" % jid, tok)
            T.check(st == 200, "results of %s" % jid)
            want = res["outputs"]["result.h5"]
            st, _, data = srv.request("GET", "/jobs/%s/results/result.h5" % jid, tok, raw=True)
            T.check(st == 200 and len(data) == want["size"]
                    and hashlib.sha256(data).hexdigest() == want["sha256"]
                    and data[:8] == b"\x89HDF\r\n\x1a\n", "result of %s incomplete" % jid)
    finally:
        if srv.proc is not None:
            srv.stop()
    # The audit trail: one terminal event per job, no overlapping attempts, fenced finish.
    db = sqlite3.connect("file:%s/queue.db?mode=ro" % srv.run, uri=True)
    max_attempt = 0
    for jid in accepted:
        ev = db.execute("SELECT event, token, attempt FROM job_events WHERE job_id = ? "
                        "ORDER BY seq", (jid,)).fetchall()
        names = [e[0] for e in ev]
        terminal = [e for e in ev if e[0] in ("successful", "failed")]
        T.check(len(terminal) == 1, "job %s terminal events: %s" % (jid, names))
        T.check(names[-1] in ("successful", "failed"), "events after the end: %s" % names)
        holder = None
        for name, token, attempt in ev:
            if name == "claimed":
                T.check(holder is None, "job %s claimed twice without requeue: %s" %
                        (jid, names))
                holder = token
                max_attempt = max(max_attempt, attempt)
            elif name in ("requeued", "released"):
                T.check(holder is not None, "requeue without claim: %s" % names)
                holder = None
            elif name in ("successful", "failed"):
                T.check(token == holder, "job %s finished by a stale lease" % jid)
        state = db.execute("SELECT state FROM jobs WHERE id = ?", (jid,)).fetchone()[0]
        T.check(state == terminal[0][0], "state %s vs event %s" % (state, terminal[0][0]))
    requeues = db.execute("SELECT count(*) FROM job_events WHERE event = 'requeued'").fetchone()[0]
    print("reps=%d server_kills=%d worker_kills=%d jobs=%d successful=%d requeues=%d "
          "max_attempt=%d" % (a.reps, server_kills, worker_kills, len(accepted), len(ok),
                              requeues, max_attempt))
    T.check(requeues > 0, "no job was ever interrupted: the test did not test anything")


T.main(run)
