/* api_processes.c — process list/description (the engine's scenes) and job submission. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api.h"
#include "continuation.h"
#include "exec_request.h"
#include "job_limits.h"
#include "json_text.h"
#include "oas_schema.h"
#include "queue.h"
#include "scene.h"
#include "spec_reader.h"
#include "status_json.h"

static json_t *summary_of(const lub_scene *s, const char *base)
{
    char href[600];
    snprintf(href, sizeof href, "%s/processes/%s", base, s->name);
    char exec[640];
    snprintf(exec, sizeof exec, "%s/execution", href);
    return json_pack("{s:s, s:s, s:s, s:s, s:[s,s], s:[s], s:[{s:s, s:s, s:s}, {s:s, s:s, s:s}]}",
                     "id", s->name, "title", s->title, "description", s->description, "version",
                     "1.0.0", "jobControlOptions", "async-execute", "dismiss", "outputTransmission",
                     "reference", "links", "href", href, "rel", "self", "type", "application/json",
                     "href", exec, "rel", "http://www.opengis.net/def/rel/ogc/1.0/execute", "type",
                     "application/json");
}

enum MHD_Result lubd_api_processes(lubd_request *r)
{
    json_t *list = json_array();
    for (const lub_scene *const *s = lub_scene_list(); *s; ++s)
        json_array_append_new(list, summary_of(*s, r->base));
    char self[600];
    snprintf(self, sizeof self, "%s/processes", r->base);
    return lubd_reply_json(r, 200,
                           json_pack("{s:o, s:[{s:s, s:s, s:s}]}", "processes", list, "links",
                                     "href", self, "rel", "self", "type", "application/json"));
}

enum MHD_Result lubd_api_process(lubd_request *r, const char *id)
{
    const lub_scene *s = lub_scene_find(id);
    if (!s) {
        lubd_fault f;
        char quoted[104];
        lub_text_one_line(id, quoted, sizeof quoted);
        lubd_fail(&f, 404, LUBD_OGC_EXC "no-such-process", "No such process", NULL,
                  "process \"%s\" does not exist (GET /processes lists them)", quoted);
        return lubd_reply_fault(r, &f);
    }
    json_t *o = summary_of(s, r->base);
    char path[1200];
    snprintf(path, sizeof path, "%s/%s.schema.json", r->srv->cfg->schema_dir, s->name);
    json_error_t err;
    json_t *schema = json_load_file(path, JSON_PRESERVE_ORDER, &err);
    /* the scene is selected by the process id, not an input (POST refuses inputs.scene):
     * the schema file (a lubdem spec file's, with "scene" required) is served without it,
     * and without its $id, which names the file's schema */
    json_object_del(json_object_get(schema, "properties"), "scene");
    json_t *req_list = json_object_get(schema, "required");
    for (size_t i = json_array_size(req_list); i-- > 0;) {
        json_t *v = json_array_get(req_list, i);
        if (json_is_string(v) && strcmp(json_string_value(v), "scene") == 0)
            json_array_remove(req_list, i);
    }
    if (req_list && json_array_size(req_list) == 0)
        json_object_del(schema, "required");
    json_object_del(schema, "$id");
    json_t *inputs = json_object();
    char untranslated[400] = ""; /* the first input whose schema has no OpenAPI 3.0 form */
    json_t *props = json_object_get(schema, "properties");
    json_t *required = json_object_get(schema, "required");
    const char *key;
    json_t *prop;
    json_object_foreach (props, key, prop) {
        int req = 0;
        size_t i;
        json_t *v;
        json_array_foreach (required, i, v)
            if (json_is_string(v) && strcmp(json_string_value(v), key) == 0)
                req = 1;
        json_t *title = json_object_get(prop, "title");
        json_t *desc = json_object_get(prop, "description");
        /* OGC's input schema is an OpenAPI 3.0 Schema Object: the draft-07 file's translation
         * (an empty schema, and inputsSchemaError, for one that has none) */
        char why[300];
        json_t *oas = lubd_oas_schema(prop, why, sizeof why);
        if (!oas) {
            if (!untranslated[0])
                snprintf(untranslated, sizeof untranslated, "input %.60s: %s", key, why);
            oas = json_object();
        }
        json_t *in = json_pack("{s:s, s:i, s:i, s:o}", "title",
                               json_is_string(title) ? json_string_value(title) : key, "minOccurs",
                               req, "maxOccurs", 1, "schema", oas);
        if (json_is_string(desc))
            json_object_set(in, "description", desc);
        json_object_set_new(inputs, key, in);
    }
    json_object_set_new(o, "inputs", inputs);
    if (!schema) {
        json_object_set_new(o, "inputsSchemaError", json_string(err.text));
    } else {
        json_object_set_new(o, "inputsSchema", schema); /* the draft-07 file, no scene */
        if (untranslated[0])
            json_object_set_new(o, "inputsSchemaError", json_string(untranslated));
    }
    json_t *outputs = json_pack(
        "{s:{s:s, s:s, s:{s:s, s:s}}, s:{s:s, s:s, s:{s:s, s:s, s:s}}}", "summary.json", "title",
        "summary", "description", "headline results (see schema/summary.schema.json)", "schema",
        "type", "object", "contentMediaType", "application/json", "result.h5", "title",
        "H5MD result file", "description",
        "observables, snapshots, verbatim and resolved spec, build provenance", "schema", "type",
        "string", "contentEncoding", "binary", "contentMediaType", "application/x-hdf5");
    if (s->resumable) {
        /* the files a continuation (continue_from) goes on from, served with the results */
        json_object_set_new(
            outputs, "checkpoint.h5",
            json_pack("{s:s, s:s, s:{s:s, s:s, s:s}}", "title", "checkpoint", "description",
                      "the run's state, which a job with continue_from continues: of a run "
                      "stopped (the CPU time limit) or killed on its last attempt after a "
                      "periodic checkpoint, and of a completed run under lubdemd "
                      "--keep-checkpoints 1 (the default) when the process can be extended",
                      "schema", "type", "string", "contentEncoding", "binary", "contentMediaType",
                      "application/x-hdf5"));
        json_object_set_new(
            outputs, "checkpoint-result.h5",
            json_pack("{s:s, s:s, s:{s:s, s:s, s:s}}", "title", "rows of a periodic checkpoint",
                      "description",
                      "a copy of result.h5 as it was at a periodic checkpoint (lubdemd "
                      "--checkpoint-s), which that checkpoint.h5 goes with: of a failed run "
                      "whose checkpoint is a periodic one",
                      "schema", "type", "string", "contentEncoding", "binary", "contentMediaType",
                      "application/x-hdf5"));
    }
    json_object_set_new(o, "outputs", outputs);
    return lubd_reply_json(r, 200, o);
}

static int valid_idempotency_key(const char *k)
{
    size_t n = strlen(k);
    if (n == 0 || n > 255)
        return 0;
    for (size_t i = 0; i < n; ++i)
        if (k[i] < 0x21 || k[i] > 0x7e)
            return 0;
    return 1;
}

enum MHD_Result lubd_api_execute(lubd_request *r, const char *id)
{
    lubd_fault f;
    if (lubd_authenticate(r, &f) != 0)
        return lubd_reply_fault(r, &f);
    const char *key = lubd_header(r, "Idempotency-Key");
    if (key && !valid_idempotency_key(key)) {
        lubd_fail(&f, 400, LUBD_PT_BASE "invalid-header", "Invalid header", NULL,
                  "Idempotency-Key must be 1..255 visible ASCII characters");
        return lubd_reply_fault(r, &f);
    }
    lubd_exec_request req;
    if (lubd_exec_parse(r->body, r->body_len, id, &req, &f) != 0)
        return lubd_reply_fault(r, &f);
    if (lubd_job_fits(&req, r->srv->cfg, &f) != 0) {
        lubd_exec_free(&req);
        return lubd_reply_fault(r, &f);
    }
    if (req.priority > 0 && !r->user.is_admin) {
        lubd_exec_free(&req);
        lubd_fail(&f, 403, LUBD_PT_BASE "forbidden", "Forbidden", "/priority",
                  "only admins may submit with priority > 0 (got %d)", req.priority);
        return lubd_reply_fault(r, &f);
    }
    if (req.continue_from[0]) {
        /* a retried submission gets its job, even once the job it continues is deleted */
        lubd_continuation cont = {req.continue_from, r->user.id, r->user.is_admin, id,
                                  req.resolved};
        sqlite3 *rdb = lubd_db_acquire(&r->srv->pool);
        const int replay = key && lubd_queue_is_replay(rdb, r->user.id, key, req.fingerprint) == 1;
        const int bad = !replay && lubd_continuation_check(rdb, &cont, &f);
        lubd_db_release(&r->srv->pool, rdb);
        if (bad) {
            lubd_exec_free(&req);
            return lubd_reply_fault(r, &f);
        }
    }
    char *spec = lub_json_dumps(req.spec, JSON_COMPACT | JSON_SORT_KEYS);
    lubd_submit in = {r->user.id,
                      r->user.max_active >= 0 ? (int)r->user.max_active : r->srv->cfg->user_cap,
                      id,
                      r->body,
                      spec,
                      req.fingerprint,
                      key,
                      req.priority,
                      r->srv->cfg->max_attempts,
                      req.continue_from};
    char job_id[33];
    int replayed = 0, rc = -1;
    lubd_job job;
    sqlite3 *db = lubd_db_acquire_writer(&r->srv->pool);
    if (spec)
        rc = lubd_queue_submit(db, &in, job_id, &replayed, &f);
    else
        lubd_fail(&f, 500, LUBD_PT_BASE "internal", "Internal error", NULL, "out of memory");
    if (rc == 0 && lubd_queue_get(db, job_id, &job) != 1) {
        rc = -1;
        lubd_fail(&f, 500, LUBD_PT_BASE "internal", "Internal error", NULL,
                  "job %s vanished after submission", job_id);
    }
    lubd_db_release_writer(&r->srv->pool, db);
    free(spec);
    lubd_exec_free(&req);
    if (rc != 0)
        return lubd_reply_fault(r, &f);
    struct MHD_Response *resp =
        lubd_json_response(lubd_status_json(&job, r->base, 0), "application/json");
    if (!resp)
        return MHD_NO;
    char loc[600];
    snprintf(loc, sizeof loc, "%s/jobs/%s", r->base, job_id);
    MHD_add_response_header(resp, MHD_HTTP_HEADER_LOCATION, loc);
    const char *prefer = lubd_header(r, "Prefer");
    if (prefer && strstr(prefer, "respond-async"))
        MHD_add_response_header(resp, "Preference-Applied", "respond-async");
    if (replayed)
        MHD_add_response_header(resp, "Idempotent-Replayed", "true");
    return lubd_queue(r, 201, resp);
}
