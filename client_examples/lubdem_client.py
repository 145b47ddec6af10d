#!/usr/bin/env python3
"""lubdem_client.py - a small client for the lubdem service (Python standard library only).

    from lubdem_client import Client
    c = Client("http://127.0.0.1:8080", token)
    job = c.submit("falling_sphere", {"duration": 2.0}, idempotency_key="my-run-1")
    job = c.wait(job["jobID"], timeout=600)          # raises JobFailed unless successful
    res = c.results(job["jobID"])                    # summary inline + files
    summary = c.summary(job["jobID"])                # also of a failed job, where there is one
    c.download(job["jobID"], "result.h5", "out.h5")  # resumable, sha256-checked
    c.outputs(job["jobID"])                          # the files, also of a failed job
    c.extend(job_id, {"strain": 60})                 # continue a completed run, longer

Command line:
    lubdem_client.py [--url URL] [--token T] submit PROCESS '{"duration": 2}' [--wait]
                     [--download FILE] [--timeout S] [--key KEY] [--fail-on-warnings]
                     [--continue-from JOB]   (continue that ended job's run: same inputs)
                     [--chain N]   (while a job stops at the CPU limit, continue it: N jobs at most)
                     [--prune]     (with --chain: delete each job of the chain once the job
                                    continuing it has ended; the last one's files hold all)
    lubdem_client.py extend JOB '{"strain": 60}' [the options of submit]   continue an ended
                     job's run with its own inputs (its summary's spec), these changed
    lubdem_client.py status JOB | results JOB | list [--status S] | dismiss JOB | log JOB
    lubdem_client.py download JOB [DIR]   every file of an ended job into DIR (default: JOB);
                     a failed job's too (its partial result.h5, the checkpoint of a run
                     stopped at its CPU limit), then exit 1 with the job's message
Token: --token, $LUBDEM_TOKEN, or ./run/local-token.
submit --wait/--download prints the run's warnings (its summary's own validity checks) as
'warning: ...' lines on stderr; with --fail-on-warnings it then exits 4.
"""
import argparse
import hashlib
import json
import os
import sys
import time
import urllib.error
import urllib.request


ENDED = ("successful", "failed", "dismissed")  # job states that do not change any more


def default_token(token):
    """token, or else the contents of ./run/local-token (the --init-defaults admin token)."""
    if not token and os.path.exists("run/local-token"):
        with open("run/local-token") as f:
            token = f.read().strip()
    return token


class ApiError(Exception):
    """An HTTP error with the service's problem+json body."""

    def __init__(self, status, problem):
        self.status = status
        self.problem = problem
        ptr = ""
        if isinstance(problem, dict) and problem.get("errors"):
            ptr = " at " + problem["errors"][0].get("pointer", "")
        detail = problem.get("detail") if isinstance(problem, dict) else problem
        super().__init__("HTTP %d%s: %s" % (status, ptr, detail))


class JobFailed(Exception):
    pass


class NotEnded(Exception):
    """The job has not ended (queued or running): it cannot be continued or downloaded yet."""


class Client:
    def __init__(self, url="http://127.0.0.1:8080", token=None, timeout=30):
        self.url = url.rstrip("/")
        self.token = token
        self.timeout = timeout

    def _req(self, method, path, body=None, headers=None, raw=False):
        h = {"Authorization": "Bearer " + self.token} if self.token else {}
        h.update(headers or {})
        data = None
        if body is not None:
            data = json.dumps(body).encode()
            h["Content-Type"] = "application/json"
        req = urllib.request.Request(self.url + path, data=data, headers=h, method=method)
        try:
            with urllib.request.urlopen(req, timeout=self.timeout) as r:
                payload = r.read()
                return (r, payload) if raw else json.loads(payload or b"null")
        except urllib.error.HTTPError as e:
            payload = e.read()
            try:
                problem = json.loads(payload)
            except ValueError:
                problem = payload.decode(errors="replace")
            raise ApiError(e.code, problem) from None

    def processes(self):
        return self._req("GET", "/processes")["processes"]

    def submit(self, process, inputs, idempotency_key=None, priority=None, retries=3,
               continue_from=None):
        """Queues a job; with continue_from (a jobID), one that continues that ended job's run
        from its checkpoint (same inputs; simple_shear may change /strain, /target_rel_error,
        /target_min_strain, /pair_network, resuspension /strain, /pair_network). Returns the
        job's status document, with "replayed": True when the service answered with the job an
        earlier request under the same idempotency_key made (nothing new queued)."""
        body = {"inputs": inputs}
        if priority is not None:
            body["priority"] = priority
        if continue_from:
            body["continue_from"] = continue_from
        headers = {"Prefer": "respond-async"}
        if idempotency_key:
            headers["Idempotency-Key"] = idempotency_key
        for attempt in range(retries + 1):
            try:
                r, payload = self._req("POST", "/processes/%s/execution" % process, body,
                                       headers, raw=True)
                doc = json.loads(payload)
                doc["replayed"] = r.headers.get("Idempotent-Replayed") == "true"
                return doc
            except ApiError as e:
                if e.status == 429 and attempt < retries:
                    time.sleep(5)
                    continue
                raise
            except OSError:
                # Network trouble: retrying is safe only with an idempotency key.
                if not idempotency_key or attempt == retries:
                    raise
                time.sleep(1)

    def ended(self, job_id):
        """What the service gives of a job that has ended: the results document of a
        successful job, or the problem of a failed one, with its "summary" and "outputs"
        where the engine wrote any. Raises ApiError otherwise (not ended: 404, dismissed:
        410)."""
        try:
            return self.results(job_id)
        except ApiError as e:
            if isinstance(e.problem, dict) and e.status in (422, 500):
                return e.problem
            raise

    def stopped_with_checkpoint(self, job_id):
        """True when the job failed because its run was stopped and kept the checkpoint a
        continuation goes on from: stopped at the service's CPU time limit (its summary's
        status "partial"), or killed (SIGKILL: the OOM killer, an operator) on its last
        attempt before its engine wrote a summary, with a periodic checkpoint kept."""
        doc = self.ended(job_id)
        summary = doc.get("summary")
        return (doc.get("status") in (422, 500) and
                (summary is None or summary.get("status") == "partial") and
                "checkpoint.h5" in (doc.get("outputs") or {}))

    def inputs_of(self, job_id):
        """The inputs an ended job ran with: the spec its summary states (defaults included),
        without "scene", or, where the engine wrote no summary (it was killed), the inputs the
        job was submitted with. What a continuation of it submits (the service compares them
        with the job's own, defaults included). Raises NotEnded for a job that has not ended."""
        job = self.status(job_id)
        if job["status"] not in ENDED:
            raise NotEnded("job %s is %s: a job can be continued once it has ended (successful, "
                           "or failed with a checkpoint); wait for it (lubdem_client.py status "
                           "%s)" % (job_id, job["status"], job_id))
        doc = self.ended(job_id)
        spec = (doc.get("summary") or {}).get("spec")
        if not isinstance(spec, dict):
            spec = doc.get("inputs")
        if not isinstance(spec, dict):
            raise KeyError("job %s has no summary stating its spec, and the service did not "
                           "give its inputs" % job_id)
        return {k: v for k, v in spec.items() if k != "scene"}

    def extension_of(self, job_id, changes=None):
        """(process, inputs) of a job that continues ended job job_id's run with the job's own
        inputs, `changes` applied."""
        return (self.status(job_id)["processID"],
                dict(self.inputs_of(job_id), **(changes or {})))

    def extend(self, job_id, changes=None, idempotency_key=None):
        """Submits a job that continues ended job job_id's run with the job's own inputs, some
        of them changed: {"strain": 60} extends a completed simple_shear or resuspension run
        (which kept its checkpoint), {} continues a run stopped at the CPU time limit. Returns
        the new job's status document."""
        process, inputs = self.extension_of(job_id, changes)
        return self.submit(process, inputs, idempotency_key=idempotency_key,
                           continue_from=job_id)

    def run_chain(self, process, inputs, max_jobs=100, timeout=600, idempotency_key=None,
                  continue_from=None, on_job=None, poll=1.0, prune=False):
        """Runs `inputs` to the end on a service whose CPU time limit is shorter than the run:
        submits a job and, while it ends stopped with a checkpoint, a job that continues it
        (continue_from), at most max_jobs in all. Returns the last job's status document
        (successful, or failed for another reason, or the last stopped one). on_job(doc) is
        called with each submitted job; with idempotency_key, job k uses key-k (a retried
        chain finds its jobs again). timeout: per job; poll: seconds between status requests.
        prune: each job's result.h5 holds every row of the jobs before it, so once a job
        has ended successful or stopped with a checkpoint, the job it continued is deleted
        (only jobs this chain submitted, never `continue_from`'s; the last one is kept, as is
        every job before one that failed otherwise). A retried chain with idempotency_key
        skips the jobs it deleted: their continuations are found again by their keys."""
        job = None
        prunable = None  # the job the current one continues, when this chain submitted it
        for k in range(max_jobs):
            key = "%s-%d" % (idempotency_key, k) if idempotency_key else None
            job = self.submit(process, inputs, idempotency_key=key, continue_from=continue_from)
            if on_job:
                on_job(job)
            try:
                job = self.wait(job["jobID"], timeout=timeout, poll=poll)
            except JobFailed:
                job = self.status(job["jobID"])
            except ApiError as e:
                if not (e.status == 410 and prune and key and k + 1 < max_jobs):
                    raise
                # deleted by this chain's earlier run: its continuation has the next key
                continue_from, prunable = job["jobID"], None
                continue
            stopped = job["status"] == "failed" and self.stopped_with_checkpoint(job["jobID"])
            if prune and prunable and (stopped or job["status"] == "successful"):
                self.dismiss_if_present(prunable)
            if not stopped:
                return job
            continue_from = prunable = job["jobID"]
        return job

    def dismiss_if_present(self, job_id):
        """Deletes a job (DELETE); a job already deleted (410) is not an error. Deleting a job
        that a queued or running continuation needs takes nothing from the continuation (the
        service hands the checkpoint over)."""
        try:
            self.dismiss(job_id)
        except ApiError as e:
            if e.status != 410:
                raise

    def status(self, job_id):
        return self._req("GET", "/jobs/" + job_id)

    def wait(self, job_id, timeout=600, poll=1.0):
        deadline = time.time() + timeout
        while True:
            job = self.status(job_id)
            if job["status"] == "successful":
                return job
            if job["status"] in ENDED:
                raise JobFailed("job %s %s: %s" % (job_id, job["status"], job.get("message")))
            if time.time() > deadline:
                raise TimeoutError("job %s still %s after %s s" % (job_id, job["status"], timeout))
            time.sleep(poll)

    def results(self, job_id):
        return self._req("GET", "/jobs/%s/results" % job_id)

    def summary(self, job_id):
        """The engine's summary.json of a job that has ended: of a successful job, or of the
        last attempt of a failed one where the engine wrote one (its diagnostic; for exit code
        4, result.h5 could not be written and the results are those of the whole run); None
        when there is none."""
        return self.ended(job_id).get("summary")

    def outputs(self, job_id):
        """The files of a job that has ended ({name: {href, type, size, sha256}}): of a
        successful job, or what the engine of a failed one wrote and the service kept (its
        summary, a partial or failed result.h5, a stopped run's checkpoint.h5); {} when
        there are none."""
        return self.ended(job_id).get("outputs") or {}

    def warnings(self, job_id):
        """The warnings of a successful job's summary (its advisory validity checks)."""
        summary = self.results(job_id).get("summary") or {}
        return list(summary.get("warnings") or [])

    def jobs(self, status=None, limit=100):
        path = "/jobs?limit=%d" % limit + ("&status=%s" % status if status else "")
        return self._req("GET", path)["jobs"]

    def dismiss(self, job_id):
        return self._req("DELETE", "/jobs/" + job_id)

    def log(self, job_id):
        return self._req("GET", "/jobs/%s/log" % job_id, raw=True)[1].decode(errors="replace")

    def download(self, job_id, name, path, chunk=1 << 20):
        """Streams an output to `path`, resuming a partial file with a Range request, and
        checks size and sha256 against the results document."""
        outputs = self.outputs(job_id)
        if name not in outputs:
            raise KeyError("job %s has no output %r (it has: %s)"
                           % (job_id, name, ", ".join(sorted(outputs)) or "none"))
        want = outputs[name]
        have = os.path.getsize(path) if os.path.exists(path) else 0
        if have > want["size"]:
            have = 0
        if have < want["size"]:
            headers = {"Authorization": "Bearer " + self.token}
            if have:
                headers["Range"] = "bytes=%d-" % have
            req = urllib.request.Request("%s/jobs/%s/results/%s" % (self.url, job_id, name),
                                         headers=headers)
            with urllib.request.urlopen(req, timeout=self.timeout) as r:
                mode = "ab" if r.status == 206 else "wb"
                with open(path, mode) as f:
                    while True:
                        block = r.read(chunk)
                        if not block:
                            break
                        f.write(block)
        h = hashlib.sha256()
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(chunk), b""):
                h.update(block)
        if h.hexdigest() != want["sha256"]:
            if have:  # the partial file was not a prefix of this output: start over
                os.unlink(path)
                return self.download(job_id, name, path, chunk)
            raise IOError("sha256 mismatch for %s" % path)
        return path


def download_all(c, job_id, directory):
    """Downloads every file of an ended job into `directory`. 0 for a successful job, 1 for a
    failed one (its files are downloaded first), 1 for a job that has not ended."""
    job = c.status(job_id)
    if job["status"] not in ENDED:
        print("error: job %s is %s; its files come when it has ended" % (job_id, job["status"]),
              file=sys.stderr)
        return 1
    os.makedirs(directory, exist_ok=True)
    outputs = c.outputs(job_id)
    for name in sorted(outputs):
        print(c.download(job_id, name, os.path.join(directory, name)))
    if job["status"] == "successful":
        return 0
    print("error: job %s %s: %s" % (job_id, job["status"], job.get("message", "")),
          file=sys.stderr)
    if "checkpoint.h5" in outputs:
        print("the run stopped with a checkpoint: continue it in the service (submit %s INPUTS "
              "--continue-from %s) or here (lubdem run SPEC --out %s --resume, SPEC being the "
              "job's inputs with \"scene\": \"%s\")"
              % (job.get("processID", ""), job_id, directory, job.get("processID", "")),
              file=sys.stderr)
    return 1


def add_run_options(parser):
    """What submit and extend share: waiting, downloading, the key, the chain."""
    parser.add_argument("--wait", action="store_true")
    parser.add_argument("--download")
    parser.add_argument("--timeout", type=float, default=600)
    parser.add_argument("--poll", type=float, default=1.0,
                        help="seconds between status requests")
    parser.add_argument("--key")
    parser.add_argument("--fail-on-warnings", action="store_true")
    parser.add_argument("--chain", type=int, metavar="N", default=0,
                        help="with --wait: while a job stops at the service's CPU time limit "
                             "with a checkpoint, submit one that continues it (at most N jobs "
                             "in all)")
    parser.add_argument("--prune", action="store_true",
                        help="with --chain: delete each job of the chain once the job that "
                             "continues it has ended successful or stopped with a checkpoint "
                             "(its result.h5 holds every row of the earlier ones)")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--url", default=os.environ.get("LUBDEM_URL", "http://127.0.0.1:8080"))
    p.add_argument("--token", default=os.environ.get("LUBDEM_TOKEN"))
    sub = p.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("submit")
    s.add_argument("process")
    s.add_argument("inputs", nargs="?", default="{}")
    s.add_argument("--continue-from", metavar="JOB",
                   help="continue that ended job's run from its checkpoint")
    add_run_options(s)
    x = sub.add_parser("extend", help="continue an ended job's run with its own inputs, "
                                      "CHANGES applied (e.g. '{\"strain\": 60}')")
    x.add_argument("job")
    x.add_argument("changes", nargs="?", default="{}")
    add_run_options(x)
    for name in ("status", "results", "dismiss", "log"):
        sub.add_parser(name).add_argument("job")
    d = sub.add_parser("download")
    d.add_argument("job")
    d.add_argument("dir", nargs="?")
    lst = sub.add_parser("list")
    lst.add_argument("--status")
    a = p.parse_args(argv)
    c = Client(a.url, default_token(a.token))
    if getattr(a, "prune", False) and not a.chain:
        print("error: --prune deletes the earlier jobs of a chain: it needs --chain N",
              file=sys.stderr)
        return 2
    try:
        if a.cmd in ("submit", "extend"):
            if a.cmd == "extend":  # the job's own inputs, changed, continuing it
                process, inputs = c.extension_of(a.job, json.loads(a.changes))
                continue_from = a.job
            else:
                process, inputs, continue_from = a.process, json.loads(a.inputs), a.continue_from
            if a.chain:
                job = c.run_chain(process, inputs, max_jobs=a.chain, timeout=a.timeout,
                                  idempotency_key=a.key, continue_from=continue_from,
                                  poll=a.poll, on_job=lambda j: print(j["jobID"], flush=True),
                                  prune=a.prune)
            else:
                job = c.submit(process, inputs, idempotency_key=a.key,
                               continue_from=continue_from)
                print(job["jobID"])
            if a.wait or a.download or a.chain:
                c.wait(job["jobID"], timeout=a.timeout, poll=a.poll)
                if a.download:
                    c.download(job["jobID"], "result.h5", a.download)
                    print("downloaded", a.download)
                warnings = c.warnings(job["jobID"])
                for w in warnings:
                    print("warning:", w, file=sys.stderr)
                if warnings and a.fail_on_warnings:
                    return 4
        elif a.cmd == "status":
            print(json.dumps(c.status(a.job), indent=1))
        elif a.cmd == "results":
            print(json.dumps(c.results(a.job), indent=1))
        elif a.cmd == "dismiss":
            print(json.dumps(c.dismiss(a.job), indent=1))
        elif a.cmd == "log":
            sys.stdout.write(c.log(a.job))
        elif a.cmd == "download":
            return download_all(c, a.job, a.dir or a.job)
        elif a.cmd == "list":
            for j in c.jobs(a.status):
                print(j["jobID"], j["processID"], j["status"], j.get("progress", 0))
    except KeyError as e:  # str() of a KeyError quotes its message
        print("error:", e.args[0] if e.args else e, file=sys.stderr)
        return 1
    except (ApiError, JobFailed, NotEnded, TimeoutError, IOError) as e:
        print("error:", e, file=sys.stderr)
        return 1
    except ValueError as e:  # INPUTS or CHANGES that are not JSON
        print("error: not JSON:", e, file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
