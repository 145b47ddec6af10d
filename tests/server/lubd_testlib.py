"""lubd_testlib.py - start a real lubdemd on 127.0.0.1 (free port) and talk to it.

Used by every tests/server/test_*.py. Standard library only. Each test passes the paths
as command-line arguments: --lubdemd BIN --engine BIN --schema DIR --work DIR.
"""
import argparse
import http.client
import json
import os
import shutil
import signal
import subprocess
import sys
import time


def args(extra=None):
    p = argparse.ArgumentParser()
    p.add_argument("--lubdemd", required=True)
    p.add_argument("--engine", required=True)
    p.add_argument("--schema", required=True)
    p.add_argument("--work", required=True)
    p.add_argument("--sanitized", type=int, default=0)
    p.add_argument("--clients", default="")
    if extra:
        extra(p)
    return p.parse_args()


class Fail(Exception):
    pass


def check(cond, what):
    if not cond:
        raise Fail(what)


class Server:
    """One lubdemd instance with its own run directory."""

    def __init__(self, a, name, workers=1, extra=()):
        self.a = a
        self.run = os.path.join(a.work, name)
        self.workers = workers
        self.extra = list(extra)
        self.proc = None
        self.port = None
        self.log_path = self.run + ".server.log"

    def fresh(self):
        shutil.rmtree(self.run, ignore_errors=True)
        os.makedirs(self.run, exist_ok=True)
        return self

    def cli(self, *argv):
        out = subprocess.run([self.a.lubdemd, *argv, "--run-dir", self.run],
                             capture_output=True, text=True, timeout=30)
        if out.returncode != 0:
            raise Fail("lubdemd %s failed: %s" % (argv, out.stderr))
        return out.stdout.strip()

    def token(self, user, admin=False):
        argv = ["token", "create", "--user", user] + (["--admin"] if admin else [])
        return self.cli(*argv)

    def start(self, timeout=20):
        port_file = self.run + ".port"
        if os.path.exists(port_file):
            os.unlink(port_file)
        mem = ["--mem-mb", "0"] if self.a.sanitized else []
        cmd = [self.a.lubdemd, "--run-dir", self.run, "--listen", "127.0.0.1:0",
               "--port-file", port_file, "--workers", str(self.workers),
               "--engine", self.a.engine, "--schema-dir", self.a.schema, "--quiet",
               *mem, *self.extra]
        logf = open(self.log_path, "a")
        self.proc = subprocess.Popen(cmd, stdout=logf, stderr=logf)
        logf.close()
        deadline = time.time() + timeout
        while time.time() < deadline:
            if self.proc.poll() is not None:
                raise Fail("lubdemd exited with %s; log:\n%s" % (self.proc.returncode,
                                                                  open(self.log_path).read()))
            if os.path.exists(port_file):
                txt = open(port_file).read().strip()
                if txt:
                    self.port = int(txt)
                    return self
            time.sleep(0.05)
        raise Fail("lubdemd did not start")

    def stop(self, sig=signal.SIGTERM, timeout=30):
        if self.proc and self.proc.poll() is None:
            self.proc.send_signal(sig)
            try:
                self.proc.wait(timeout)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
                raise Fail("lubdemd did not stop within %s s" % timeout)
        rc = self.proc.returncode if self.proc else None
        self.proc = None
        self.check_log()
        return rc

    def check_log(self):
        """Sanitizer reports from the service or its workers fail the test."""
        try:
            text = open(self.log_path, errors="replace").read()
        except OSError:
            return
        for marker in ("ERROR: AddressSanitizer", "ERROR: LeakSanitizer", "runtime error:",
                       "Sanitizer:DEADLYSIGNAL"):
            if marker in text:
                i = text.index(marker)
                raise Fail("sanitizer report in %s:\n%s" % (self.log_path, text[i:i + 3000]))

    def worker_pids(self):
        """Direct children of the server process (the workers)."""
        if not self.proc:
            return []
        try:
            with open("/proc/%d/task/%d/children" % (self.proc.pid, self.proc.pid)) as f:
                return [int(x) for x in f.read().split()]
        except OSError:
            return []

    def request(self, method, path, token=None, body=None, headers=None, raw=False,
                timeout=30):
        return request(self.port, method, path, token, body, headers, raw, timeout)


def request(port, method, path, token=None, body=None, headers=None, raw=False, timeout=30):
    """Returns (status, headers dict (lower-case), parsed JSON or bytes)."""
    h = dict(headers or {})
    if token:
        h["Authorization"] = "Bearer " + token
    data = None
    if body is not None:
        data = body if isinstance(body, (bytes, str)) else json.dumps(body)
        if isinstance(data, str):
            data = data.encode()
        h.setdefault("Content-Type", "application/json")
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
    try:
        conn.request(method, path, body=data, headers=h)
        resp = conn.getresponse()
        payload = resp.read()
        hdrs = {k.lower(): v for k, v in resp.getheaders()}
        if raw:
            return resp.status, hdrs, payload
        ctype = hdrs.get("content-type", "")
        if "json" in ctype and payload:
            return resp.status, hdrs, json.loads(payload)
        return resp.status, hdrs, payload
    finally:
        conn.close()


FINAL = ("successful", "failed", "dismissed")


def wait_final(srv, token, job_id, timeout=120):
    deadline = time.time() + timeout
    while time.time() < deadline:
        st, _, body = srv.request("GET", "/jobs/" + job_id, token)
        check(st == 200, "GET /jobs/%s -> %s %s" % (job_id, st, body))
        if body["status"] in FINAL:
            return body
        time.sleep(0.1)
    raise Fail("job %s not final after %s s" % (job_id, timeout))


def engine_processes(marker):
    """PIDs of live processes whose command line mentions `marker` (e.g. a run dir)."""
    found = []
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open("/proc/%s/cmdline" % pid, "rb") as f:
                cmd = f.read().replace(b"\0", b" ").decode(errors="replace")
            with open("/proc/%s/stat" % pid) as f:
                state = f.read().rsplit(")", 1)[1].split()[0]
        except OSError:
            continue
        if marker in cmd and " run " in cmd and state != "Z":
            found.append(int(pid))
    return found


def main(fn):
    try:
        fn()
    except Fail as e:
        print("FAIL:", e)
        sys.exit(1)
    print("PASS")
