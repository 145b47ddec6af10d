"""Bad requests get the right status and a precise problem+json, and queue nothing:
malformed JSON, wrong types, out-of-range, unknown fields (top level and inside inputs),
oversized bodies (Content-Length and chunked), a job too large for the memory a job may use,
wrong Content-Type, unknown process, missing/invalid token, another user's job, priority
without admin rights, bad job ids."""
import socket

import jsonschema

import lubd_testlib as T

PROBLEM = "application/problem+json"


def run():
    a = T.args()
    srv = T.Server(a, "bad_inputs", workers=0, extra=["--max-body-kb", "16"]).fresh()
    alice = srv.token("alice")
    bob = srv.token("bob")
    admin = srv.token("root", admin=True)
    srv.start()
    try:
        ex = "/processes/falling_sphere/execution"
        # (description, path, body, headers, token, status, pointer or None, detail fragment)
        cases = [
            ("malformed JSON", ex, b'{"inputs": {"duration": 1,}', {}, alice, 400, "",
             "not valid JSON"),
            # named at its member since 2026-12-07, as lubdem names it (it was malformed JSON)
            ("duplicate key", ex, b'{"inputs": {}, "inputs": {}}', {}, alice, 400, "/inputs",
             "appears twice"),
            ("nested duplicate key", ex, b'{"inputs": {"law": {"eps": 0.01, "eps": 0.02}}}', {},
             alice, 400, "/inputs/law/eps", "appears twice"),
            # read as 0 by the parser: refused at its member, as lubdem refuses it (the service
            # took it as 0, the automatic step, until 2026-12-07)
            ("number below a double", ex, b'{"inputs": {"dt": 1e-400}}', {}, alice, 400,
             "/inputs/dt", "below the range of a double"),
            ("body not an object", ex, b'[1,2]', {}, alice, 400, "", "JSON object"),
            ("number beyond a double", ex, b'{"inputs": {"duration": 1e400}}', {}, alice,
             400, "/inputs/duration", "beyond the range of a double"),
            ("inputs missing", ex, {"priority": 0}, {}, alice, 400, "/inputs", "required"),
            ("inputs wrong type", ex, {"inputs": [1]}, {}, alice, 400, "/inputs", "object"),
            ("unknown top-level member", ex, {"inputs": {}, "input": {}}, {}, alice, 400,
             "/input", "unknown member"),
            ("scene inside inputs", ex, {"inputs": {"scene": "x"}}, {}, alice, 400,
             "/inputs/scene", "process id"),
            ("wrong type", ex, {"inputs": {"duration": "long"}}, {}, alice, 400,
             "/inputs/duration", ""),
            ("out of range", ex, {"inputs": {"duration": -1}}, {}, alice, 400,
             "/inputs/duration", ""),
            ("nested out of range", ex, {"inputs": {"law": {"eps": -0.5}}}, {}, alice, 400,
             "/inputs/law/eps", ""),
            ("unknown input", ex, {"inputs": {"durration": 1}}, {}, alice, 400,
             "/inputs/durration", ""),
            ("nested unknown input", ex, {"inputs": {"law": {"bogus": 1}}}, {}, alice, 400,
             "/inputs/law/bogus", ""),
            ("enum", ex, {"inputs": {"sample_spacing": "cubic"}}, {}, alice, 400,
             "/inputs/sample_spacing", ""),
            ("priority type", ex, {"inputs": {}, "priority": "high"}, {}, alice, 400,
             "/priority", "integer"),
            ("priority range", ex, {"inputs": {}, "priority": 11}, {}, alice, 400,
             "/priority", "[-10, 10]"),
            ("priority not integral", ex, {"inputs": {}, "priority": -2.5}, {}, alice, 400,
             "/priority", "integer"),
            ("integral priority out of range", ex, {"inputs": {}, "priority": -11.0}, {},
             alice, 400, "/priority", "[-10, 10]"),
            ("priority > 0 without admin", ex, {"inputs": {}, "priority": 5}, {}, alice, 403,
             "/priority", "admin"),
            ("two_spheres_shear wrong type", "/processes/two_spheres_shear/execution",
             {"inputs": {"St": True}}, {}, alice, 400, "/inputs/St", ""),
            # a lower bound of about 0.7 TiB (cut-off 10 a): above --mem-mb and any machine
            ("too large for the service", "/processes/simple_shear/execution",
             {"inputs": {"n_particles": 10000000, "cutoff": 10}}, {}, alice, 400,
             "/inputs/n_particles", "not enough memory: 10000000 particles"),
            ("unknown process", "/processes/nope/execution", {"inputs": {}}, {}, alice, 404,
             None, "does not exist"),
            ("text/plain", ex, b'{"inputs": {}}', {"Content-Type": "text/plain"}, alice, 415,
             None, "Content-Type"),
            ("form encoding", ex, b'inputs=1',
             {"Content-Type": "application/x-www-form-urlencoded"}, alice, 415, None,
             "application/json"),
            ("oversized body", ex, b'{"inputs": {"pad": "' + b"x" * 20000 + b'"}}', {},
             alice, 413, None, "exceeds"),
            ("no token", ex, {"inputs": {}}, {}, None, 401, None, "Authorization"),
            ("bad token", ex, {"inputs": {}}, {}, "lub_0000000000000000_" + "0" * 64, 401,
             None, "unknown"),
            ("garbage token", ex, {"inputs": {}}, {}, "hello", 401, None, "malformed"),
            ("bad idempotency key", ex, {"inputs": {}}, {"Idempotency-Key": "a b"}, alice,
             400, None, "Idempotency-Key"),
            ("GET on execution", ex, None, {}, alice, 405, None, "not allowed"),
        ]
        for desc, path, body, headers, tok, status, pointer, frag in cases:
            method = "GET" if body is None else "POST"
            st, h, doc = srv.request(method, path, tok, body, headers)
            T.check(st == status, "%s: status %s (want %s): %s" % (desc, st, status, doc))
            T.check(h.get("content-type") == PROBLEM, "%s: content-type %s" %
                    (desc, h.get("content-type")))
            T.check(doc["status"] == status and doc["type"] and doc["title"], desc + ": shape")
            if pointer is not None:
                T.check(doc.get("errors") and doc["errors"][0]["pointer"] == pointer,
                        "%s: pointer %s (want %s)" % (desc, doc.get("errors"), pointer))
            T.check(frag in doc["detail"], "%s: detail %r lacks %r" % (desc, doc["detail"],
                                                                       frag))
            if status == 401:
                T.check(h.get("www-authenticate", "").startswith("Bearer"), desc + ": 401 hdr")

        # A chunked oversized body (no Content-Length) is cut off at the limit too.
        s = socket.create_connection(("127.0.0.1", srv.port), timeout=10)
        head = ("POST %s HTTP/1.1\r\nHost: x\r\nAuthorization: Bearer %s\r\n"
                "Content-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n" %
                (ex, alice)).encode()
        chunk = b"x" * 4096
        payload = b"".join(b"%x\r\n%s\r\n" % (len(chunk), chunk) for _ in range(6)) + b"0\r\n\r\n"
        s.sendall(head + payload)
        reply = b""
        while b"\r\n\r\n" not in reply:
            got = s.recv(4096)
            if not got:
                break
            reply += got
        s.close()
        T.check(reply.startswith(b"HTTP/1.1 413"), "chunked oversized -> %r" % reply[:40])

        # An input name cut at the pointer's 250 bytes in the middle of a character: the
        # problem stays valid UTF-8 (it used to come back as "(detail not valid UTF-8)" with
        # an empty pointer).
        for name in ("\u00e9" * 130, "a" + "\u20ac" * 90):
            st, _, doc = srv.request("POST", ex, alice, {"inputs": {name: 1}})
            ptr = doc.get("errors", [{}])[0].get("pointer", "")
            T.check(st == 400 and len(ptr.encode()) > 240 and ptr.startswith("/inputs/" + name[:40])
                    and name.startswith(ptr[len("/inputs/"):]) and ptr in doc["detail"],
                    "long non-ASCII name -> %s %s" % (st, doc))

        # An input's value quoted in the detail, cut at 80 bytes inside a character: the
        # detail is the engine's message, valid UTF-8 (it came back "(detail not valid UTF-8)").
        st, _, doc = srv.request("POST", ex, alice,
                                 {"inputs": {"sample_spacing": "a" * 79 + "\u00e9"}})
        T.check(st == 400 and ('(got "%s")' % ("a" * 79)) in doc.get("detail", "")
                and doc["errors"][0]["pointer"] == "/inputs/sample_spacing",
                "enum value cut inside a character -> %s %s" % (st, doc))

        # Nothing was queued by any of the above.
        st, _, lst = srv.request("GET", "/jobs?limit=1000", admin)
        T.check(st == 200 and lst["jobs"] == [], "jobs were queued: %s" % lst["jobs"])
        st, _, health = srv.request("GET", "/health")
        T.check(health["queue"] == {"accepted": 0, "running": 0}, "queue not empty")

        # Every process's published inputsSchema takes {} and refuses "scene", as POST does:
        # until 2026-12-07 it was the spec file's, "scene" required, so no inputs passed it
        # and were accepted; and the unknown-input message listed "scene" among the inputs.
        st, _, procs = srv.request("GET", "/processes")
        for pid in [p["id"] for p in procs["processes"]]:
            st, _, desc = srv.request("GET", "/processes/" + pid)
            schema = desc["inputsSchema"]
            v = jsonschema.Draft7Validator(schema)
            T.check("scene" not in schema["properties"] and
                    "scene" not in schema.get("required", []) and v.is_valid({}) and
                    not v.is_valid({"scene": pid}),
                    "%s: inputsSchema takes {} and refuses scene: %s" %
                    (pid, [e.message for e in v.iter_errors({})]))
            st, _, doc = srv.request("POST", "/processes/%s/execution" % pid, alice,
                                     {"inputs": {}})
            T.check(st == 201, "%s: {} -> %s %s" % (pid, st, doc))
            st, _, doc = srv.request("DELETE", "/jobs/" + doc["jobID"], alice)
            T.check(st == 200, "%s: dismiss -> %s" % (pid, st))
            st, _, doc = srv.request("POST", "/processes/%s/execution" % pid, alice,
                                     {"inputs": {"durration": 1}})
            T.check(st == 400 and "unknown field (allowed: " in doc["detail"] and
                    "scene" not in doc["detail"], "%s: unknown input -> %s" % (pid, doc))

        # A priority of integral value written as a number (2.0, 1e1) is that integer, as
        # JSON Schema's "integer" (openapi.json) and the engine's integer inputs take it;
        # until 2026-12-07 it was refused, "must be an integer".
        for tok, prio, want in ((admin, 2.0, 2), (admin, 1e1, 10), (alice, -1.0, -1)):
            st, _, doc = srv.request("POST", ex, tok, {"inputs": {}, "priority": prio})
            T.check(st == 201 and doc["priority"] == want,
                    "priority %r -> %s %s" % (prio, st, doc))
            srv.request("DELETE", "/jobs/" + doc["jobID"], tok)

        # Another user's job; bad job ids; unknown routes; wrong methods.
        st, _, doc = srv.request("POST", ex, alice, {"inputs": {"duration": 1}})
        T.check(st == 201, "valid submit")
        jid = doc["jobID"]
        for path in ("/jobs/" + jid, "/jobs/%s/results" % jid, "/jobs/%s/log" % jid,
                     "/jobs/%s/results/result.h5" % jid):
            st, h, doc = srv.request("GET", path, bob)
            T.check(st == 404 and doc["type"].endswith("no-such-job"),
                    "bob GET %s -> %s" % (path, st))
        st, _, doc = srv.request("DELETE", "/jobs/" + jid, bob)
        T.check(st == 404, "bob DELETE -> %s" % st)
        st, _, doc = srv.request("GET", "/jobs/" + jid, alice)
        T.check(st == 200 and doc["status"] == "accepted", "alice's job untouched")
        for path in ("/jobs/../../etc/passwd", "/jobs/ZZZ", "/jobs/" + "0" * 32):
            st, _, doc = srv.request("GET", path, alice)
            T.check(st == 404, "GET %s -> %s" % (path, st))
        st, _, doc = srv.request("GET", "/jobs/%s/results/..%%2Fqueue.db" % jid, alice)
        T.check(st == 404, "traversal -> %s" % st)
        st, _, doc = srv.request("GET", "/nope", alice)
        T.check(st == 404 and doc["status"] == 404, "unknown route")
        st, h, doc = srv.request("PUT", "/jobs", alice, {"x": 1})
        T.check(st == 405 and "GET" in h.get("allow", ""), "PUT /jobs -> %s" % st)
        # a POST is checked as every POST is before its path, as openapi.json says: the
        # token (401), the Content-Type (415), then 405
        for tok, ctype, status in ((None, "application/json", 401), (alice, "text/plain", 415),
                                   (alice, "application/json", 405)):
            st, h, doc = srv.request("POST", "/jobs", tok, b"{}", {"Content-Type": ctype})
            T.check(st == status and (status != 405 or "GET" in h.get("allow", "")),
                    "POST /jobs (%s) -> %s (want %s)" % (ctype, st, status))
        st, _, doc = srv.request("GET", "/jobs?limit=0", alice)
        T.check(st == 400 and "limit" in doc["detail"], "limit=0")
        st, _, doc = srv.request("GET", "/jobs?cursor=abc", alice)
        T.check(st == 400 and "cursor" in doc["detail"], "bad cursor")
        st, _, doc = srv.request("GET", "/processes/nope")
        T.check(st == 404 and doc["type"].endswith("no-such-process"), "unknown process desc")

        # A user's string quoted in a detail (job id, process id, status value, body member,
        # Content-Type) is cut on a character boundary, with control characters
        # and bytes that are not UTF-8 escaped; until 2026-12-07 a "%.64s" cut inside a
        # character, or a byte such as 0xFF, made the detail "(detail not valid UTF-8)".
        e_acute = "\u00e9"
        quoted = [
            ("GET", "/jobs/" + "a" * 63 + "%C3%A9", None, {}, 404,
             'job "%s" does not exist' % ("a" * 63 + e_acute)),
            ("GET", "/jobs/" + "a" * 66 + "%C3%A9", None, {}, 404,
             'job "%s" does not exist' % ("a" * 66)),
            ("GET", "/jobs/%FF", None, {}, 404, 'job "\\xFF" does not exist'),
            ("GET", "/processes/" + "b" * 99 + "%C3%A9", None, {}, 404,
             'process "%s" does not exist' % ("b" * 99 + e_acute)),
            ("GET", "/jobs?status=%FF%0A", None, {}, 400, 'unknown value "\\xFF\\n"'),
            ("POST", ex, ('{"%s%s": 1}' % ("d" * 99, e_acute)).encode(), {}, 400,
             'unknown member "%s"' % ("d" * 99 + e_acute)),
            ("POST", ex, b'{"inputs": {}}', {"Content-Type": ("e" * 99 + e_acute).encode()},
             415, "(got %s)" % ("e" * 99 + e_acute)),
        ]
        for method, path, body, headers, status, fragment in quoted:
            st, _, doc = srv.request(method, path, alice, body, headers)
            T.check(st == status and fragment in doc.get("detail", ""),
                    "%s %s -> %s %s (wanted %s with %r)" % (method, path[:40], st, doc, status,
                                                            fragment))
    finally:
        srv.stop()


T.main(run)
