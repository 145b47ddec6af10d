#!/usr/bin/env python3
"""flow_curve.py - a parameter sweep through the lubdem service: one job per value, all queued
at once, then one table of the steady-state means with their standard errors (Python standard
library only; uses lubdem_client.py from this directory).

    flow_curve.py --vary /Iv --values 1e-3,1e-2,0.1,1 \\
        --base '{"control": "pressure", "n_particles": 500, "target_rel_error": 0.02}' \\
        --key my-flow-curve --out flow_curve.csv

    --url URL        the service                       [$LUBDEM_URL, http://127.0.0.1:8080]
    --vary POINTER   JSON pointer of the swept input (/Iv, /phi, /law/mu, ...)
    --values LIST    comma-separated JSON values (numbers, or strings in double quotes;
                     write --values=-1,2 when the list starts with a minus sign)
    --also POINTER=LIST  one more input set per value, in step with --values (repeatable):
                     e.g. the initial phi of each imposed-pressure run, --also /phi=0.3,0.44
    --base JSON      the other inputs, as JSON text or @file             [{}]
    --process ID     the process                                         [simple_shear]
    --observables L  summary results to tabulate, comma-separated   [phi,mu,eta_r,Iv,...]
    --key PREFIX     idempotency key prefix: running the same command again (after a crash,
                     in a retried CI step) finds the same jobs instead of queueing new ones
                     (printed as "found POINT job ID (status)", new ones as "queued ...")
    --timeout S      give up waiting after S seconds in all                  [3600]
    --poll S         seconds between status requests                            [2]
    --out CSV        also write the table as CSV (one row per value, written even when some
                     jobs failed; value, stderr and the seed's reference value `ref` when the
                     summary gives one; a failed job's values where its run completed but could
                     not write its result.h5, exit code 4)
    --fail-on-warnings  exit 4 when any run reports warnings (its own validity checks)
    --chain N        on a service whose CPU time limit (lubdemd --cpu-s) is shorter than the
                     runs: a job that stops at the limit with a checkpoint is continued by a
                     new job ("continue_from"), up to N jobs per value; the table gives the
                     last job of each value and how many it took (column `jobs`)   [1: off]
    --prune          with --chain: delete each job of a chain once the job that continues it
                     has ended successful or stopped with a checkpoint (its result.h5 holds
                     every row of the earlier ones), so a chain of n jobs keeps one run's
                     files, not n; with --key, the command run again skips the deleted jobs

Exit status: 0 all runs successful; 1 a job failed or the wait timed out (the table still
lists every value, with its status), or the service went away while waiting (the jobs are
named, or found again by the same command with --key); 2 bad arguments, or a submission was
rejected (the message names the input by its JSON pointer) or could not reach the service (an
'error:' line; until 2026-12-07 a Python traceback): the values after it are not submitted, the
jobs already queued keep running and are named; 4 warnings with --fail-on-warnings.
Token: --token, $LUBDEM_TOKEN, or ./run/local-token.
"""
import argparse
import csv
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lubdem_client import ENDED, ApiError, Client, default_token  # noqa: E402

DEFAULT_OBSERVABLES = ("phi,mu,eta_r,Iv,pressure,Z_contact,sigma11_over_sigma22,"
                       "sigma33_over_sigma22,elastic_number")


def pointer_tokens(pointer):
    """RFC 6901 tokens of a JSON pointer; ValueError unless it names a member ("/a/b")."""
    if not pointer.startswith("/") or pointer == "/":
        raise ValueError("a swept input must be a JSON pointer such as /Iv or /law/mu, not %r"
                         % pointer)
    return [t.replace("~1", "/").replace("~0", "~") for t in pointer[1:].split("/")]


def with_value(base, tokens, value):
    """A deep copy of `base` with the member at `tokens` set to `value` (objects created as
    needed; an existing non-object on the way is an error)."""
    inputs = json.loads(json.dumps(base))
    node = inputs
    for t in tokens[:-1]:
        child = node.setdefault(t, {})
        if not isinstance(child, dict):
            raise ValueError("a swept input goes through /%s, which is not an object in --base"
                             % t)
        node = child
    node[tokens[-1]] = value
    return inputs


def parse_values(text, what="--values"):
    values = []
    for item in text.split(","):
        item = item.strip()
        try:
            values.append(json.loads(item))
        except ValueError:
            raise ValueError("%s: %r is not a JSON value" % (what, item)) from None
    return values


def parse_sweep(vary, values_text, also):
    """[(pointer, tokens, values)]: --vary first, then each --also, all of one length."""
    sweep = [(vary, pointer_tokens(vary), parse_values(values_text))]
    for item in also:
        pointer, sep, text = item.partition("=")
        if not sep:
            raise ValueError("--also must be POINTER=LIST, not %r" % item)
        sweep.append((pointer, pointer_tokens(pointer), parse_values(text, "--also " + pointer)))
        if len(sweep[-1][2]) != len(sweep[0][2]):
            raise ValueError("--also %s has %d values, --values has %d" % (
                pointer, len(sweep[-1][2]), len(sweep[0][2])))
    return sweep


def collect(client, job, observables):
    """status, message, {name: (value, stderr, ref)}, steady flag and warnings of one job, from
    its last status document `job` (and its summary: of a successful job, or of a failed one
    whose run completed but could not write its result.h5, exit code 4)."""
    job_id = job["jobID"]
    row = {"status": job["status"], "message": job.get("message", ""), "obs": {},
           "steady": None, "warnings": []}
    if job["status"] not in ("successful", "failed"):
        return row
    summary = client.summary(job_id) or {}
    if job["status"] == "failed" and summary.get("exit_code") != 4:
        return row
    results = summary.get("results") or {}
    for name in observables:
        r = results.get(name)
        if isinstance(r, dict):
            row["obs"][name] = (r.get("value"), r.get("stderr"), r.get("ref"))
    row["steady"] = summary.get("steady_state_detected")
    row["warnings"] = list(summary.get("warnings") or [])
    return row


def wait_all(client, chains, deadline, poll=2.0, cont=None, prune=False):
    """Polls the last job of each value's chain (its job ids, the first one first) until every
    one has ended or the deadline passes; returns the last status document of each, in order,
    and the ids still open. With cont(i, doc), called for value i's job that ended stopped
    with a checkpoint, a continuation may be appended to chains[i] (which is then polled).
    With prune, a job of a chain is deleted once the job continuing it has ended successful or
    stopped with a checkpoint, and a chain's job found deleted (410: this command's earlier
    run pruned it) is passed to cont, whose continuation its key finds again."""
    last = {}
    pruned = set()
    while True:
        for i, chain in enumerate(chains):
            if chain[-1] in last and last[chain[-1]]["status"] in ENDED:
                continue
            try:
                doc = client.status(chain[-1])
            except ApiError as e:
                if not (e.status == 410 and prune and cont):
                    raise
                pruned.add(chain[-1])
                cont(i, {"jobID": chain[-1]})
                if chain[-1] in pruned:  # no continuation (the chain is as long as allowed)
                    raise
                continue
            last[chain[-1]] = doc
            stopped = (doc["status"] == "failed" and
                       client.stopped_with_checkpoint(doc["jobID"]))
            if (prune and len(chain) > 1 and chain[-2] not in pruned and
                    (stopped or doc["status"] == "successful")):
                client.dismiss_if_present(chain[-2])
                pruned.add(chain[-2])
            if cont and stopped:
                cont(i, doc)
        open_ids = [c[-1] for c in chains if c[-1] not in last or last[c[-1]]["status"] not in ENDED]
        if not open_ids or time.time() > deadline:
            break
        time.sleep(poll)
    # a continuation submitted in the last round before the deadline has not been polled yet
    # (it used to be a KeyError here instead of the timeout's table)
    for c in chains:
        if c[-1] not in last:
            last[c[-1]] = client.status(c[-1])
    return [last[c[-1]] for c in chains], open_ids


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--url", default=os.environ.get("LUBDEM_URL", "http://127.0.0.1:8080"))
    p.add_argument("--token", default=os.environ.get("LUBDEM_TOKEN"))
    p.add_argument("--process", default="simple_shear")
    p.add_argument("--vary", required=True)
    p.add_argument("--values", required=True)
    p.add_argument("--also", action="append", default=[])
    p.add_argument("--base", default="{}")
    p.add_argument("--observables", default=DEFAULT_OBSERVABLES)
    p.add_argument("--key")
    p.add_argument("--timeout", type=float, default=3600)
    p.add_argument("--poll", type=float, default=2.0)
    p.add_argument("--out")
    p.add_argument("--fail-on-warnings", action="store_true")
    p.add_argument("--chain", type=int, default=1)
    p.add_argument("--prune", action="store_true")
    a = p.parse_args(argv)
    if a.prune and a.chain < 2:
        print("error: --prune deletes the earlier jobs of each value's chain: it needs "
              "--chain N (N > 1)", file=sys.stderr)
        return 2
    try:
        sweep = parse_sweep(a.vary, a.values, a.also)
        values = sweep[0][2]
        base_text = open(a.base[1:]).read() if a.base.startswith("@") else a.base
        base = json.loads(base_text)
        if not isinstance(base, dict):
            raise ValueError("--base must be a JSON object")
        bodies = []
        for i in range(len(values)):
            body = base
            for _, tokens, vals in sweep:
                body = with_value(body, tokens, vals[i])
            bodies.append(body)
    except (ValueError, OSError) as e:
        print("error:", e, file=sys.stderr)
        return 2
    observables = [o.strip() for o in a.observables.split(",") if o.strip()]
    client = Client(a.url, default_token(a.token))

    job_ids = []
    points = [",".join("%s=%s" % (ptr, json.dumps(vals[i])) for ptr, _, vals in sweep)
              for i in range(len(values))]
    for point, body in zip(points, bodies):
        key = "%s:%s" % (a.key, point) if a.key else None
        try:
            job = client.submit(a.process, body, idempotency_key=key)
        except (ApiError, OSError) as e:  # OSError: urllib's URLError, a connection refused
            if isinstance(e, ApiError):
                print("error: %s rejected: %s" % (point, e), file=sys.stderr)
            else:
                print("error: %s not submitted: the service at %s cannot be reached (%s)" % (
                    point, a.url, getattr(e, "reason", e)), file=sys.stderr)
            if job_ids:
                print("the %d job(s) queued before it keep running (%s); %s" % (
                    len(job_ids), " ".join(job_ids),
                    "the same command with the same --key finds them again" if a.key else
                    "dismiss them with lubdem_client.py dismiss JOB, or pass --key next time"),
                    file=sys.stderr)
            return 2
        job_ids.append(job["jobID"])
        if job.get("replayed"):  # found by its --key: queued by an earlier run of the command
            print("found %s job %s (%s)" % (point, job["jobID"], job["status"]), flush=True)
        else:
            print("queued %s job %s" % (point, job["jobID"]), flush=True)

    chains = [[j] for j in job_ids]  # every job of each value, the first one first

    def cont(i, doc):
        """Value i's job stopped at the CPU time limit: a job that continues it, while the
        chain is shorter than --chain."""
        if len(chains[i]) >= a.chain:
            return
        key = "%s:%s:%d" % (a.key, points[i], len(chains[i])) if a.key else None
        job = client.submit(a.process, bodies[i], idempotency_key=key,
                            continue_from=doc["jobID"])
        chains[i].append(job["jobID"])
        print("%s %s job %s as job %s" % ("found the continuation of" if job.get("replayed")
                                          else "continued", points[i], doc["jobID"],
                                          job["jobID"]), flush=True)

    try:
        jobs, still_open = wait_all(client, chains, time.time() + a.timeout, a.poll,
                                    cont if a.chain > 1 else None, a.prune)
        job_ids = [c[-1] for c in chains]
        rows = [collect(client, job, observables) for job in jobs]
    except (ApiError, OSError) as e:
        print("error: lost the service while waiting (%s); the jobs keep running: %s" % (
            e, "the same command with the same --key collects them" if a.key else
            " ".join(c[-1] for c in chains)), file=sys.stderr)
        return 1

    # columns named by the pointers: an input may share its name with an observable (Iv)
    header = [ptr for ptr, _, _ in sweep] + ["job", "jobs", "status", "steady"]
    for o in observables:
        header += [o, o + "_stderr"]
        if any(o in r["obs"] and r["obs"][o][2] is not None for r in rows):
            header.append(o + "_ref")
    header += ["warnings", "message"]
    table = []
    for i, (j, r) in enumerate(zip(job_ids, rows)):
        line = {"job": j, "jobs": len(chains[i]), "status": r["status"], "steady": r["steady"],
                "warnings": " | ".join(r["warnings"]), "message": r["message"]}
        for ptr, _, vals in sweep:
            line[ptr] = json.dumps(vals[i]) if isinstance(vals[i], str) else vals[i]
        for o in observables:
            val, err, ref = r["obs"].get(o, (None, None, None))
            line[o], line[o + "_stderr"] = val, err
            if o + "_ref" in header:
                line[o + "_ref"] = ref
        table.append(line)

    print("".join("%-10s " % ptr for ptr, _, _ in sweep) + "%-11s %-6s " % ("status", "steady")
          + " ".join("%-26s" % o for o in observables))
    for i, (line, r) in enumerate(zip(table, rows)):
        cells = []
        for o in observables:
            val, err, ref = r["obs"].get(o, (None, None, None))
            cell = "" if val is None else "%.4g" % val + ("" if err is None else " ± %.2g" % err)
            cells.append("%-26s" % (cell + ("" if ref is None else " (%.4g)" % ref)))
        steady = {True: "yes", False: "no"}.get(line["steady"], "")
        print("".join("%-10s " % json.dumps(vals[i]) for _, _, vals in sweep)
              + "%-11s %-6s " % (line["status"], steady) + " ".join(cells))
    print("(value ± standard error, the seed's reference value in parentheses)")
    if a.out:
        tmp = a.out + ".tmp"
        with open(tmp, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=header)
            w.writeheader()
            w.writerows(table)
        os.replace(tmp, a.out)
        print("wrote", a.out)

    failed = [i for i, line in enumerate(table) if line["status"] in ("failed", "dismissed")]
    for i in failed:
        line = table[i]
        print("error: %s job %s %s%s" % (points[i], line["job"], line["status"],
                                         ": " + line["message"] if line["message"] else ""),
              file=sys.stderr)
    if still_open:
        print("error: timeout after %g s with %d job(s) not finished" % (a.timeout,
                                                                         len(still_open)),
              file=sys.stderr)
    warned = [i for i, line in enumerate(table) if line["warnings"]]
    for i in warned:
        print("warning: %s: %s" % (points[i], table[i]["warnings"]), file=sys.stderr)
    if failed or still_open:
        return 1
    if warned and a.fail_on_warnings:
        return 4
    return 0


if __name__ == "__main__":
    sys.exit(main())
