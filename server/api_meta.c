/* api_meta.c — landing page, conformance, OpenAPI document, health. */
#include <stdio.h>
#include <string.h>

#include "api.h"
#include "queue.h"

static json_t *mklink(const char *base, const char *path, const char *rel, const char *type,
                      const char *title)
{
    char href[600];
    snprintf(href, sizeof href, "%s%s", base, path);
    return json_pack("{s:s, s:s, s:s, s:s}", "href", href, "rel", rel, "type", type, "title",
                     title);
}

enum MHD_Result lubd_api_landing(lubd_request *r)
{
    json_t *links = json_array();
    json_array_append_new(links, mklink(r->base, "/", "self", "application/json", "this page"));
    json_array_append_new(links,
                          mklink(r->base, "/openapi.json", "service-desc",
                                 "application/vnd.oai.openapi+json;version=3.0", "API definition"));
    json_array_append_new(links, mklink(r->base, "/conformance",
                                        "http://www.opengis.net/def/rel/ogc/1.0/conformance",
                                        "application/json", "conformance classes"));
    json_array_append_new(links, mklink(r->base, "/processes",
                                        "http://www.opengis.net/def/rel/ogc/1.0/processes",
                                        "application/json", "processes (engine scenes)"));
    json_array_append_new(links, mklink(r->base, "/jobs",
                                        "http://www.opengis.net/def/rel/ogc/1.0/job-list",
                                        "application/json", "jobs"));
    json_array_append_new(links, mklink(r->base, "/health", "status", "application/json",
                                        "liveness and queue depth"));
    json_t *o = json_pack("{s:s, s:s, s:o}", "title", "lubdem simulation service", "description",
                          "Runs lubdem discrete-element and continuum simulations of dense "
                          "non-Brownian suspensions as asynchronous jobs (OGC API - Processes).",
                          "links", links);
    return lubd_reply_json(r, 200, o);
}

enum MHD_Result lubd_api_conformance(lubd_request *r)
{
    json_t *o = json_pack("{s:[s,s,s,s,s]}", "conformsTo",
                          "http://www.opengis.net/spec/ogcapi-processes-1/1.0/conf/core",
                          "http://www.opengis.net/spec/ogcapi-processes-1/1.0/conf/json",
                          "http://www.opengis.net/spec/ogcapi-processes-1/1.0/conf/oas30",
                          "http://www.opengis.net/spec/ogcapi-processes-1/1.0/conf/job-list",
                          "http://www.opengis.net/spec/ogcapi-processes-1/1.0/conf/dismiss");
    return lubd_reply_json(r, 200, o);
}

enum MHD_Result lubd_api_openapi(lubd_request *r)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/openapi.json", r->srv->cfg->schema_dir);
    json_error_t err;
    json_t *doc = json_load_file(path, JSON_PRESERVE_ORDER, &err);
    if (!doc) {
        lubd_fault f;
        lubd_fail(&f, 500, LUBD_PT_BASE "internal", "Internal error", NULL, "cannot read %s: %s",
                  path, err.text);
        return lubd_reply_fault(r, &f);
    }
    return lubd_queue(r, 200,
                      lubd_json_response(doc, "application/vnd.oai.openapi+json;version=3.0"));
}

enum MHD_Result lubd_api_health(lubd_request *r)
{
    sqlite3 *db = lubd_db_acquire(&r->srv->pool);
    int accepted = 0, running = 0;
    int rc = lubd_queue_counts(db, &accepted, &running);
    lubd_db_release(&r->srv->pool, db);
    int alive = atomic_load(&r->srv->workers_alive);
    json_t *o =
        json_pack("{s:s, s:{s:i, s:i}, s:{s:i, s:i}}", "status",
                  rc == 0 ? "ok" : "database unavailable", "queue", "accepted", accepted, "running",
                  running, "workers", "configured", r->srv->cfg->workers, "alive", alive);
    return lubd_reply_json(r, rc == 0 ? 200 : 503, o);
}
