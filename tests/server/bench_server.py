"""Benchmark (ctest -L bench): requests/s of GET /jobs/{id} and p50/p99 latency of
POST /processes/falling_sphere/execution, on a queue-only server (--workers 0), with the
loopback load generator (loadgen.c). Prints name=value lines and writes
/tmp/readme-server-bench.md for the README."""
import os
import subprocess

import lubd_testlib as T


def extra(p):
    p.add_argument("--loadgen", required=True)
    p.add_argument("--seconds", type=float, default=5.0)


def parse(line):
    return {k: float(v) for k, v in (kv.split("=") for kv in line.split())}


def run():
    a = T.args(extra)
    srv = T.Server(a, "bench", workers=0, extra=["--user-cap", "1000000"]).fresh()
    tok = srv.token("bench")
    srv.start()
    try:
        st, _, doc = srv.request("POST", "/processes/falling_sphere/execution", tok,
                                 {"inputs": {"duration": 1.0}})
        T.check(st == 201, "seed job")
        jid = doc["jobID"]
        rows = []
        for threads in (1, 4):
            out = subprocess.run([a.loadgen, str(srv.port), "GET", "/jobs/" + jid, tok,
                                  str(threads), str(a.seconds), "0"],
                                 capture_output=True, text=True, timeout=120)
            T.check(out.returncode == 0, "loadgen GET failed: %s %s" % (out.stdout, out.stderr))
            r = parse(out.stdout)
            rows.append(("GET /jobs/{id}", threads, r))
            print("get_job_c%d_rps=%.0f" % (threads, r["rps"]))
            print("get_job_c%d_p50_ms=%.3f" % (threads, r["p50_ms"]))
            print("get_job_c%d_p99_ms=%.3f" % (threads, r["p99_ms"]))
        for threads in (1, 4):
            out = subprocess.run([a.loadgen, str(srv.port), "POST",
                                  "/processes/falling_sphere/execution", tok, str(threads),
                                  str(a.seconds), "4000", '{"inputs": {"duration": 1.0}}'],
                                 capture_output=True, text=True, timeout=120)
            T.check(out.returncode == 0, "loadgen POST failed: %s %s" % (out.stdout, out.stderr))
            r = parse(out.stdout)
            rows.append(("POST execution", threads, r))
            print("post_exec_c%d_rps=%.0f" % (threads, r["rps"]))
            print("post_exec_c%d_p50_ms=%.3f" % (threads, r["p50_ms"]))
            print("post_exec_c%d_p99_ms=%.3f" % (threads, r["p99_ms"]))
    finally:
        srv.stop()
    cpu = "?"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    with open("/tmp/readme-server-bench.md", "w") as f:
        f.write("Server benchmark (`ctest -L bench -R server.bench`): loopback, keep-alive, "
                "queue-only server (`--workers 0`), %d cores (%s), %s, %.0f s per row.\n\n"
                % (os.cpu_count(), cpu, "sanitized build" if a.sanitized else "optimised build",
                   a.seconds))
        f.write("| request | clients | requests/s | p50 ms | p99 ms |\n|---|---|---|---|---|\n")
        for name, threads, r in rows:
            f.write("| %s | %d | %.0f | %.3f | %.3f |\n" % (name, threads, r["rps"], r["p50_ms"],
                                                          r["p99_ms"]))
    print("PASS")


run()
