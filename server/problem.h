/* problem.h — RFC 7807 problem details (application/problem+json).
 *
 * A lubd_fault is filled by validation and handler code (no allocation) and turned into the
 * JSON body by lubd_fault_json. When the fault concerns one field, `pointer` is its JSON
 * pointer inside the request body (e.g. "/inputs/eps") and is reported as
 * errors[0].pointer. */
#ifndef LUBD_PROBLEM_H
#define LUBD_PROBLEM_H

#include <jansson.h>

typedef struct {
    int status;        /* HTTP status */
    const char *type;  /* URI (static string) */
    const char *title; /* short summary (static string) */
    int has_pointer;
    char pointer[300];
    char detail[700];
    int retry_after; /* seconds, 0 = no Retry-After header */
} lubd_fault;

#define LUBD_PT_BASE "https://lubdem.example/problems/"
#define LUBD_OGC_EXC "http://www.opengis.net/def/exceptions/ogcapi-processes-1/1.0/"

/* Fills *f; pointer NULL = not about a single field. Returns -1 (for "return lubd_fail(...)").*/
int lubd_fail(lubd_fault *f, int status, const char *type, const char *title, const char *pointer,
              const char *fmt, ...) __attribute__((format(printf, 6, 7)));
/* lubd_fail cuts an incomplete UTF-8 character off the end of pointer and detail (what a
 * "%.Ns" or a full buffer leaves of a multi-byte name; the engine's lub_utf8_trim_tail,
 * spec_reader.h), so that the texts stay valid for JSON. */
/* New JSON object {type,title,status,detail[,instance][,errors:[{pointer,detail}]]}. */
json_t *lubd_fault_json(const lubd_fault *f, const char *instance);

#endif
