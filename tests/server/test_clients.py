"""The client examples against a live server: the curl walk-through, the CI script (success
with sha256 check, a failing job -> exit 1, a rejected submission -> exit 2, a timeout ->
exit 3, a retried CI step -> same job, a run with warnings -> printed, exit 4 with
LUBDEM_FAIL_ON_WARNINGS=1), the Python client (exit 4 with --fail-on-warnings) + h5py
reader, and the flow_curve.py sweep (table and CSV, the same jobs on a second run, a rejected
value, a timeout, a failed job, the service gone while waiting, runs longer than the CPU
limit continued job after job with --chain, found again by a second run with the same
--key; with --prune only each chain's last job kept), and lubdem_client.py extend (a
completed run taken further with its own inputs; with --chain --prune)."""
import csv
import json
import os
import re
import shutil
import subprocess
import sys

import lubd_testlib as T


def run():
    a = T.args()
    ce = a.clients
    # CPU limit 20 s: the short jobs here take well under a second; the "failing" job is
    # a very long run that the limit kills.
    srv = T.Server(a, "clients", workers=2, extra=["--cpu-s", "20", "--grace-s", "1"]).fresh()
    tok = srv.token("ci")
    srv.start()
    out_dir = os.path.join(a.work, "clients-out")
    shutil.rmtree(out_dir, ignore_errors=True)
    os.makedirs(out_dir)
    env = dict(os.environ, LUBDEM_URL="http://127.0.0.1:%d" % srv.port, LUBDEM_TOKEN=tok,
               LUBDEM_OUT=out_dir, PATH="/usr/bin:/bin:" + os.environ.get("PATH", ""))

    def sh(*argv, timeout=300, extra_env=None):
        e = dict(env, **(extra_env or {}))
        r = subprocess.run(list(argv), env=e, capture_output=True, text=True, timeout=timeout,
                           cwd=out_dir)
        return r.returncode, r.stdout + r.stderr

    try:
        rc, out = sh("bash", os.path.join(ce, "walkthrough.sh"))
        T.check(rc == 0 and "sha256" in out and "OK" in out, "walkthrough.sh:\n" + out)

        ci = os.path.join(ce, "ci_submit.sh")
        h5 = os.path.join(out_dir, "ci.h5")
        rc, out = sh("bash", ci, "two_spheres_shear", '{"duration": 30.0}', "300", h5,
                     extra_env={"LUBDEM_IDEMPOTENCY_KEY": "ci-step-1"})
        T.check(rc == 0 and "verified" in out and "warning:" not in out,
                "ci_submit.sh success:\n" + out)
        job1 = out.split("job ", 1)[1].split()[0]
        # A run whose own validity checks fail (soft contacts at phi = 0.55: elastic number far
        # below 5e3): the warnings are printed, and LUBDEM_FAIL_ON_WARNINGS=1 turns them into
        # exit 4 after the verified download.
        soft = ('{"n_particles": 300, "phi": 0.55, "stiffness": 1e4, "strain": 0.3, '
                '"transient_strain": 0.1, "sample_strain": 0.01, "snapshots": 0}')
        rc, out = sh("bash", ci, "simple_shear", soft, "300", os.path.join(out_dir, "soft.h5"),
                     extra_env={"LUBDEM_IDEMPOTENCY_KEY": "ci-soft"})
        T.check(rc == 0 and "verified" in out and "warning: elastic number" in out,
                "ci_submit.sh warnings printed:\n" + out)
        rc, out = sh("bash", ci, "simple_shear", soft, "300", os.path.join(out_dir, "soft.h5"),
                     extra_env={"LUBDEM_IDEMPOTENCY_KEY": "ci-soft",
                                "LUBDEM_FAIL_ON_WARNINGS": "1"})
        T.check(rc == 4 and "verified" in out and "warning: elastic number" in out,
                "ci_submit.sh LUBDEM_FAIL_ON_WARNINGS=1:\n" + out)
        rc, out = sh("bash", ci, "two_spheres_shear", '{"duration": 30.0}', "300", h5,
                     extra_env={"LUBDEM_IDEMPOTENCY_KEY": "ci-step-1"})
        T.check(rc == 0 and ("job %s" % job1) in out, "retried CI step made a new job:\n" + out)
        rc, out = sh("bash", ci, "falling_sphere", '{"duration": "x"}', "60")
        T.check(rc == 2 and "/inputs/duration" in out, "rejected submission:\n" + out)
        rc, out = sh("bash", ci, "falling_sphere", '{"duration": 1e6}', "2")
        T.check(rc == 3 and "timeout" in out, "timeout:\n" + out)
        # A failing job: the CPU limit kills it (rc 1, message printed).
        slow = T.Server(a, "clients-fail", workers=1, extra=["--cpu-s", "1"]).fresh()
        tok2 = slow.token("ci")
        slow.start()
        try:
            slow_env = {"LUBDEM_URL": "http://127.0.0.1:%d" % slow.port, "LUBDEM_TOKEN": tok2}
            rc, out = sh("bash", ci, "falling_sphere", '{"duration": 1e6}', "120",
                         extra_env=slow_env)
            T.check(rc == 1 and "failed" in out and "CPU time limit" in out,
                    "failed job:\n" + out)
            # flow_curve.py: a timeout, then a failed job (both 1e3 strain, which the 1 s CPU
            # limit kills): exit 1 and the table lists the value with its status.
            long_run = '{"control": "pressure", "n_particles": 300, "strain": 1000}'
            rc, out = sh(sys.executable, os.path.join(ce, "flow_curve.py"), "--vary", "/Iv",
                         "--values", "0.1", "--base", long_run, "--timeout", "0",
                         extra_env=slow_env)
            T.check(rc == 1 and "timeout" in out, "flow_curve.py timeout:\n" + out)
            fc_fail = os.path.join(out_dir, "flow_curve_failed.csv")
            rc, out = sh(sys.executable, os.path.join(ce, "flow_curve.py"), "--vary", "/Iv",
                         "--values", "0.01", "--base", long_run, "--poll", "0.3",
                         "--timeout", "120", "--out", fc_fail, extra_env=slow_env)
            with open(fc_fail) as f:
                rows = list(csv.DictReader(f))
            T.check(rc == 1 and "CPU time limit" in out and len(rows) == 1 and
                    rows[0]["status"] == "failed" and rows[0]["mu"] == "",
                    "flow_curve.py failed job:\n%s\n%s" % (out, rows))
            # flow_curve.py --chain: runs longer than the CPU limit go on in continuation jobs
            # (continue_from) until complete; the table has each value's last job and how many
            # it took
            fc_chain = os.path.join(out_dir, "flow_curve_chain.csv")
            chained = ('{"control": "pressure", "n_particles": 300, "strain": %s, '
                       '"transient_strain": 0.5}' % ("2" if a.sanitized else "6"))
            chain_cmd = [sys.executable, os.path.join(ce, "flow_curve.py"), "--vary", "/Iv",
                         "--values", "0.1,1", "--base", chained, "--poll", "0.1",
                         "--timeout", "600", "--chain", "40", "--key", "fc-chain"]
            rc, out = sh(*chain_cmd, "--out", fc_chain, extra_env=slow_env)
            with open(fc_chain) as f:
                rows = list(csv.DictReader(f))
            T.check(rc == 0 and len(rows) == 2 and "continued" in out and
                    all(r["status"] == "successful" and int(r["jobs"]) > 1 and r["mu"]
                        for r in rows),
                    "flow_curve.py --chain:\n%s\n%s" % (out, rows))
            print("flow_curve_chain_jobs=%s" % ",".join(r["jobs"] for r in rows))
            # the same command again (a CI step retried) finds every job of both chains by
            # their idempotency keys (KEY:POINT, then KEY:POINT:k) and submits none: the same
            # table, and as many jobs on the service as before
            st, _, before = slow.request("GET", "/jobs?limit=1000", tok2)
            fc_again = os.path.join(out_dir, "flow_curve_chain_again.csv")
            rc2, out2 = sh(*chain_cmd, "--out", fc_again, extra_env=slow_env)
            st, _, after = slow.request("GET", "/jobs?limit=1000", tok2)
            T.check(rc2 == 0 and open(fc_again).read() == open(fc_chain).read() and
                    after["numberReturned"] == before["numberReturned"] and
                    out2.count("found the continuation of") == out.count("continued") and
                    "queued" not in out2 and "continued" not in out2,
                    "flow_curve.py --chain again with the same --key: the same jobs (%s -> %s "
                    "jobs)\n%s" % (before["numberReturned"], after["numberReturned"], out2))
            # lubdem_client.py extend: the Iv = 1 run, completed, taken 1 strain further with
            # its own inputs (read from its summary) in a chain of CPU-limited jobs; the
            # result is the engine's run asked for the longer strain
            done = rows[1]["job"]
            rc, out = sh(sys.executable, os.path.join(ce, "lubdem_client.py"), "extend", done,
                         '{"strain": %s}' % ("3" if a.sanitized else "7"), "--chain", "20",
                         "--poll", "0.1", "--timeout", "300", extra_env=slow_env)
            ext_jobs = re.findall(r"\b[0-9a-f]{32}\b", out)  # every job it submitted
            T.check(rc == 0 and ext_jobs, "lubdem_client.py extend exit %s:\n%s" % (rc, out))
            st, _, first = slow.request("GET", "/jobs/" + ext_jobs[0], tok2)
            st, _, res = slow.request("GET", "/jobs/%s/results" % ext_jobs[-1], tok2)
            ext = res.get("summary") or {}
            spec = dict(ext.get("spec") or {})
            ext_dir = os.path.join(out_dir, "extend_direct")
            shutil.rmtree(ext_dir, ignore_errors=True)
            with open(ext_dir + ".json", "w") as f:
                json.dump(spec, f)
            subprocess.run([a.engine, "run", ext_dir + ".json", "--out", ext_dir, "--quiet"],
                           check=True, timeout=600, stderr=subprocess.DEVNULL)
            with open(os.path.join(ext_dir, "summary.json")) as f:
                direct = json.load(f)
            T.check(first.get("continue_from") == done and
                    spec.get("Iv") == 1 and ext.get("resumed_from_step", 0) > 0 and
                    ext["results"] == direct["results"] and ext["steps"] == direct["steps"],
                    "lubdem_client.py extend: %d job(s), the longer run's results (mu %s / %s)"
                    "\n%s" % (len(ext_jobs), ext.get("results", {}).get("mu", {}).get("value"),
                               direct["results"]["mu"]["value"], out))
            print("extend_jobs=%d" % len(ext_jobs))
            # --prune: the same extension again under another key; the job it extends
            # (continue_from, not one the chain submitted) is kept, and so is the last job
            prune_cmd = [sys.executable, os.path.join(ce, "lubdem_client.py"), "extend", done,
                         '{"strain": %s}' % ("3" if a.sanitized else "7"), "--chain", "20",
                         "--prune", "--key", "ext-prune", "--poll", "0.1", "--timeout", "300"]
            rc, out = sh(*prune_cmd, extra_env=slow_env)
            pr_jobs = re.findall(r"\b[0-9a-f]{32}\b", out)
            codes = [slow.request("GET", "/jobs/" + j, tok2)[0] for j in pr_jobs]
            src_code = slow.request("GET", "/jobs/" + done, tok2)[0]
            st, _, res = slow.request("GET", "/jobs/%s/results" % pr_jobs[-1], tok2) \
                if pr_jobs else (0, None, {})
            pruned = res.get("summary") or {}
            T.check(rc == 0 and pr_jobs and codes[:-1] == [410] * (len(pr_jobs) - 1)
                    and codes[-1] == 200 and src_code == 200 and
                    pruned.get("results") == direct["results"],
                    "lubdem_client.py extend --prune: job codes %s, the extended job %s\n%s"
                    % (codes, src_code, out))
            # submit --chain --prune: the Iv = 1 run of the flow_curve chain above, each job
            # of the chain deleted once the job continuing it has ended, so only the last
            # one's files stay; the results are the unpruned chain's; the command run again
            # finds the kept job and submits nothing
            iv1 = dict(json.loads(chained), Iv=1)
            prune_cmd = [sys.executable, os.path.join(ce, "lubdem_client.py"), "submit",
                         "simple_shear", json.dumps(iv1), "--chain", "40", "--prune", "--key",
                         "sub-prune", "--poll", "0.1", "--timeout", "300"]
            rc, out = sh(*prune_cmd, extra_env=slow_env)
            pr_jobs = re.findall(r"\b[0-9a-f]{32}\b", out)
            codes = [slow.request("GET", "/jobs/" + j, tok2)[0] for j in pr_jobs]
            st, _, res = slow.request("GET", "/jobs/%s/results" % pr_jobs[-1], tok2) \
                if pr_jobs else (0, None, {})
            st, _, unpruned = slow.request("GET", "/jobs/%s/results" % rows[1]["job"], tok2)
            T.check(rc == 0 and len(pr_jobs) > 1 and
                    codes[:-1] == [410] * (len(pr_jobs) - 1) and codes[-1] == 200 and
                    (res.get("summary") or {}).get("results") ==
                    (unpruned.get("summary") or {}).get("results"),
                    "lubdem_client.py submit --chain --prune: job codes %s\n%s" % (codes, out))
            st, _, before = slow.request("GET", "/jobs?limit=1000", tok2)
            rc2, out2 = sh(*prune_cmd, extra_env=slow_env)
            st, _, after = slow.request("GET", "/jobs?limit=1000", tok2)
            T.check(rc2 == 0 and re.findall(r"\b[0-9a-f]{32}\b", out2) == pr_jobs and
                    after["numberReturned"] == before["numberReturned"],
                    "lubdem_client.py submit --prune again with the same --key:\n%s" % out2)
            print("submit_prune_jobs=%d" % len(pr_jobs))
            # flow_curve.py --prune: one value's chain keeps only its last job, with the
            # results of the unpruned chain above (the same run); run again, the same table
            prune_fc = [sys.executable, os.path.join(ce, "flow_curve.py"), "--vary", "/Iv",
                        "--values", "0.1", "--base", chained, "--poll", "0.1",
                        "--timeout", "600", "--chain", "40", "--key", "fc-prune", "--prune"]
            fc_pruned = os.path.join(out_dir, "flow_curve_pruned.csv")
            rc, out = sh(*prune_fc, "--out", fc_pruned, extra_env=slow_env)
            with open(fc_pruned) as f:
                prow = list(csv.DictReader(f))
            ids = re.findall(r"\b[0-9a-f]{32}\b", out)
            codes = {j: slow.request("GET", "/jobs/" + j, tok2)[0] for j in ids}
            kept = [j for j, c in codes.items() if c == 200]
            T.check(rc == 0 and len(prow) == 1 and int(prow[0]["jobs"]) > 1 and
                    kept == [prow[0]["job"]] and
                    all(c == 410 for j, c in codes.items() if j != prow[0]["job"]) and
                    prow[0]["mu"] == rows[0]["mu"] and prow[0]["phi"] == rows[0]["phi"],
                    "flow_curve.py --prune: kept %s of %d jobs, mu %s against %s\n%s"
                    % (kept, len(codes), prow[0]["mu"] if prow else None, rows[0]["mu"], out))
            fc_pruned2 = os.path.join(out_dir, "flow_curve_pruned_again.csv")
            st, _, before = slow.request("GET", "/jobs?limit=1000", tok2)
            rc2, out2 = sh(*prune_fc, "--out", fc_pruned2, extra_env=slow_env)
            st, _, after = slow.request("GET", "/jobs?limit=1000", tok2)
            T.check(rc2 == 0 and open(fc_pruned2).read() == open(fc_pruned).read() and
                    after["numberReturned"] == before["numberReturned"],
                    "flow_curve.py --prune again with the same --key:\n%s" % out2)
            rc, out = sh(sys.executable, os.path.join(ce, "flow_curve.py"), "--vary", "/Iv",
                         "--values", "1", "--prune", extra_env=slow_env)
            T.check(rc == 2 and "--chain" in out, "flow_curve.py --prune without --chain:\n" + out)
            print("flow_curve_prune_jobs=%s" % prow[0]["jobs"])
            # the service goes away while flow_curve.py waits: exit 1, the job named
            lost = subprocess.Popen(
                [sys.executable, os.path.join(ce, "flow_curve.py"), "--vary", "/Iv",
                 "--values", "1e-3", "--base", long_run, "--poll", "0.2"],
                env=dict(env, **slow_env), cwd=out_dir, stdout=subprocess.PIPE,
                stderr=subprocess.STDOUT, text=True)
            while not (lost.stdout.readline() or "queued").startswith("queued"):
                pass
            slow.stop()
            out = lost.communicate(timeout=60)[0]
            T.check(lost.returncode == 1 and "lost the service" in out,
                    "flow_curve.py with the service gone:\n%s" % out)
        finally:
            slow.stop()
        # flow_curve.py: a job whose result.h5 does not fit under --fsize-mb 1 (5000 samples,
        # about 1.3 MB) fails with exit 4, and the table still gets the values of its complete
        # run from the summary that comes with the failure
        full = T.Server(a, "clients-full", workers=1, extra=["--fsize-mb", "1"]).fresh()
        tok3 = full.token("ci")
        full.start()
        try:
            full_env = {"LUBDEM_URL": "http://127.0.0.1:%d" % full.port, "LUBDEM_TOKEN": tok3}
            fc_full = os.path.join(out_dir, "flow_curve_full.csv")
            many = ('{"n_particles": 250, "strain": 0.5, "transient_strain": 0.1, '
                    '"sample_strain": 0.0001, "snapshots": 0}')
            rc, out = sh(sys.executable, os.path.join(ce, "flow_curve.py"), "--vary", "/phi",
                         "--values", "0.45", "--base", many, "--poll", "0.3",
                         "--timeout", "600", "--out", fc_full, extra_env=full_env)
            with open(fc_full) as f:
                rows = list(csv.DictReader(f))
            T.check(rc == 1 and "File too large" in out and len(rows) == 1
                    and rows[0]["status"] == "failed" and float(rows[0]["eta_r"]) > 1
                    and float(rows[0]["eta_r_stderr"]) > 0,
                    "flow_curve.py, result.h5 lost:\n%s\n%s" % (out, rows))
            # ci_submit.sh: exit 1, and the failed run's summary kept as an artifact
            lost_h5 = os.path.join(out_dir, "lost.h5")
            rc, out = sh("bash", ci, "simple_shear", many.replace("}", ', "phi": 0.45}'), "600",
                         lost_h5, extra_env=full_env)
            kept = lost_h5 + ".failed.json"
            doc = json.load(open(kept)) if os.path.exists(kept) else {}
            summary = doc.get("summary") or {}
            T.check(rc == 1 and "File too large" in out and summary.get("exit_code") == 4
                    and summary["results"]["eta_r"]["value"] > 1 and not os.path.exists(lost_h5),
                    "ci_submit.sh, result.h5 lost:\n%s\n%s" % (out, doc))
        finally:
            full.stop()

        # flow_curve.py: a sweep of two tiny imposed-pressure runs, then the same command
        # again (same jobs) and a rejected value; the timeout and the failed job are above.
        py = sys.executable
        fc = os.path.join(ce, "flow_curve.py")
        fc_csv = os.path.join(out_dir, "flow_curve.csv")
        base = ('{"control": "pressure", "n_particles": 300, "strain": 0.6, '
                '"transient_strain": 0.2, "sample_strain": 0.01, "snapshots": 0}')
        sweep = [py, fc, "--vary", "/Iv", "--values", "0.1,0.01", "--also", "/phi=0.44,0.52",
                 "--base", base, "--key", "fc-test", "--poll", "0.3", "--out", fc_csv]
        rc, out = sh(*sweep)
        T.check(rc == 0 and "wrote" in out, "flow_curve.py sweep:\n" + out)
        with open(fc_csv) as f:
            rows = list(csv.DictReader(f))
        T.check([r["/Iv"] for r in rows] == ["0.1", "0.01"] and
                [r["/phi"] for r in rows] == ["0.44", "0.52"] and
                all(r["status"] == "successful" for r in rows), "flow_curve rows: %s" % rows)
        for r in rows:
            mu, err, ref = float(r["mu"]), float(r["mu_stderr"]), float(r["mu_ref"])
            T.check(0.2 < mu < 3 and 0 < err < mu and 0.5 < ref < 1.1 and
                    abs(float(r["Iv"]) - float(r["/Iv"])) < 0.2 * float(r["/Iv"]),
                    "flow_curve values: %s" % r)
        jobs_first = [ln.split()[-1] for ln in out.splitlines() if ln.startswith("queued")]
        rc, out = sh(*sweep)
        # found again, and said so (it printed "queued" for them until 2026-12-06)
        jobs_again = [ln.split()[3] for ln in out.splitlines() if ln.startswith("found")]
        T.check(rc == 0 and len(jobs_first) == 2 and jobs_again == jobs_first and
                "queued" not in out,
                "flow_curve.py again found other jobs: %s / %s\n%s" % (jobs_first, jobs_again,
                                                                       out))
        rc, out = sh(py, fc, "--vary", "/Iv", "--values", "0.1,-1", "--base", base,
                     "--key", "fc-test")
        T.check(rc == 2 and "/inputs/Iv" in out and "keep running" in out,
                "flow_curve.py rejected value:\n" + out)
        rc, out = sh(py, fc, "--vary", "Iv", "--values", "0.1")
        T.check(rc == 2 and "JSON pointer" in out, "flow_curve.py bad pointer:\n" + out)
        rc, out = sh(py, fc, "--vary", "/Iv", "--values", "0.1", "--also", "/phi=0.4,0.5")
        T.check(rc == 2 and "--also /phi has 2 values" in out,
                "flow_curve.py --also length:\n" + out)

        client = os.path.join(ce, "lubdem_client.py")
        pyh5 = os.path.join(out_dir, "py.h5")
        rc, out = sh(py, client, "submit", "falling_sphere", '{"duration": 2.0}',
                     "--download", pyh5, "--timeout", "300")
        T.check(rc == 0 and "downloaded" in out and os.path.exists(pyh5),
                "python client:\n" + out)
        rc, out = sh(py, client, "submit", "simple_shear", soft, "--wait", "--timeout", "300",
                     "--fail-on-warnings")
        T.check(rc == 4 and "warning: elastic number" in out,
                "python client --fail-on-warnings:\n" + out)
        rc, out = sh(py, client, "list", "--status", "successful")
        T.check(rc == 0 and "falling_sphere successful" in out, "python list:\n" + out)
        rc, out = sh(py, client, "submit", "falling_sphere", '{"duration": -1}')
        T.check(rc == 1 and "/inputs/duration" in out, "python client error:\n" + out)
        # Resume: truncate the file and download again with a Range request.
        sys.path.insert(0, ce)
        import lubdem_client
        c = lubdem_client.Client(env["LUBDEM_URL"], tok)
        job = c.jobs("successful", limit=1)[0]
        full = c.download(job["jobID"], "result.h5", os.path.join(out_dir, "resume.h5"))
        size = os.path.getsize(full)
        with open(full, "r+b") as f:
            f.truncate(size // 3)
        c.download(job["jobID"], "result.h5", full)
        T.check(os.path.getsize(full) == size, "resumed download size")
        try:
            import h5py  # noqa: F401
            rc, out = sh(py, os.path.join(ce, "read_result.py"), pyh5)
            T.check(rc == 0 and "H5MD version: [1, 1]" in out, "read_result.py:\n" + out)
        except ImportError:
            print("h5py not available: read_result.py not exercised")
    finally:
        srv.stop()


T.main(run)
