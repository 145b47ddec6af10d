"""8 concurrent clients submit 500 jobs in total (queue-only server, --workers 0), each
with an Idempotency-Key; a fifth of them are retried with the same key (sequentially and
racing from two threads). Expect exactly 500 distinct jobs, every retry mapped to its
original job, 409 for a key reused with another body, and 429 + Retry-After over the
per-user cap. Last, a DELETE that races a worker's claim of the job acts on the state the job is
in when it is dismissed, not on the one the request read first (dismiss_racing_claim)."""
import os
import sqlite3
import threading
import time

import lubd_testlib as T

CLIENTS = 8
TOTAL = 500


def dismiss_racing_claim(srv, tok):
    """A DELETE that the request reads queued while a worker claims it and its engine writes
    into attempt-1/out, before the dismissal's transaction (the test stands in for the worker:
    it holds the queue's write lock, so that the request reads the job queued and then waits
    for the lock until the claim is committed). The job is dismissed as the running job it is
    by then, and the files of its engine are left to its worker, which frees them once it has
    stopped the engine. Until 2026-12-07 the request acted on the state it had read before the
    dismissal and removed the files as those of a job taken out of the queue, under the running
    engine."""
    st, _, doc = srv.request("POST", "/processes/falling_sphere/execution", tok,
                             {"inputs": {"duration": 3.0}})
    T.check(st == 201, "submit for the race: %s %s" % (st, doc))
    jid = doc["jobID"]
    out = os.path.join(srv.run, "jobs", jid, "attempt-1", "out")
    db = sqlite3.connect(os.path.join(srv.run, "queue.db"), timeout=30, isolation_level=None)
    answer = []
    try:
        db.execute("BEGIN IMMEDIATE")
        now = "((julianday('now') - 2440587.5) * 86400.0)"
        db.execute("UPDATE jobs SET state = 'running', worker = 'test-worker', lease_token = "
                   "'0123456789abcdef0123456789abcdef', attempt = attempt + 1, started = %s, "
                   "lease_until = %s + 600, heartbeat = %s, updated = %s, message = 'running' "
                   "WHERE id = ?" % (now, now, now, now), (jid,))
        deleter = threading.Thread(
            target=lambda: answer.append(srv.request("DELETE", "/jobs/" + jid, tok)))
        deleter.start()
        time.sleep(1.5)  # the request has read the job (queued) and waits for the lock
        T.check(deleter.is_alive(), "the DELETE did not wait for the claim: %s" % answer)
        os.makedirs(out)
        with open(os.path.join(out, "result.h5"), "w") as f:
            f.write("rows the engine is writing\n")
        db.execute("COMMIT")
        deleter.join(30)
    finally:
        db.close()
    T.check(answer and answer[0][0] == 200 and answer[0][2]["status"] == "dismissed" and
            answer[0][2]["message"].startswith("stopped while it ran"),
            "DELETE racing the claim: %s" % (answer,))
    T.check(os.path.exists(os.path.join(out, "result.h5")),
            "the running engine's files were removed by the DELETE that raced its claim: "
            "%s holds %s" % (os.path.dirname(out), os.listdir(os.path.dirname(out))
                             if os.path.isdir(os.path.dirname(out)) else "nothing"))


def run():
    a = T.args()
    srv = T.Server(a, "concurrency", workers=0,
                   extra=["--user-cap", "100000", "--http-threads", "4"]).fresh()
    tokens = [srv.token("client%d" % i) for i in range(CLIENTS)]
    admin = srv.token("root", admin=True)
    capped = srv.token("capped")
    srv.cli("user", "cap", "--user", "capped", "3")
    srv.start()
    errors = []
    results = {}  # key -> job id
    lock = threading.Lock()

    def submit(tok, key, n):
        body = {"inputs": {"duration": 1.0 + n * 1e-3}}
        for attempt in range(5):
            try:
                return srv.request("POST", "/processes/falling_sphere/execution", tok, body,
                                   {"Idempotency-Key": key})
            except OSError as e:  # connection trouble: retry with the same key
                err = e
                time.sleep(0.05)
        raise err

    def client(ci):
        tok = tokens[ci]
        mine = range(ci, TOTAL, CLIENTS)
        try:
            for n in mine:
                key = "c%d-job%d" % (ci, n)
                st, h, doc = submit(tok, key, n)
                if st != 201:
                    errors.append("submit %s -> %s %s" % (key, st, doc))
                    continue
                jid = doc["jobID"]
                if n % 5 == 0:  # a retry of the same request
                    st2, h2, doc2 = submit(tok, key, n)
                    if st2 != 201 or doc2["jobID"] != jid or h2.get("idempotent-replayed") != "true":
                        errors.append("retry %s -> %s %s" % (key, st2, doc2.get("jobID")))
                with lock:
                    results[key] = jid
        except Exception as e:  # noqa: BLE001 - report any client failure
            errors.append("client %d: %r" % (ci, e))

    t0 = time.time()
    threads = [threading.Thread(target=client, args=(i,)) for i in range(CLIENTS)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(120)
    elapsed = time.time() - t0
    try:
        T.check(not errors, "errors: %s" % errors[:5])
        T.check(len(results) == TOTAL, "accepted %d of %d" % (len(results), TOTAL))
        T.check(len(set(results.values())) == TOTAL, "duplicate job ids")
        # Racing duplicates: the same key from 4 threads at once -> one job.
        race = []
        def racer():
            st, h, doc = submit(tokens[0], "race-key", 7)
            race.append((st, doc.get("jobID")))
        rt = [threading.Thread(target=racer) for _ in range(4)]
        for t in rt:
            t.start()
        for t in rt:
            t.join(30)
        T.check(len(race) == 4 and all(s == 201 for s, _ in race)
                and len({j for _, j in race}) == 1, "racing retries: %s" % race)
        # Numbers compare by value: the same key with the same numbers spelt otherwise (an
        # integer for a real of integral value, an exponent, members reordered) is the same
        # request and gets the original job (it was a 409 until 2026-12-06).
        st, _, doc = srv.request("POST", "/processes/falling_sphere/execution", tokens[0],
                                 b'{"inputs": {"duration": 2}, "priority": -1}',
                                 {"Idempotency-Key": "by-value"})
        T.check(st == 201, "keyed submission: %s %s" % (st, doc))
        for text in (b'{"priority": -1, "inputs": {"duration": 2.0}}',
                     b'{"inputs": {"duration": 2e0}, "priority": -1}'):
            st, h, again = srv.request("POST", "/processes/falling_sphere/execution", tokens[0],
                                       text, {"Idempotency-Key": "by-value"})
            T.check(st == 201 and again.get("jobID") == doc["jobID"] and
                    h.get("idempotent-replayed") == "true",
                    "%s under the same key: %s %s" % (text, st, again))
        # Key reused with a different body -> 409, nothing new queued.
        st, _, doc = srv.request("POST", "/processes/falling_sphere/execution", tokens[0],
                                 {"inputs": {"duration": 99.0}}, {"Idempotency-Key": "race-key"})
        T.check(st == 409 and "different request" in doc["detail"], "409: %s %s" % (st, doc))
        # The queue holds exactly TOTAL + 2 jobs (the race's and by-value's), all distinct.
        ids, path = [], "/jobs?limit=1000"
        while path:
            st, _, lst = srv.request("GET", path, admin)
            T.check(st == 200, "list")
            ids += [j["jobID"] for j in lst["jobs"]]
            nxt = [l["href"] for l in lst["links"] if l["rel"] == "next"]
            path = nxt[0].split(str(srv.port), 1)[1] if nxt else None
        T.check(len(ids) == TOTAL + 2 and len(set(ids)) == TOTAL + 2,
                "queue has %d jobs (%d distinct)" % (len(ids), len(set(ids))))
        st, _, health = srv.request("GET", "/health")
        T.check(health["queue"]["accepted"] == TOTAL + 2, "health queue depth")
        # Per-user cap -> 429 with Retry-After.
        for i in range(3):
            st, _, doc = srv.request("POST", "/processes/falling_sphere/execution", capped,
                                     {"inputs": {}})
            T.check(st == 201, "capped submit %d -> %s" % (i, st))
        st, h, doc = srv.request("POST", "/processes/falling_sphere/execution", capped,
                                 {"inputs": {}})
        T.check(st == 429 and int(h.get("retry-after", "0")) > 0 and "limit 3" in doc["detail"],
                "cap: %s %s" % (st, doc))
        # Dismissing one frees a slot.
        st, _, lst = srv.request("GET", "/jobs?limit=1", capped)
        srv.request("DELETE", "/jobs/" + lst["jobs"][0]["jobID"], capped)
        st, _, doc = srv.request("POST", "/processes/falling_sphere/execution", capped,
                                 {"inputs": {}})
        T.check(st == 201, "after dismiss -> %s" % st)
        dismiss_racing_claim(srv, tokens[1])
        print("submitted=%d clients=%d seconds=%.2f" % (TOTAL, CLIENTS, elapsed))
    finally:
        srv.stop()


T.main(run)
