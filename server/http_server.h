/* http_server.h — the HTTP front end (libmicrohttpd) and the helpers handlers share.
 *
 * lubd_http_start() binds cfg->listen_host:port (127.0.0.1 by default) with an internal
 * thread pool, explicit connection/per-IP/timeout/memory limits, and routes requests to the
 * api_*.c handlers. Request bodies (POST only) are accumulated up to cfg->max_body; larger
 * bodies get 413 as soon as Content-Length or the data shows it, non-JSON Content-Type gets
 * 415, and a missing/invalid token 401, all before the body is read. The server struct is
 * owned by the caller; lubd_http_stop() releases what start acquired. */
#ifndef LUBD_HTTP_SERVER_H
#define LUBD_HTTP_SERVER_H

#include <jansson.h>
#include <microhttpd.h>
#include <stdatomic.h>

#include "config.h"
#include "db.h"
#include "problem.h"
#include "tokens.h"

typedef struct {
    const lubd_config *cfg;
    lubd_db_pool pool;
    struct MHD_Daemon *daemon;
    int port;                 /* bound port */
    atomic_int workers_alive; /* maintained by the supervisor */
} lubd_server;

/* One request, as handlers see it. */
typedef struct {
    lubd_server *srv;
    struct MHD_Connection *conn;
    const char *method;
    const char *url;
    char *seg[8]; /* path segments (point into path_buf) */
    int nseg;
    char path_buf[1024];
    const char *body; /* POST body (NUL-terminated), may be NULL */
    size_t body_len;
    char base[300]; /* "http://host:port" for absolute links */
    int have_user;
    lubd_user user;
} lubd_request;

int lubd_http_start(lubd_server *s, const lubd_config *cfg);
void lubd_http_stop(lubd_server *s);

/* Response helpers: each queues a response and returns the MHD result. */
enum MHD_Result lubd_reply_json(lubd_request *r, unsigned status, json_t *body /* stolen */);
enum MHD_Result lubd_reply_fault(lubd_request *r, const lubd_fault *f);
/* Creates a JSON response (body stolen) so the caller can add headers. */
struct MHD_Response *lubd_json_response(json_t *body, const char *content_type);
enum MHD_Result lubd_queue(lubd_request *r, unsigned status, struct MHD_Response *resp);

/* Authenticates the bearer token into r->user. Returns 0, or -1 with *f set (401/500). */
int lubd_authenticate(lubd_request *r, lubd_fault *f);
const char *lubd_header(lubd_request *r, const char *name);
const char *lubd_query(lubd_request *r, const char *name);

#endif
