"""Client examples retried and timed out, against a live server:

* ci_submit.sh that times out leaves its job to run (it used to dismiss it, and a retried CI
  step with the same Idempotency-Key then got the dismissed job back for a day and could
  never succeed): the retried step finds the same job and succeeds; with
  LUBDEM_DISMISS_ON_TIMEOUT=1 the job is dismissed, and the retried step submits a new one
  under KEY-after-JOBID; the default key is the CI step's (GitLab's pipeline and job name,
  GitHub's run and job) with a hash of the request: a retry with a new CI_JOB_ID gets the same
  job, other inputs a new one, and without a CI step a random key comes with a warning;
* ci_submit.sh after two dismissals under a 200-character CI job name: the derived key stays
  within 255 characters (it grew past them and was refused); a token revoked while it polls:
  exit 1 with an error line (curl's 22); no service at the URL: exit 2 with an error line
  (curl's 7), and flow_curve.py exit 2 with an error line (a traceback);
* lubdem_client.py extend of a running job says it has not ended (it said HTTP 404);
* read_result.py prints the build provenance (the attributes of /parameters/build; it printed
  the group's repr);
* flow_curve.py --chain with --key run again after the deadline passed, when a continuation
  is submitted in its last round of polls: the table is written and it exits 1 on the timeout
  (it raised KeyError), and the jobs it found again are printed as "found", not "queued"."""
import csv
import os
import re
import shutil
import socket
import subprocess
import sys
import time

import lubd_testlib as T


class Dead:
    """A server that is not there: a port nothing listens on."""

    def __init__(self, port):
        self.port = port


def run():
    a = T.args()
    ce = a.clients
    out_dir = os.path.join(a.work, "client-retries-out")
    shutil.rmtree(out_dir, ignore_errors=True)
    os.makedirs(out_dir)

    def sh(srv, tok, *argv, timeout=300, extra_env=None):
        e = dict(os.environ, LUBDEM_URL="http://127.0.0.1:%d" % srv.port, LUBDEM_TOKEN=tok,
                 PATH="/usr/bin:/bin:" + os.environ.get("PATH", ""), **(extra_env or {}))
        r = subprocess.run(list(argv), env=e, capture_output=True, text=True, timeout=timeout,
                           cwd=out_dir)
        return r.returncode, r.stdout + r.stderr

    srv = T.Server(a, "client-retries", workers=1).fresh()
    tok = srv.token("ci")
    srv.start()
    try:
        ci = os.path.join(ce, "ci_submit.sh")

        def block():
            """A long job that keeps the only worker busy."""
            st, _, doc = srv.request("POST", "/processes/falling_sphere/execution", tok,
                                     {"inputs": {"duration": 1e6}})
            T.check(st == 201, "blocker: %s" % doc)
            deadline = time.time() + 30
            while doc["status"] != "running" and time.time() < deadline:
                time.sleep(0.1)
                doc = srv.request("GET", "/jobs/" + doc["jobID"], tok)[2]
            T.check(doc["status"] == "running", "blocker running: %s" % doc)
            return doc["jobID"]

        blocker = block()
        # extend of a running job: the client says it has not ended
        rc, out = sh(srv, tok, sys.executable, os.path.join(ce, "lubdem_client.py"), "extend",
                     blocker, "{}")
        # "404" looked for with the job ID taken out: a random ID holds "404" about once in
        # 140 jobs (ce750360932b233f8f4049f93bc3b763 failed the 2026-12-07 clean-clone run)
        T.check(rc == 1 and "is running: a job can be continued once it has ended" in out and
                "404" not in out.replace(blocker, "JOBID"), "extend of a running job:\n" + out)
        # ci_submit.sh times out while its job waits behind the blocker: the job stays
        inputs = '{"duration": 30.0}'
        key = {"LUBDEM_IDEMPOTENCY_KEY": "ci-retry-1"}
        h5 = os.path.join(out_dir, "ci.h5")
        rc, out = sh(srv, tok, "bash", ci, "two_spheres_shear", inputs, "1", h5, extra_env=key)
        job = re.search(r"job ([0-9a-f]{32}) submitted", out)
        T.check(rc == 3 and job and "left to run" in out, "ci_submit.sh timeout:\n" + out)
        job = job.group(1)
        st, _, doc = srv.request("GET", "/jobs/" + job, tok)
        T.check(doc["status"] == "accepted", "the timed-out CI job: %s" % doc)
        srv.request("DELETE", "/jobs/" + blocker, tok)
        # the retried step: the same job, which it waits for, successful
        rc, out = sh(srv, tok, "bash", ci, "two_spheres_shear", inputs, "300", h5, extra_env=key)
        T.check(rc == 0 and ("job %s submitted" % job) in out and "verified" in out,
                "retried CI step after a timeout:\n" + out)
        # LUBDEM_DISMISS_ON_TIMEOUT=1: dismissed, and the retried step submits anew
        blocker = block()
        key = {"LUBDEM_IDEMPOTENCY_KEY": "ci-retry-2"}
        rc, out = sh(srv, tok, "bash", ci, "two_spheres_shear", inputs, "1", h5,
                     extra_env=dict(key, LUBDEM_DISMISS_ON_TIMEOUT="1"))
        job = re.search(r"job ([0-9a-f]{32}) submitted", out)
        T.check(rc == 3 and job and "dismissing job" in out,
                "ci_submit.sh timeout, dismissing:\n" + out)
        job = job.group(1)
        T.check(srv.request("GET", "/jobs/" + job, tok)[2]["status"] == "dismissed",
                "dismissed on timeout")
        srv.request("DELETE", "/jobs/" + blocker, tok)
        rc, out = sh(srv, tok, "bash", ci, "two_spheres_shear", inputs, "300", h5, extra_env=key)
        again = re.search(r"job ([0-9a-f]{32}) submitted \(Idempotency-Key ci-retry-2-after-%s\)"
                          % job, out)
        T.check(rc == 0 and again and again.group(1) != job and
                ("job %s (Idempotency-Key ci-retry-2) was dismissed; submitting again" % job)
                in out and "verified" in out,
                "retried CI step after a dismissal:\n" + out)
        # once more: the job of the derived key is found again, no new one
        rc, out = sh(srv, tok, "bash", ci, "two_spheres_shear", inputs, "300", h5, extra_env=key)
        T.check(rc == 0 and ("job %s submitted" % again.group(1)) in out,
                "a second retry finds the resubmitted job:\n" + out)
        # two dismissals under a long CI job name: the key stays within the service's 255
        # characters (until 2026-12-07 it grew by -after-JOBID per dismissal, to 266 here, and
        # the third try was refused, exit 2)
        long_step = {"LUBDEM_IDEMPOTENCY_KEY": "", "CI_PIPELINE_ID": "813",
                     "CI_JOB_NAME": "n" * 200, "GITHUB_RUN_ID": "", "GITHUB_JOB": ""}
        blocker = block()
        dismissed = []
        for _ in range(2):
            rc, out = sh(srv, tok, "bash", ci, "two_spheres_shear", inputs, "1", h5,
                         extra_env=dict(long_step, LUBDEM_DISMISS_ON_TIMEOUT="1"))
            job = re.search(r"job ([0-9a-f]{32}) submitted \(Idempotency-Key ([^)]*)\)", out)
            T.check(rc == 3 and job and "dismissing job" in out,
                    "long CI job name, dismissal %d:\n%s" % (len(dismissed) + 1, out))
            dismissed.append(job.group(1))
            if len(dismissed) == 1:
                base_key = job.group(2)
        srv.request("DELETE", "/jobs/" + blocker, tok)
        rc, out = sh(srv, tok, "bash", ci, "two_spheres_shear", inputs, "300", h5,
                     extra_env=long_step)
        job = re.search(r"job ([0-9a-f]{32}) submitted \(Idempotency-Key ([^)]*)\)", out)
        T.check(rc == 0 and job and job.group(1) not in dismissed and len(base_key) > 180 and
                job.group(2) == base_key[:216] + "-after-" + dismissed[1] and
                len(job.group(2)) <= 255 and "verified" in out,
                "long CI job name after two dismissals (key %s):\n%s" % (base_key, out))
        # the default Idempotency-Key: a retry of the same CI step (GitLab: a new CI_JOB_ID,
        # the same pipeline and job name; GitHub: the same run and job) gets the same job; the
        # same step with other inputs a new one (until 2026-12-07 the key was ci-$CI_JOB_ID-
        # PROCESS: a GitLab retry submitted a second job, and other inputs were refused, 409)
        no_ci = {"LUBDEM_IDEMPOTENCY_KEY": "", "CI_JOB_ID": "", "CI_PIPELINE_ID": "",
                 "CI_JOB_NAME": "", "GITHUB_RUN_ID": "", "GITHUB_JOB": ""}
        small = '{"duration": 2.0}'

        def ci_job(inputs, **env):
            rc, out = sh(srv, tok, "bash", ci, "two_spheres_shear", inputs, "300", h5,
                         extra_env=dict(no_ci, **env))
            job = re.search(r"job ([0-9a-f]{32}) submitted \(Idempotency-Key ([^)]*)\)", out)
            T.check(rc == 0 and job, "ci_submit.sh with %s:\n%s" % (env, out))
            return job.group(1) if job else None, job.group(2) if job else None, out
        gitlab = {"CI_PIPELINE_ID": "812", "CI_JOB_NAME": "shear sweep 1/2"}
        first, key1, _ = ci_job(small, CI_JOB_ID="5001", **gitlab)
        retry, _, _ = ci_job(small, CI_JOB_ID="5002", **gitlab)
        other, key2, _ = ci_job('{"duration": 3.0}', CI_JOB_ID="5002", **gitlab)
        T.check(first and first == retry and other != first and key1 != key2 and
                key1.startswith("ci-gitlab-812-shear_sweep_1_2-two_spheres_shear-"),
                "GitLab retry: jobs %s %s, other inputs %s (keys %s, %s)"
                % (first, retry, other, key1, key2))
        github = {"GITHUB_RUN_ID": "77", "GITHUB_JOB": "sweep"}
        first, _, _ = ci_job(small, **github)
        retry, _, _ = ci_job(small, **github)
        T.check(first and first == retry, "GitHub retry: jobs %s %s" % (first, retry))
        _, key, out = ci_job(small)
        T.check(key and key.startswith("ci-random-") and
                "warning: neither LUBDEM_IDEMPOTENCY_KEY nor a CI" in out,
                "no CI step: a random key and a warning (%s):\n%s" % (key, out))
        # the token revoked while ci_submit.sh polls: exit 1 with an error line naming the 401
        # (until 2026-12-07 curl's exit 22, through set -e, with curl's words only)
        blocker = block()
        tok2 = srv.token("ci2")
        env2 = dict(os.environ, LUBDEM_URL="http://127.0.0.1:%d" % srv.port, LUBDEM_TOKEN=tok2,
                    LUBDEM_IDEMPOTENCY_KEY="ci-revoked")
        proc = subprocess.Popen(["bash", ci, "two_spheres_shear", inputs, "300", h5], env=env2,
                                cwd=out_dir, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                text=True)
        first_line = proc.stdout.readline()
        job = re.search(r"job ([0-9a-f]{32}) submitted", first_line)
        srv.cli("token", "revoke", tok2)
        try:
            rest, _ = proc.communicate(timeout=120)
        except subprocess.TimeoutExpired:
            proc.kill()
            rest, _ = proc.communicate()
        out = first_line + rest
        T.check(job and proc.returncode == 1 and
                re.search(r"^error: GET \S+/jobs/%s: HTTP 401: " % job.group(1), out, re.M),
                "ci_submit.sh, token revoked while polling (exit %s):\n%s"
                % (proc.returncode, out))
        root = srv.token("root", admin=True)
        if job:
            srv.request("DELETE", "/jobs/" + job.group(1), root)
        srv.request("DELETE", "/jobs/" + blocker, tok)
        # read_result.py: the build provenance from the group's attributes
        try:
            import h5py  # noqa: F401
            rc, out = sh(srv, tok, sys.executable, os.path.join(ce, "read_result.py"), h5)
            T.check(rc == 0 and re.search(r"^build: .*compiler=.*git_commit=.*version=", out,
                                          re.M) and "<HDF5 group" not in out,
                    "read_result.py build provenance:\n" + out)
        except ImportError:
            print("h5py not available: read_result.py not exercised")
    finally:
        srv.stop()

    # no service at the URL: ci_submit.sh exits 2 (nothing submitted) and flow_curve.py 2,
    # each with an error line (until 2026-12-07 ci_submit.sh exited with curl's 7 and
    # flow_curve.py with a Python traceback)
    with socket.socket() as free:
        free.bind(("127.0.0.1", 0))
        dead = Dead(free.getsockname()[1])
    rc, out = sh(dead, tok, "bash", ci, "two_spheres_shear", '{"duration": 2.0}', "60", "x.h5",
                 extra_env={"LUBDEM_IDEMPOTENCY_KEY": "ci-dead"})
    T.check(rc == 2 and re.search(r"^error: POST \S+/execution failed \(curl exit 7\): the "
                                  r"service cannot be reached", out, re.M),
            "ci_submit.sh, no service (exit %s):\n%s" % (rc, out))
    fc_dead = [sys.executable, os.path.join(ce, "flow_curve.py"), "--vary", "/Iv", "--values",
               "0.1,0.2", "--poll", "0.2"]
    for key in ([], ["--key", "dead"]):
        rc, out = sh(dead, tok, *fc_dead, *key)
        T.check(rc == 2 and "Traceback" not in out and
                re.search(r"^error: /Iv=0.1 not submitted: the service at \S+ cannot be reached",
                          out, re.M),
                "flow_curve.py %s, no service (exit %s):\n%s" % (key, rc, out))

    # flow_curve.py: a run stopped at the CPU time limit (1 s) with its checkpoint, then the
    # same command with --chain 2 and a deadline already passed: its first round of polls
    # submits the continuation, which is then past the deadline
    slow = T.Server(a, "client-retries-cpu", workers=1, extra=["--cpu-s", "1"]).fresh()
    tok = slow.token("ci")
    slow.start()
    try:
        fc = [sys.executable, os.path.join(ce, "flow_curve.py"), "--vary", "/Iv",
              "--values", "0.1", "--base",
              '{"control": "pressure", "n_particles": 300, "strain": 1000}', "--poll", "0.2",
              "--key", "fc-late"]
        rc, out = sh(slow, tok, *fc, "--timeout", "120")
        first = re.search(r"^queued /Iv=0.1 job ([0-9a-f]{32})$", out, re.M)
        T.check(rc == 1 and first and "CPU time limit" in out,
                "flow_curve.py, a run stopped at the CPU limit:\n" + out)
        csv_path = os.path.join(out_dir, "late.csv")
        rc, out = sh(slow, tok, *fc, "--timeout", "0", "--chain", "2", "--out", csv_path)
        with open(csv_path) if os.path.exists(csv_path) else open(os.devnull) as f:
            rows = list(csv.DictReader(f))
        T.check(rc == 1 and "Traceback" not in out and "timeout after 0 s" in out and
                ("found /Iv=0.1 job %s (failed)" % first.group(1)) in out and
                "queued" not in out and ("continued /Iv=0.1 job %s" % first.group(1)) in out and
                len(rows) == 1 and rows[0]["jobs"] == "2" and
                rows[0]["status"] in ("accepted", "running"),
                "flow_curve.py, a continuation past the deadline:\n%s\n%s" % (out, rows))
    finally:
        slow.stop()


T.main(run)
