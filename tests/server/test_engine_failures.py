"""Worker failure paths with a fake engine (fake_engine.sh): a numerical failure (diagnostic
from summary.json), an output error (failure_kind system; result.h5 lost, the summary kept), a
crash (SIGSEGV), a clean exit without files and a stopped run (exit 5) that left a partial
result.h5 and a checkpoint. Each job fails once with the engine's diagnostic and is not
retried; /results answers with the problem and, where the engine wrote any, the failed
attempt's summary (the results of a run whose result.h5 could not be written) and the files it
kept, listed under "outputs" and served with their sha256 (never a temporary file); the worker
survives."""
import hashlib
import os
import sys
import time

import lubd_testlib as T

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "client_examples"))
import lubdem_client  # noqa: E402


def run():
    a = T.args()
    a.engine = os.path.join(os.path.dirname(os.path.abspath(__file__)), "fake_engine.sh")
    srv = T.Server(a, "engine_failures", workers=1, extra=["--lease-s", "2"]).fresh()
    tok = srv.token("dave")
    srv.start()
    try:
        cases = {3: ("executor", "NaN in the gap"),
                 4: ("system", "No space left on device"),
                 11: ("executor", "signal 11"),
                 7: ("executor", "summary.json or result.h5 is missing"),
                 5: ("executor", "CPU time limit")}
        kept = {3: ["summary.json"], 4: ["summary.json"], 11: [], 7: [],
                5: ["checkpoint.h5", "result.h5", "summary.json"]}
        ids = {}
        for dur in cases:
            st, _, doc = srv.request("POST", "/processes/falling_sphere/execution", tok,
                                     {"inputs": {"duration": dur}})
            T.check(st == 201, "submit %s" % dur)
            ids[dur] = doc["jobID"]
        for dur, (kind, text) in cases.items():
            final = T.wait_final(srv, tok, ids[dur], timeout=60)
            T.check(final["status"] == "failed" and final["failure_kind"] == kind
                    and text in final["message"] and final["attempt"] == 1,
                    "duration %s: %s" % (dur, final))
            st, _, res = srv.request("GET", "/jobs/%s/results" % ids[dur], tok)
            T.check(st == (500 if kind == "system" else 422) and text in res["detail"],
                    "results of failed job %s -> %s" % (dur, st))
            summary = res.get("summary")
            if dur in (3, 4, 5):  # the engine wrote a summary: it comes with the problem
                T.check(isinstance(summary, dict)
                        and summary["status"] == ("partial" if dur == 5 else "failed")
                        and text in summary["diagnostic"], "summary of failed job %s: %s" % (dur, res))
            else:
                T.check(summary is None, "summary of failed job %s: %s" % (dur, res))
            if dur == 4:  # result.h5 lost, the run's results kept
                T.check(summary and summary["results"]["rebound_height"]["value"] == 0.25,
                        "results of job %s: %s" % (dur, summary))
            # the Python client example hands out the same summary (None without one)
            client = lubdem_client.Client("http://127.0.0.1:%d" % srv.port, tok)
            T.check(client.summary(ids[dur]) == summary, "client summary of job %s" % dur)
            outputs = res.get("outputs") or {}
            T.check(sorted(outputs) == kept[dur], "outputs of failed job %s: %s" % (dur, outputs))
            for name, o in outputs.items():
                st, hd, body = srv.request("GET", "/jobs/%s/results/%s" % (ids[dur], name), tok,
                                           raw=True)
                T.check(st == 200 and hashlib.sha256(body).hexdigest() == o["sha256"]
                        and len(body) == o["size"] and o["href"].endswith("/results/" + name),
                        "file %s of failed job %s -> %s" % (name, dur, st))
            if "result.h5" not in outputs:
                st, _, res = srv.request("GET", "/jobs/%s/results/result.h5" % ids[dur], tok)
                T.check(st == 404, "result.h5 of failed job %s -> %s" % (dur, st))
            st, _, res = srv.request("GET", "/jobs/%s/results/.result.h5.tmp" % ids[dur], tok)
            T.check(st == 404, "temporary file of failed job %s -> %s" % (dur, st))
            st, _, log = srv.request("GET", "/jobs/%s/log" % ids[dur], tok, raw=True)
            T.check(st == 200 and b"progress fraction=0.5000" in log, "log of %s" % dur)
        time.sleep(3)  # > lease: nothing comes back to life
        for dur in cases:
            st, _, doc = srv.request("GET", "/jobs/" + ids[dur], tok)
            T.check(doc["status"] == "failed" and doc["attempt"] == 1, "retried: %s" % doc)
        st, _, h = srv.request("GET", "/health")
        T.check(h["workers"]["alive"] == 1 and h["queue"]["running"] == 0, "health %s" % h)
    finally:
        srv.stop()


T.main(run)
