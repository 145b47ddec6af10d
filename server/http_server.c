/* http_server.c — MHD daemon set-up, body accumulation, routing, response helpers. */
#include "http_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "api.h"
#include "json_text.h"
#include "spec_reader.h"

typedef struct {
    char *body;
    size_t len, cap;
    int too_large;
    size_t discarded; /* bytes thrown away after too_large */
    int have_user;
    lubd_user user;
} conn_state;

struct MHD_Response *lubd_json_response(json_t *body, const char *content_type)
{
    char *text = lub_json_dumps(body, JSON_INDENT(1) | JSON_PRESERVE_ORDER);
    json_decref(body);
    if (!text)
        return NULL;
    size_t n = strlen(text);
    text[n] = '\n'; /* replace the NUL: bodies end with a newline */
    struct MHD_Response *resp = MHD_create_response_from_buffer(n + 1, text, MHD_RESPMEM_MUST_FREE);
    if (!resp) {
        free(text);
        return NULL;
    }
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE, content_type);
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
    return resp;
}

enum MHD_Result lubd_queue(lubd_request *r, unsigned status, struct MHD_Response *resp)
{
    if (!resp)
        return MHD_NO;
    enum MHD_Result ret = MHD_queue_response(r->conn, status, resp);
    MHD_destroy_response(resp);
    return ret;
}

enum MHD_Result lubd_reply_json(lubd_request *r, unsigned status, json_t *body)
{
    return lubd_queue(r, status, lubd_json_response(body, "application/json"));
}

enum MHD_Result lubd_reply_fault(lubd_request *r, const lubd_fault *f)
{
    struct MHD_Response *resp =
        lubd_json_response(lubd_fault_json(f, r->url), "application/problem+json");
    if (!resp)
        return MHD_NO;
    if (f->status == 401)
        MHD_add_response_header(resp, MHD_HTTP_HEADER_WWW_AUTHENTICATE, "Bearer realm=\"lubdem\"");
    if (f->retry_after > 0) {
        char v[16];
        snprintf(v, sizeof v, "%d", f->retry_after);
        MHD_add_response_header(resp, MHD_HTTP_HEADER_RETRY_AFTER, v);
    }
    return lubd_queue(r, (unsigned)f->status, resp);
}

const char *lubd_header(lubd_request *r, const char *name)
{
    return MHD_lookup_connection_value(r->conn, MHD_HEADER_KIND, name);
}

const char *lubd_query(lubd_request *r, const char *name)
{
    return MHD_lookup_connection_value(r->conn, MHD_GET_ARGUMENT_KIND, name);
}

int lubd_authenticate(lubd_request *r, lubd_fault *f)
{
    if (r->have_user)
        return 0;
    const char *h = lubd_header(r, MHD_HTTP_HEADER_AUTHORIZATION);
    if (!h)
        return lubd_fail(f, 401, LUBD_PT_BASE "unauthorized", "Unauthorized", NULL,
                         "missing 'Authorization: Bearer <token>' header (create a token with "
                         "`lubdemd token create --user NAME`)");
    sqlite3 *db = lubd_db_acquire(&r->srv->pool);
    int rc = lubd_auth_bearer(db, h, &r->user);
    lubd_db_release(&r->srv->pool, db);
    if (rc < 0)
        return lubd_fail(f, 500, LUBD_PT_BASE "internal", "Internal error", NULL,
                         "database error while checking the token");
    if (rc > 0)
        return lubd_fail(f, 401, LUBD_PT_BASE "unauthorized", "Unauthorized", NULL,
                         "the bearer token is malformed, unknown or revoked");
    r->have_user = 1;
    return 0;
}

/* Host header restricted to host[:port] characters, else the bound address. */
static void make_base(lubd_request *r)
{
    const char *host = lubd_header(r, MHD_HTTP_HEADER_HOST);
    int ok = host && host[0] && strlen(host) < 200;
    for (const char *p = host; ok && *p; ++p)
        ok = (*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') ||
             *p == '.' || *p == '-' || *p == ':' || *p == '[' || *p == ']';
    if (ok)
        snprintf(r->base, sizeof r->base, "http://%s", host);
    else
        snprintf(r->base, sizeof r->base, "http://%s:%d", r->srv->cfg->listen_host, r->srv->port);
}

static void split_path(lubd_request *r)
{
    snprintf(r->path_buf, sizeof r->path_buf, "%s", r->url);
    r->nseg = 0;
    char *save = NULL;
    for (char *s = strtok_r(r->path_buf, "/", &save); s && r->nseg < 8;
         s = strtok_r(NULL, "/", &save))
        r->seg[r->nseg++] = s;
}

static enum MHD_Result method_not_allowed(lubd_request *r, const char *allow)
{
    lubd_fault f;
    lubd_fail(&f, 405, LUBD_PT_BASE "method-not-allowed", "Method not allowed", NULL,
              "%s is not allowed on %s (allowed: %s)", r->method, r->url, allow);
    struct MHD_Response *resp =
        lubd_json_response(lubd_fault_json(&f, r->url), "application/problem+json");
    if (!resp)
        return MHD_NO;
    MHD_add_response_header(resp, MHD_HTTP_HEADER_ALLOW, allow);
    return lubd_queue(r, 405, resp);
}

static enum MHD_Result not_found(lubd_request *r)
{
    lubd_fault f;
    lubd_fail(&f, 404, LUBD_PT_BASE "not-found", "Not found", NULL, "no resource at %s", r->url);
    return lubd_reply_fault(r, &f);
}

static int is(const lubd_request *r, const char *m) { return strcmp(r->method, m) == 0; }

static enum MHD_Result route(lubd_request *r)
{
    int get = is(r, "GET") || is(r, "HEAD");
    if (r->nseg == 0)
        return get ? lubd_api_landing(r) : method_not_allowed(r, "GET, HEAD");
    const char *s0 = r->seg[0];
    if (r->nseg == 1 && strcmp(s0, "conformance") == 0)
        return get ? lubd_api_conformance(r) : method_not_allowed(r, "GET, HEAD");
    if (r->nseg == 1 && (strcmp(s0, "openapi.json") == 0 || strcmp(s0, "api") == 0))
        return get ? lubd_api_openapi(r) : method_not_allowed(r, "GET, HEAD");
    if (r->nseg == 1 && strcmp(s0, "health") == 0)
        return get ? lubd_api_health(r) : method_not_allowed(r, "GET, HEAD");
    if (strcmp(s0, "processes") == 0) {
        if (r->nseg == 1)
            return get ? lubd_api_processes(r) : method_not_allowed(r, "GET, HEAD");
        if (r->nseg == 2)
            return get ? lubd_api_process(r, r->seg[1]) : method_not_allowed(r, "GET, HEAD");
        if (r->nseg == 3 && strcmp(r->seg[2], "execution") == 0)
            return is(r, "POST") ? lubd_api_execute(r, r->seg[1]) : method_not_allowed(r, "POST");
        return not_found(r);
    }
    if (strcmp(s0, "jobs") == 0) {
        if (r->nseg == 1)
            return get ? lubd_api_jobs(r) : method_not_allowed(r, "GET, HEAD");
        if (r->nseg == 2) {
            if (get)
                return lubd_api_job(r, r->seg[1]);
            if (is(r, "DELETE"))
                return lubd_api_dismiss(r, r->seg[1]);
            return method_not_allowed(r, "GET, HEAD, DELETE");
        }
        if (r->nseg == 3 && strcmp(r->seg[2], "results") == 0)
            return get ? lubd_api_results(r, r->seg[1]) : method_not_allowed(r, "GET, HEAD");
        if (r->nseg == 4 && strcmp(r->seg[2], "results") == 0)
            return get ? lubd_api_result_file(r, r->seg[1], r->seg[3])
                       : method_not_allowed(r, "GET, HEAD");
        if (r->nseg == 3 && strcmp(r->seg[2], "log") == 0)
            return get ? lubd_api_log(r, r->seg[1]) : method_not_allowed(r, "GET, HEAD");
    }
    return not_found(r);
}

static int json_content_type(const char *ct)
{
    if (!ct)
        return 0;
    size_t n = strcspn(ct, ";");
    while (n > 0 && (ct[n - 1] == ' ' || ct[n - 1] == '\t'))
        --n;
    if (n == 16 && strncasecmp(ct, "application/json", 16) == 0)
        return 1;
    return n > 5 && strncasecmp(ct + n - 5, "+json", 5) == 0 &&
           strncasecmp(ct, "application/", 12) == 0;
}

static enum MHD_Result on_request(void *cls, struct MHD_Connection *conn, const char *url,
                                  const char *method, const char *version, const char *upload_data,
                                  size_t *upload_size, void **con_cls)
{
    (void)version;
    lubd_server *srv = cls;
    lubd_request r;
    memset(&r, 0, sizeof r);
    r.srv = srv;
    r.conn = conn;
    r.method = method;
    r.url = url;
    conn_state *cs = *con_cls;
    int post = strcmp(method, "POST") == 0;
    if (!cs) {
        cs = calloc(1, sizeof *cs);
        if (!cs)
            return MHD_NO;
        *con_cls = cs;
        if (post) {
            /* Early rejections, before any of the body is read (no 100-continue). */
            lubd_fault f;
            make_base(&r);
            const char *cl = lubd_header(&r, MHD_HTTP_HEADER_CONTENT_LENGTH);
            if (cl && strtoull(cl, NULL, 10) > (unsigned long long)srv->cfg->max_body) {
                lubd_fail(&f, 413, LUBD_PT_BASE "body-too-large", "Request body too large", NULL,
                          "request body of %s bytes exceeds the limit of %ld bytes", cl,
                          srv->cfg->max_body);
                return lubd_reply_fault(&r, &f);
            }
            if (lubd_authenticate(&r, &f) != 0)
                return lubd_reply_fault(&r, &f);
            cs->have_user = 1;
            cs->user = r.user;
            const char *ct = lubd_header(&r, MHD_HTTP_HEADER_CONTENT_TYPE);
            if (!json_content_type(ct)) {
                char quoted[104];
                lub_text_one_line(ct ? ct : "none", quoted, sizeof quoted);
                lubd_fail(&f, 415, LUBD_PT_BASE "unsupported-media-type", "Unsupported media type",
                          NULL, "Content-Type must be application/json (got %s)", quoted);
                return lubd_reply_fault(&r, &f);
            }
            return MHD_YES;
        }
        /* Respond on the next call, once MHD has the whole request: a response queued on
         * the first call makes MHD close the connection (no keep-alive). */
        return MHD_YES;
    } else if (*upload_size > 0) {
        size_t n = *upload_size;
        if (!post) { /* a body on GET/DELETE is ignored */
            *upload_size = 0;
            return MHD_YES;
        }
        *upload_size = 0;
        if (cs->too_large) {
            /* Drained so that the 413 can be sent; an endless chunked body is cut off. */
            cs->discarded += n;
            return cs->discarded > (size_t)srv->cfg->max_body * 16 ? MHD_NO : MHD_YES;
        }
        if (cs->len + n > (size_t)srv->cfg->max_body) {
            cs->too_large = 1;
            free(cs->body);
            cs->body = NULL;
            cs->len = cs->cap = 0;
            return MHD_YES;
        }
        if (cs->len + n + 1 > cs->cap) {
            size_t cap = cs->cap ? cs->cap : 4096;
            while (cap < cs->len + n + 1)
                cap *= 2;
            char *nb = realloc(cs->body, cap);
            if (!nb)
                return MHD_NO;
            cs->body = nb;
            cs->cap = cap;
        }
        memcpy(cs->body + cs->len, upload_data, n);
        cs->len += n;
        cs->body[cs->len] = '\0';
        return MHD_YES;
    }
    make_base(&r);
    split_path(&r);
    if (cs->have_user) {
        r.have_user = 1;
        r.user = cs->user;
    }
    if (post) {
        if (cs->too_large) {
            lubd_fault f;
            lubd_fail(&f, 413, LUBD_PT_BASE "body-too-large", "Request body too large", NULL,
                      "request body exceeds the limit of %ld bytes", srv->cfg->max_body);
            return lubd_reply_fault(&r, &f);
        }
        r.body = cs->body ? cs->body : "";
        r.body_len = cs->len;
    }
    return route(&r);
}

static void on_completed(void *cls, struct MHD_Connection *conn, void **con_cls,
                         enum MHD_RequestTerminationCode toe)
{
    (void)cls;
    (void)conn;
    (void)toe;
    conn_state *cs = *con_cls;
    if (cs) {
        free(cs->body);
        free(cs);
        *con_cls = NULL;
    }
}

int lubd_http_start(lubd_server *s, const lubd_config *cfg)
{
    s->cfg = cfg;
    if (lubd_db_pool_init(&s->pool, cfg->db_path, cfg->http_threads + 2) != 0) {
        fprintf(stderr, "lubdemd: cannot open the database pool\n");
        return -1;
    }
    struct sockaddr_in addr;
    memset(&addr, 0, sizeof addr);
    addr.sin_family = AF_INET;
    addr.sin_port = htons((uint16_t)cfg->port);
    if (inet_pton(AF_INET, cfg->listen_host, &addr.sin_addr) != 1) {
        fprintf(stderr, "lubdemd: --listen host must be an IPv4 address (got %s)\n",
                cfg->listen_host);
        return -1;
    }
    s->daemon = MHD_start_daemon(
        MHD_USE_AUTO_INTERNAL_THREAD | MHD_USE_ERROR_LOG, (uint16_t)cfg->port, NULL, NULL,
        on_request, s, MHD_OPTION_SOCK_ADDR, (struct sockaddr *)&addr, MHD_OPTION_THREAD_POOL_SIZE,
        (unsigned)cfg->http_threads, MHD_OPTION_CONNECTION_LIMIT, (unsigned)512,
        MHD_OPTION_PER_IP_CONNECTION_LIMIT, (unsigned)128, MHD_OPTION_CONNECTION_TIMEOUT,
        (unsigned)60, MHD_OPTION_CONNECTION_MEMORY_LIMIT, (size_t)(64 * 1024),
        MHD_OPTION_LISTEN_BACKLOG_SIZE, (unsigned)256, MHD_OPTION_NOTIFY_COMPLETED, on_completed, s,
        MHD_OPTION_END);
    if (!s->daemon) {
        fprintf(stderr, "lubdemd: cannot listen on %s:%d (port in use?)\n", cfg->listen_host,
                cfg->port);
        lubd_db_pool_destroy(&s->pool);
        return -1;
    }
    const union MHD_DaemonInfo *info = MHD_get_daemon_info(s->daemon, MHD_DAEMON_INFO_BIND_PORT);
    s->port = info ? info->port : cfg->port;
    return 0;
}

void lubd_http_stop(lubd_server *s)
{
    if (s->daemon)
        MHD_stop_daemon(s->daemon);
    s->daemon = NULL;
    lubd_db_pool_destroy(&s->pool);
}
