/* api_jobs.c — job list, status, dismiss and the results document. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api.h"
#include "deletion.h"
#include "fsutil.h"
#include "queue.h"
#include "scene.h"
#include "sha256.h"
#include "spec_reader.h"
#include "status_json.h"

int lubd_load_visible_job(lubd_request *r, const char *id, void *out, lubd_fault *f,
                          int allow_purged)
{
    lubd_job *j = out;
    if (lubd_authenticate(r, f) != 0)
        return -1;
    const int ok = lubd_is_hex(id, 16);
    int found = 0;
    if (ok) {
        sqlite3 *db = lubd_db_acquire(&r->srv->pool);
        found = lubd_queue_get(db, id, j);
        lubd_db_release(&r->srv->pool, db);
    }
    if (found < 0)
        return lubd_fail(f, 500, LUBD_PT_BASE "internal", "Internal error", NULL, "database error");
    if (found == 0 || (j->user_id != r->user.id && !r->user.is_admin)) {
        char quoted[68];
        lub_text_one_line(id, quoted, sizeof quoted);
        return lubd_fail(f, 404, LUBD_OGC_EXC "no-such-job", "No such job", NULL,
                         "job \"%s\" does not exist (or belongs to another user)", quoted);
    }
    if (j->purged && !allow_purged)
        return lubd_fail(f, 410, LUBD_PT_BASE "job-purged", "Job purged", NULL,
                         "job %s was deleted (DELETE of a job that had ended or been "
                         "dismissed); its results and files are gone",
                         id);
    return 0;
}

static void add_retry_after(struct MHD_Response *resp, const lubd_job *j)
{
    if (resp && !lubd_job_finished(j))
        MHD_add_response_header(resp, MHD_HTTP_HEADER_RETRY_AFTER,
                                strcmp(j->state, "running") == 0 ? "2" : "5");
}

enum MHD_Result lubd_api_job(lubd_request *r, const char *id)
{
    lubd_fault f;
    lubd_job j;
    if (lubd_load_visible_job(r, id, &j, &f, 0) != 0)
        return lubd_reply_fault(r, &f);
    struct MHD_Response *resp =
        lubd_json_response(lubd_status_json(&j, r->base, r->user.is_admin), "application/json");
    add_retry_after(resp, &j);
    return lubd_queue(r, 200, resp);
}

/* Collects repeated and comma-separated "status" values into a mask. */
typedef struct {
    int mask;
    int bad;
    char bad_value[64];
} status_acc;

static enum MHD_Result collect_status(void *cls, enum MHD_ValueKind kind, const char *key,
                                      const char *value)
{
    (void)kind;
    status_acc *a = cls;
    if (strcmp(key, "status") != 0 && strcmp(key, "status[]") != 0)
        return MHD_YES;
    char buf[256];
    snprintf(buf, sizeof buf, "%s", value ? value : "");
    char *save = NULL;
    for (char *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
        int bit = lubd_state_bit(t);
        if (!bit && !a->bad) {
            a->bad = 1;
            snprintf(a->bad_value, sizeof a->bad_value, "%s", t);
        }
        a->mask |= bit;
    }
    return MHD_YES;
}

/* Collects the values of a list parameter (name or name[], repeated and comma-separated; empty
 * items skipped) into a JSON array of strings. */
typedef struct {
    const char *name, *alias; /* alias: another name for it, or NULL */
    json_t *values;
} list_acc;

static enum MHD_Result collect_list(void *cls, enum MHD_ValueKind kind, const char *key,
                                    const char *value)
{
    (void)kind;
    list_acc *a = cls;
    const size_t n = strlen(a->name);
    const int named = (strncmp(key, a->name, n) == 0 && (!key[n] || strcmp(key + n, "[]") == 0)) ||
                      (a->alias && strcmp(key, a->alias) == 0);
    if (!named || !value)
        return MHD_YES;
    for (const char *t = value; *t;) {
        const size_t len = strcspn(t, ",");
        if (len > 0)
            json_array_append_new(a->values, json_stringn(t, len));
        t += len + (t[len] == ',');
    }
    return MHD_YES;
}

/* Appends s to the growing string *buf (NULL on allocation failure, which sticks),
 * percent-encoding every byte but RFC 3986's unreserved ones when `escape`. */
static void append(char **buf, size_t *len, const char *s, int escape)
{
    if (!*buf)
        return;
    const size_t add = strlen(s) * (escape ? 3 : 1);
    char *grown = realloc(*buf, *len + add + 1);
    if (!grown) {
        free(*buf);
        *buf = NULL;
        return;
    }
    *buf = grown;
    for (const unsigned char *c = (const unsigned char *)s; *c; ++c) {
        if (!escape || isalnum(*c) || strchr("-._~", *c))
            grown[(*len)++] = (char)*c;
        else
            *len += (size_t)sprintf(grown + *len, "%%%02X", *c);
    }
    grown[*len] = '\0';
}

static enum MHD_Result bad_parameter(lubd_request *r, const char *fmt, const char *value)
{
    lubd_fault f;
    char quoted[104];
    lub_text_one_line(value ? value : "", quoted, sizeof quoted);
    lubd_fail(&f, 400, LUBD_PT_BASE "invalid-parameter", "Invalid query parameter", NULL, fmt,
              quoted);
    return lubd_reply_fault(r, &f);
}

/* processID names no process: a 400 naming the value and the known process ids (a typo is not
 * "no jobs"; until 2026-12-07 it listed nothing with a 200). */
static enum MHD_Result unknown_process(lubd_request *r, const char *value)
{
    char known[512] = "";
    size_t used = 0;
    for (const lub_scene *const *s = lub_scene_list(); *s && used < sizeof known; ++s)
        used += (size_t)snprintf(known + used, sizeof known - used, "%s%s", used ? ", " : "",
                                 (*s)->name);
    char quoted[104];
    lub_text_one_line(value, quoted, sizeof quoted);
    lubd_fault f;
    lubd_fail(&f, 400, LUBD_PT_BASE "invalid-parameter", "Invalid query parameter", NULL,
              "processID: unknown process \"%s\" (the processes: %s)", quoted, known);
    return lubd_reply_fault(r, &f);
}

/* datetime (OGC API - Processes job list): an instant, or an interval start/end whose either
 * end may be open ("" or ".."), matched against the jobs' created times. 0, or -1. */
static int parse_datetime(const char *v, lubd_list_query *q)
{
    const char *slash = strchr(v, '/');
    long long lo, hi;
    if (!slash) {
        if (lubd_parse_rfc3339(v, &hi, &lo) != 0)
            return -1;
        q->created_from_ms = lo;
        q->created_to_ms = hi;
        return 0;
    }
    char start[64];
    const size_t n = (size_t)(slash - v);
    if (n >= sizeof start || strchr(slash + 1, '/'))
        return -1;
    memcpy(start, v, n);
    start[n] = '\0';
    const char *end = slash + 1;
    long long unused;
    if (n > 0 && strcmp(start, "..") != 0) {
        if (lubd_parse_rfc3339(start, &unused, &lo) != 0)
            return -1;
        q->created_from_ms = lo;
    }
    if (*end && strcmp(end, "..") != 0) {
        if (lubd_parse_rfc3339(end, &hi, &unused) != 0)
            return -1;
        q->created_to_ms = hi;
    }
    return 0;
}

/* minDuration/maxDuration: seconds, a number >= 0. 0, or -1. */
static int parse_seconds(const char *v, double *out)
{
    char *end;
    errno = 0;
    const double x = strtod(v, &end);
    if (end == v || *end || errno || !isfinite(x) || x < 0 || !isdigit((unsigned char)v[0]))
        return -1;
    *out = x;
    return 0;
}

enum MHD_Result lubd_api_jobs(lubd_request *r)
{
    lubd_fault f;
    if (lubd_authenticate(r, &f) != 0)
        return lubd_reply_fault(r, &f);
    lubd_list_query q = {r->user.is_admin ? -1 : r->user.id, 0, NULL, 10, 0, -1, -1, -1.0, -1.0};
    status_acc acc = {0, 0, ""};
    MHD_get_connection_values(r->conn, MHD_GET_ARGUMENT_KIND, collect_status, &acc);
    if (acc.bad)
        return bad_parameter(r,
                             "status: unknown value \"%s\" (accepted, running, successful, "
                             "failed, dismissed)",
                             acc.bad_value);
    q.state_mask = acc.mask;
    /* type: "process", the only type of job there is (OGC API - Processes Part 1) */
    list_acc types = {"type", NULL, json_array()};
    MHD_get_connection_values(r->conn, MHD_GET_ARGUMENT_KIND, collect_list, &types);
    size_t i;
    json_t *v;
    json_array_foreach (types.values, i, v)
        if (strcmp(json_string_value(v), "process") != 0) {
            enum MHD_Result rc = bad_parameter(
                r, "type: unknown value \"%s\" (process: the only job type)", json_string_value(v));
            json_decref(types.values);
            return rc;
        }
    const int typed = json_array_size(types.values) > 0;
    json_decref(types.values);
    const char *dt = lubd_query(r, "datetime");
    if (dt && parse_datetime(dt, &q) != 0)
        return bad_parameter(r,
                             "datetime: \"%s\" is neither an RFC 3339 date-time (such as "
                             "2026-12-07T10:00:00Z) nor an interval of two, either end open "
                             "(\"..\" or empty)",
                             dt);
    const char *mind = lubd_query(r, "minDuration"), *maxd = lubd_query(r, "maxDuration");
    if (mind && parse_seconds(mind, &q.min_duration) != 0)
        return bad_parameter(r, "minDuration: \"%s\" is not a number of seconds >= 0", mind);
    if (maxd && parse_seconds(maxd, &q.max_duration) != 0)
        return bad_parameter(r, "maxDuration: \"%s\" is not a number of seconds >= 0", maxd);
    const char *lim = lubd_query(r, "limit");
    if (lim) {
        char *end;
        long val = strtol(lim, &end, 10);
        if (*end || end == lim || val < 1 || val > 1000)
            return bad_parameter(r, "limit: must be an integer in [1, 1000] (got \"%s\")", lim);
        q.limit = (int)val;
    }
    const char *cur = lubd_query(r, "cursor");
    if (cur) {
        char *end;
        long long val = cur[0] == 's' ? strtoll(cur + 1, &end, 10) : -1;
        if (val <= 0 || *end)
            return bad_parameter(r, "cursor: \"%s\" is not a cursor from a 'next' link", cur);
        q.before_seq = val;
    }
    /* processID (or process): repeated and comma-separated, any of them; each a process */
    list_acc procs = {"processID", "process", json_array()};
    MHD_get_connection_values(r->conn, MHD_GET_ARGUMENT_KIND, collect_list, &procs);
    json_array_foreach (procs.values, i, v)
        if (!lub_scene_find(json_string_value(v))) {
            enum MHD_Result bad = unknown_process(r, json_string_value(v));
            json_decref(procs.values);
            return bad;
        }
    char *proc_json = json_array_size(procs.values) ? json_dumps(procs.values, JSON_COMPACT) : NULL;
    q.process_ids = proc_json;
    lubd_job *jobs = NULL;
    int n = 0, more = 0, rc = -1;
    if (!json_array_size(procs.values) || proc_json) {
        sqlite3 *db = lubd_db_acquire(&r->srv->pool);
        rc = lubd_queue_list(db, &q, &jobs, &n, &more);
        lubd_db_release(&r->srv->pool, db);
    }
    free(proc_json);
    if (rc != 0) {
        json_decref(procs.values);
        lubd_fail(&f, 500, LUBD_PT_BASE "internal", "Internal error", NULL, "database error");
        return lubd_reply_fault(r, &f);
    }
    json_t *arr = json_array();
    for (int k = 0; k < n; ++k)
        json_array_append_new(arr, lubd_status_json(&jobs[k], r->base, r->user.is_admin));
    /* The links' filters: the validated values, percent-encoded */
    size_t fl = 0;
    char *filters = calloc(1, 1);
    static const char *const names[] = {"accepted", "running", "successful", "failed", "dismissed"};
    for (int b = 0; b < 5; ++b)
        if (q.state_mask & (1 << b)) {
            append(&filters, &fl, "&status=", 0);
            append(&filters, &fl, names[b], 0);
        }
    json_array_foreach (procs.values, i, v) {
        append(&filters, &fl, "&processID=", 0);
        append(&filters, &fl, json_string_value(v), 1);
    }
    json_decref(procs.values);
    if (typed)
        append(&filters, &fl, "&type=process", 0);
    if (dt) {
        append(&filters, &fl, "&datetime=", 0);
        append(&filters, &fl, dt, 1);
    }
    char num[40];
    if (mind) {
        snprintf(num, sizeof num, "&minDuration=%.17g", q.min_duration);
        append(&filters, &fl, num, 0);
    }
    if (maxd) {
        snprintf(num, sizeof num, "&maxDuration=%.17g", q.max_duration);
        append(&filters, &fl, num, 0);
    }
    json_t *links = json_array();
    char cursor[40] = "";
    if (cur) /* this page, not the first */
        snprintf(cursor, sizeof cursor, "&cursor=s%lld", q.before_seq);
    if (filters)
        json_array_append_new(links, json_pack("{s:o, s:s, s:s}", "href",
                                               json_sprintf("%s/jobs?limit=%d%s%s", r->base,
                                                            q.limit, filters, cursor),
                                               "rel", "self", "type", "application/json"));
    if (filters && more && n > 0)
        json_array_append_new(links,
                              json_pack("{s:o, s:s, s:s}", "href",
                                        json_sprintf("%s/jobs?limit=%d%s&cursor=s%lld", r->base,
                                                     q.limit, filters, jobs[n - 1].seq),
                                        "rel", "next", "type", "application/json"));
    free(filters);
    free(jobs);
    return lubd_reply_json(
        r, 200, json_pack("{s:o, s:i, s:o}", "jobs", arr, "numberReturned", n, "links", links));
}

enum MHD_Result lubd_api_dismiss(lubd_request *r, const char *id)
{
    lubd_fault f;
    lubd_job j, after;
    /* j: who may see the job; its state is not used (a worker may change it before the
     * dismissal: what is done below follows `was`, read in the dismissal's transaction) */
    if (lubd_load_visible_job(r, id, &j, &f, 0) != 0)
        return lubd_reply_fault(r, &f);
    int purge = 0;
    char was[16] = "";
    sqlite3 *db = lubd_db_acquire_writer(&r->srv->pool);
    int rc = lubd_queue_dismiss(db, id, &after, was, &purge);
    lubd_db_release_writer(&r->srv->pool, db);
    if (rc == 1) {
        lubd_fail(&f, 410, LUBD_PT_BASE "job-purged", "Job purged", NULL,
                  "job %s was already purged", id);
        return lubd_reply_fault(r, &f);
    }
    if (rc != 0) {
        lubd_fail(&f, 500, LUBD_PT_BASE "internal", "Internal error", NULL, "database error");
        return lubd_reply_fault(r, &f);
    }
    /* Jobs that continue this one and have not ended keep its files (the deletion frees
     * their space once they end); if they cannot, the folder stays for them until then. A
     * continuation dismissed before it started no longer needs files handed over to it. */
    char why[1400] = "";
    int left = 0; /* 0: nothing left on disk that should not be */
    sqlite3 *rdb = lubd_db_acquire(&r->srv->pool);
    if (purge)
        left = lubd_deletion_free(rdb, r->srv->cfg->jobs_dir, id, why, sizeof why);
    else if (strcmp(was, "accepted") == 0) { /* a running one is tidied by its worker */
        left = lubd_deletion_tidy_ended(r->srv->cfg->jobs_dir, &after, why, sizeof why) < 0;
        if (!left && after.continue_from[0])
            left = lubd_deletion_continuation_ended(rdb, r->srv->cfg->jobs_dir, id,
                                                    after.continue_from, why, sizeof why);
    }
    lubd_db_release(&r->srv->pool, rdb);
    if (left != 0)
        fprintf(stderr, "lubdemd: %s\n", why);
    return lubd_reply_json(r, 200, lubd_status_json(&after, r->base, r->user.is_admin));
}

/* The outputs document of a finished job ({name: {href, type, size, sha256}}) and, in
 * *summary, its summary.json (NULL when it has none). NULL on a database error. */
static json_t *outputs_json(lubd_request *r, const char *id, json_t **summary)
{
    *summary = NULL;
    lubd_result_file *files;
    int n;
    sqlite3 *db = lubd_db_acquire(&r->srv->pool);
    int rc = lubd_queue_results(db, id, &files, &n);
    lubd_db_release(&r->srv->pool, db);
    if (rc != 0)
        return NULL;
    json_t *outputs = json_object();
    for (int i = 0; i < n; ++i) {
        char href[1200];
        snprintf(href, sizeof href, "%s/jobs/%s/results/%s", r->base, id, files[i].name);
        json_object_set_new(outputs, files[i].name,
                            json_pack("{s:s, s:s, s:I, s:s}", "href", href, "type",
                                      files[i].media_type, "size", (json_int_t)files[i].size,
                                      "sha256", files[i].sha256));
        if (strcmp(files[i].name, "summary.json") == 0) {
            char path[1400];
            snprintf(path, sizeof path, "%s/%s/result/summary.json", r->srv->cfg->jobs_dir, id);
            *summary = json_load_file(path, JSON_PRESERVE_ORDER, NULL);
        }
    }
    free(files);
    return outputs;
}

/* The inputs the job was submitted with (its spec without "scene"): what a job that
 * continues it submits, also when the engine wrote no summary stating its spec (an engine
 * killed with SIGKILL). NULL when they cannot be read. */
static json_t *inputs_json(lubd_request *r, const char *id)
{
    char *text = NULL;
    sqlite3 *db = lubd_db_acquire(&r->srv->pool);
    const int found = lubd_queue_spec(db, id, &text);
    lubd_db_release(&r->srv->pool, db);
    json_t *spec = found == 1 ? json_loads(text, JSON_DECODE_ANY, NULL) : NULL;
    free(text);
    if (!json_is_object(spec)) {
        json_decref(spec);
        return NULL;
    }
    json_object_del(spec, "scene");
    return spec;
}

enum MHD_Result lubd_api_results(lubd_request *r, const char *id)
{
    lubd_fault f;
    lubd_job j;
    if (lubd_load_visible_job(r, id, &j, &f, 0) != 0)
        return lubd_reply_fault(r, &f);
    if (strcmp(j.state, "accepted") == 0 || strcmp(j.state, "running") == 0) {
        lubd_fail(&f, 404, LUBD_OGC_EXC "result-not-ready", "Result not ready", NULL,
                  "job %s is %s (progress %d%%); poll /jobs/%s", id, j.state, j.progress, id);
        f.retry_after = 2;
        return lubd_reply_fault(r, &f);
    }
    if (strcmp(j.state, "dismissed") == 0) {
        lubd_fail(&f, 410, LUBD_PT_BASE "job-dismissed", "Job dismissed", NULL,
                  "job %s was dismissed: %s", id, j.message);
        return lubd_reply_fault(r, &f);
    }
    json_t *summary;
    json_t *outputs = outputs_json(r, id, &summary);
    if (!outputs) {
        lubd_fail(&f, 500, LUBD_PT_BASE "internal", "Internal error", NULL, "database error");
        return lubd_reply_fault(r, &f);
    }
    if (strcmp(j.state, "failed") == 0) {
        int system = strcmp(j.failure_kind, "system") == 0;
        lubd_fail(&f, system ? 500 : 422, LUBD_PT_BASE "job-failed", "Job failed", NULL,
                  "job %s failed (%s): %s", id, j.failure_kind, j.message);
        /* The job's inputs (always: what a job continuing it submits; until 2026-12-07 they
         * were left out with the files when the engine had written nothing), and what the
         * failed attempt's engine wrote, where it wrote anything: its summary (the diagnostic,
         * and the results of a run whose result.h5 could not be written) and the files it kept
         * (a partial or failed result.h5, a stopped run's checkpoint; {} for none), served
         * like a successful job's. Jobs that failed before the files were kept (or whose files
         * could not be moved) have their summary in the attempt's folder only. */
        if (!summary && j.attempt > 0) {
            char path[1400];
            snprintf(path, sizeof path, "%s/%s/attempt-%d/out/summary.json", r->srv->cfg->jobs_dir,
                     id, j.attempt);
            summary = json_load_file(path, JSON_PRESERVE_ORDER, NULL);
        }
        json_t *body = lubd_fault_json(&f, r->url);
        json_t *inputs = inputs_json(r, id);
        if (inputs)
            json_object_set_new(body, "inputs", inputs);
        if (json_is_object(summary))
            json_object_set_new(body, "summary", summary);
        else
            json_decref(summary);
        json_object_set_new(body, "outputs", outputs);
        struct MHD_Response *resp = lubd_json_response(body, "application/problem+json");
        return resp ? lubd_queue(r, (unsigned)f.status, resp) : MHD_NO;
    }
    char self[1200];
    snprintf(self, sizeof self, "%s/jobs/%s/results", r->base, id);
    json_t *inputs = inputs_json(r, id);
    json_t *o = json_pack("{s:s, s:s, s:o, s:o, s:o, s:[{s:s, s:s, s:s}]}", "jobID", id,
                          "processID", j.process_id, "inputs", inputs ? inputs : json_null(),
                          "summary", summary ? summary : json_null(), "outputs", outputs, "links",
                          "href", self, "rel", "self", "type", "application/json");
    return lubd_reply_json(r, 200, o);
}
