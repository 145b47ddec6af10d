/* exec_request.c — execution request validation (shape here, scene rules in the engine). */
#include "exec_request.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json_overflow.h"
#include "scene.h"
#include "sha256.h"
#include "spec_reader.h"

static const char *const allowed_members[] = {"inputs",     "priority",      "outputs", "response",
                                              "subscriber", "continue_from", NULL};

static int check_members(const json_t *body, lubd_fault *f)
{
    const char *key;
    json_t *v;
    json_object_foreach ((json_t *)body, key, v) {
        int ok = 0;
        for (const char *const *a = allowed_members; *a; ++a)
            if (strcmp(*a, key) == 0)
                ok = 1;
        if (!ok) {
            char ptr[300];
            lub_pointer_join(ptr, sizeof ptr, "", key);
            char quoted[104];
            lub_text_one_line(key, quoted, sizeof quoted);
            return lubd_fail(f, 400, LUBD_PT_BASE "invalid-request", "Invalid request", ptr,
                             "unknown member \"%s\" (allowed: inputs, priority, outputs, "
                             "response, subscriber, continue_from)",
                             quoted);
        }
    }
    json_t *o = json_object_get(body, "outputs");
    if (o && !json_is_object(o))
        return lubd_fail(f, 400, LUBD_PT_BASE "invalid-request", "Invalid request", "/outputs",
                         "must be an object");
    json_t *s = json_object_get(body, "subscriber");
    if (s && !json_is_object(s))
        return lubd_fail(f, 400, LUBD_PT_BASE "invalid-request", "Invalid request", "/subscriber",
                         "must be an object");
    json_t *resp = json_object_get(body, "response");
    if (resp && !(json_is_string(resp) && strcmp(json_string_value(resp), "document") == 0))
        return lubd_fail(f, 400, LUBD_PT_BASE "invalid-request", "Invalid request", "/response",
                         "only \"document\" is supported");
    return 0;
}

/* 1 with *out set when v is a real of integral value within the range of a 64-bit integer. */
static int integral_real(const json_t *v, json_int_t *out)
{
    if (!json_is_real(v))
        return 0;
    const double x = json_real_value(v);
    if (!(x >= -9223372036854775808.0 && x < 9223372036854775808.0) || x != (double)(long long)x)
        return 0;
    *out = (json_int_t)x;
    return 1;
}

/* The body's numbers by value, for the fingerprint: a real of integral value within the range
 * of a 64-bit integer becomes that integer (1e5, 100000.0 and 100000 are one number; -0.0 is
 * 0), in place, through objects and arrays. Other reals keep jansson's shortest round-trip
 * text, so 0.5 and 0.50 already print alike. */
static void numbers_by_value(json_t *v)
{
    json_int_t n;
    if (json_is_object(v)) {
        const char *key;
        json_t *m;
        json_object_foreach (v, key, m) {
            if (integral_real(m, &n))
                json_object_set_new(v, key, json_integer(n)); /* replaces: no rehash */
            else
                numbers_by_value(m);
        }
    } else if (json_is_array(v)) {
        for (size_t i = 0; i < json_array_size(v); ++i) {
            json_t *m = json_array_get(v, i);
            if (integral_real(m, &n))
                json_array_set_new(v, i, json_integer(n));
            else
                numbers_by_value(m);
        }
    }
}

int lubd_exec_parse(const char *body, size_t len, const char *process_id, lubd_exec_request *r,
                    lubd_fault *f)
{
    memset(r, 0, sizeof *r);
    if (!lub_scene_find(process_id)) {
        char quoted[104];
        lub_text_one_line(process_id, quoted, sizeof quoted);
        return lubd_fail(f, 404, LUBD_OGC_EXC "no-such-process", "No such process", NULL,
                         "process \"%s\" does not exist (GET /processes lists them)", quoted);
    }
    json_error_t jerr;
    r->body = json_loadb(body, len, JSON_REJECT_DUPLICATES, &jerr);
    /* the body as a string, for naming a member the parser refused or read as 0; it is parsed
     * again (up to 100 times), so only for a body of at most 64 KiB, on the request's thread */
    char *text =
        body && len <= ((size_t)64 << 10) && !memchr(body, '\0', len) ? malloc(len + 1) : NULL;
    if (text) {
        memcpy(text, body, len);
        text[len] = '\0';
    }
    lub_error big;
    int named = -1;
    if (!r->body && text) {
        /* a number beyond a double or an int64, or a duplicate key, is named at its member,
         * as lubdem does (until 2026-12-07 a duplicate was answered as malformed JSON) */
        named = lub_json_overflow_member(text, &jerr, &big);
        if (named != 0)
            named = lub_json_duplicate_member(text, &jerr, &big);
    } else if (r->body && text) {
        /* a number below the range of a double, which the parser reads as 0 without a word
         * (until 2026-12-07 the service took "dt": 1e-400 as the automatic step) */
        named = lub_json_underflow_member(text, &big);
        if (named == 0) {
            json_decref(r->body);
            r->body = NULL;
        }
    }
    free(text);
    if (!r->body) {
        if (named == 0) {
            const int input = strncmp(big.pointer, "/inputs/", 8) == 0;
            return lubd_fail(f, 400,
                             input ? LUBD_PT_BASE "invalid-input" : LUBD_PT_BASE "invalid-request",
                             input ? "Invalid input" : "Invalid request", big.pointer, "%s: %s",
                             big.pointer, big.message);
        }
        return lubd_fail(f, 400, LUBD_PT_BASE "malformed-json", "Malformed JSON", "",
                         "request body is not valid JSON: %s (line %d, column %d)", jerr.text,
                         jerr.line, jerr.column);
    }
    if (!json_is_object(r->body)) {
        lubd_fail(f, 400, LUBD_PT_BASE "invalid-request", "Invalid request", "",
                  "request body must be a JSON object {\"inputs\": {...}}");
        goto fail;
    }
    if (check_members(r->body, f) != 0)
        goto fail;
    json_t *prio = json_object_get(r->body, "priority");
    if (prio) {
        /* an integer, or a number of integral value (2.0), as JSON Schema's "integer" and the
         * engine's integer inputs take it (until 2026-12-07 2.0 was refused) */
        json_int_t p = 0;
        const int whole =
            json_is_integer(prio) ? (p = json_integer_value(prio), 1) : integral_real(prio, &p);
        if (!whole || p < -10 || p > 10) {
            lubd_fail(f, 400, LUBD_PT_BASE "invalid-request", "Invalid request", "/priority",
                      "must be an integer in [-10, 10]");
            goto fail;
        }
        r->priority = (int)p;
    }
    json_t *from = json_object_get(r->body, "continue_from");
    if (from) {
        const char *id = json_is_string(from) ? json_string_value(from) : "";
        if (!lubd_is_hex(id, 16)) {
            lubd_fail(f, 400, LUBD_PT_BASE "invalid-request", "Invalid request", "/continue_from",
                      "/continue_from: must be the jobID of a finished job (32 hexadecimal "
                      "digits)");
            goto fail;
        }
        if (!lub_scene_find(process_id)->resumable) {
            lubd_fail(f, 400, LUBD_PT_BASE "invalid-request", "Invalid request", "/continue_from",
                      "/continue_from: %s runs do not keep checkpoints; only simple_shear and "
                      "resuspension jobs can be continued",
                      process_id);
            goto fail;
        }
        memcpy(r->continue_from, id, 33);
    }
    json_t *inputs = json_object_get(r->body, "inputs");
    if (!inputs) {
        lubd_fail(f, 400, LUBD_PT_BASE "invalid-request", "Invalid request", "/inputs",
                  "required member is missing (an object with the process inputs; may be {})");
        goto fail;
    }
    if (!json_is_object(inputs)) {
        lubd_fail(f, 400, LUBD_PT_BASE "invalid-request", "Invalid request", "/inputs",
                  "must be an object");
        goto fail;
    }
    if (json_object_get(inputs, "scene")) {
        lubd_fail(f, 400, LUBD_PT_BASE "invalid-input", "Invalid input", "/inputs/scene",
                  "not an input: the process id in the URL selects the scene");
        goto fail;
    }
    r->spec = json_deep_copy(inputs);
    if (!r->spec || json_object_set_new(r->spec, "scene", json_string(process_id)) != 0) {
        lubd_fail(f, 500, LUBD_PT_BASE "internal", "Internal error", NULL, "out of memory");
        goto fail;
    }
    lub_error err;
    memset(&err, 0, sizeof err);
    if (lub_spec_resolve(r->spec, &r->resolved, &err) != 0) {
        /* the engine lists the spec file's members, "scene" first; the scene is not an
         * input here (the process id in the URL selects it) */
        static const char listed[] = "unknown field (allowed: ", first[] = "scene, ";
        const int top = err.pointer[0] == '/' && !strchr(err.pointer + 1, '/');
        if (top && strncmp(err.message, listed, sizeof listed - 1) == 0) {
            char *names = err.message + sizeof listed - 1;
            if (strncmp(names, first, sizeof first - 1) == 0)
                memmove(names, names + sizeof first - 1, strlen(names + sizeof first - 1) + 1);
        }
        char ptr[300];
        snprintf(ptr, sizeof ptr, "/inputs%.250s", err.pointer);
        lub_utf8_trim_tail(ptr);
        lubd_fail(f, 400, LUBD_PT_BASE "invalid-input", "Invalid input", ptr, "%s: %s", ptr,
                  err.message);
        goto fail;
    }
    /* the fingerprint of an Idempotency-Key's request: members in any order, numbers by
     * value (as a continuation's spec is compared, engine/resume_spec.h) */
    json_t *by_value = json_deep_copy(r->body);
    numbers_by_value(by_value);
    char *canon = by_value ? json_dumps(by_value, JSON_SORT_KEYS | JSON_COMPACT) : NULL;
    json_decref(by_value);
    if (!canon) {
        lubd_fail(f, 500, LUBD_PT_BASE "internal", "Internal error", NULL, "out of memory");
        goto fail;
    }
    lubd_sha256 c;
    uint8_t d[32];
    lubd_sha256_init(&c);
    lubd_sha256_update(&c, process_id, strlen(process_id));
    lubd_sha256_update(&c, "\n", 1);
    lubd_sha256_update(&c, canon, strlen(canon));
    lubd_sha256_final(&c, d);
    lubd_hex_encode(d, 32, r->fingerprint);
    free(canon);
    return 0;
fail:
    lubd_exec_free(r);
    return -1;
}

void lubd_exec_free(lubd_exec_request *r)
{
    json_decref(r->body);
    json_decref(r->spec);
    json_decref(r->resolved);
    r->body = r->spec = r->resolved = NULL;
}
